// Command-line options of compaction-server (and their environment fallbacks).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "config/tokens.hpp"

namespace compaction::server {

struct ServerOptions {
  std::string db = "./data/compaction.db";  // SQLite file, created with its folder
  std::string host = "127.0.0.1";
  int port = 8080;                          // 0: any free port (see --port-file)
  std::string port_file;                    // write the bound port here once listening
  std::string submit_token;                 // required to create or cancel sweeps ("" = open)
  std::string worker_token;                 // required by the worker endpoints ("" = open)
  std::string tokens_file;                  // named tokens, one per line: ROLE NAME TOKEN
  TokenTable tokens;                        // all of the above, as the guard checks them
  std::string web_dir;                      // static files of the dashboard
  double lease_seconds = 60;                // a lease lasts this long after each heartbeat
  double rescue_interval_seconds = 5;       // how often expired leases are requeued
  double retry_backoff_seconds = 5;         // first retry delay, doubling per attempt
  int max_sweep_points = 2000;              // scenes per sweep
  int max_upload_mb = 256;                  // largest result upload (a bundle)       [MiB]
  int http_threads = 128;                   // connections served at once (threads start on demand)
  double request_timeout_seconds = 300;     // one request, body and answer included
  std::string log_level = "info";
  std::string import_file;                  // --import: merge this export file into --db and exit
};

// Parses argv (environment: COMPACTION_SUBMIT_TOKEN, COMPACTION_WORKER_TOKEN) with the
// programs' common grammar (engine/cli/command_line.hpp). Returns the options, or nullopt
// after printing --help or --version (exit 0) or an error naming the flag and its value
// (exit 2); `exit_code` says which.
std::optional<ServerOptions> parse_server_options(int argc, char** argv, int& exit_code);

// The text of --help, with the defaults and ranges of the flags.
std::string server_usage();

// Whether every address the host name resolves to is a loopback address (127.0.0.0/8, ::1);
// false when it does not resolve.
bool is_loopback_host(const std::string& host);

}  // namespace compaction::server
