#include "config/options.hpp"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <cstdlib>

#include "command_line.hpp"

namespace compaction::server {

bool is_loopback_host(const std::string& host) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE;
  addrinfo* found = nullptr;
  if (getaddrinfo(host.c_str(), nullptr, &hints, &found) != 0 || !found) return false;
  bool all_loopback = true;
  for (const addrinfo* a = found; a; a = a->ai_next) {
    if (a->ai_family == AF_INET) {
      const auto* in = reinterpret_cast<const sockaddr_in*>(a->ai_addr);
      all_loopback &= (ntohl(in->sin_addr.s_addr) >> 24) == 127;
    } else if (a->ai_family == AF_INET6) {
      const auto* in = reinterpret_cast<const sockaddr_in6*>(a->ai_addr);
      all_loopback &= IN6_IS_ADDR_LOOPBACK(&in->sin6_addr) != 0;
    } else {
      all_loopback = false;
    }
  }
  freeaddrinfo(found);
  return all_loopback;
}

namespace {

// The flags, their ranges and defaults in one place: parsing and --help read them.
cli::CommandLine command_line(ServerOptions& o) {
  cli::CommandLine cl("compaction-server",
                      "the sweep service (REST API over SQLite, job queue, dashboard).",
                      "[options]");
  cl.text("--db", o.db, "FILE", "SQLite database, created with its folder", o.db, true);
  cl.text("--host", o.host, "ADDR", "address to listen on", o.host, true);
  cl.integer("--port", o.port, {0, 65535}, "N", "TCP port, 0 picks a free one");
  cl.text("--port-file", o.port_file, "FILE", "write the bound port to FILE once listening");
  cl.text("--submit-token", o.submit_token, "TOKEN",
          "token to create and cancel sweeps (env COMPACTION_SUBMIT_TOKEN)");
  cl.text("--worker-token", o.worker_token, "TOKEN",
          "token of the worker endpoints (env COMPACTION_WORKER_TOKEN)\n"
          "Both tokens are mandatory when --host is not a loopback address;\n"
          "reading endpoints stay open. Clients send \"Authorization: Bearer TOKEN\".");
  cl.text("--tokens", o.tokens_file, "FILE",
          "named tokens, beside or instead of the two above: one per line,\n"
          "\"ROLE NAME TOKEN\" (ROLE: submit or worker; NAME: letters, digits,\n"
          "'.', '_', '-'; TOKEN: 8 to 256 printable characters); a relabel\n"
          "or an import records the name of the token that made it");
  cl.text("--web-dir", o.web_dir, "DIR", "static files of the dashboard", "the source tree's web/");
  cl.real("--lease-seconds", o.lease_seconds, {0.5, 86400}, "S",
          "lease length in seconds, renewed by each heartbeat");
  cl.real("--rescue-interval", o.rescue_interval_seconds, {0.05, 3600}, "S",
          "how often expired leases are requeued, seconds");
  cl.real("--retry-backoff", o.retry_backoff_seconds, {0, 3600}, "S",
          "delay before the first retry, doubling per attempt, seconds");
  cl.integer("--max-sweep-points", o.max_sweep_points, {1, 1000000}, "N", "largest sweep accepted");
  cl.integer("--max-upload-mb", o.max_upload_mb, {1, 4096}, "N",
             "largest result upload a worker may send, in MiB; sweeps\n"
             "whose results could not fit are refused at submission");
  cl.integer("--http-threads", o.http_threads, {1, 1024}, "N",
             "connections served at once; handler threads start on demand");
  cl.real("--request-timeout", o.request_timeout_seconds, {1, 86400}, "S",
          "longest exchange of one request, body and answer, seconds;\n"
          "headers must arrive within 10 s, a silence of 10 s ends a request");
  cl.text("--import", o.import_file, "FILE",
          "merge the sweep export FILE (GET /api/v1/sweeps/ID/export?format=archive\n"
          "of another server) into --db and exit; run it with that database's\n"
          "server stopped, or POST the file to /api/v1/imports instead");
  cl.choice("--log-level", o.log_level, {"trace", "debug", "info", "warn", "error"}, "LEVEL",
            "log level");
  cl.notes("API: /api/v1 (OpenAPI at /api/v1/openapi.yaml), metrics at /metrics, dashboard at /.\n");
  return cl;
}

}  // namespace

std::string server_usage() {
  ServerOptions defaults;
  return command_line(defaults).help();
}

std::optional<ServerOptions> parse_server_options(int argc, char** argv, int& exit_code) {
  ServerOptions o;
#ifdef COMPACTION_SOURCE_DIR
  o.web_dir = std::string(COMPACTION_SOURCE_DIR) + "/web";
#endif
  if (const char* t = std::getenv("COMPACTION_SUBMIT_TOKEN")) o.submit_token = t;
  if (const char* t = std::getenv("COMPACTION_WORKER_TOKEN")) o.worker_token = t;
  cli::CommandLine cl = command_line(o);
  if (const auto code = cl.parse(argc, argv)) {
    exit_code = *code;
    return std::nullopt;
  }
  try {
    if (!o.submit_token.empty()) o.tokens.add({TokenKind::submit, "", o.submit_token}, false);
    if (!o.worker_token.empty()) o.tokens.add({TokenKind::worker, "", o.worker_token}, false);
    if (!o.tokens_file.empty()) load_tokens_file(o.tokens_file, o.tokens);
  } catch (const std::invalid_argument& e) {
    exit_code = cl.fail(o.tokens_file.empty() ? "--submit-token" : "--tokens", e.what());
    return std::nullopt;
  }
  if (!is_loopback_host(o.host) && (o.tokens.open(TokenKind::submit) || o.tokens.open(TokenKind::worker))) {
    exit_code = cl.fail("--host", "listening on " + o.host +
                                      " (not a loopback address, or a name that does not resolve)"
                                      " needs submit and worker tokens (--submit-token and"
                                      " --worker-token, or --tokens)");
    return std::nullopt;
  }
  exit_code = 0;
  return o;
}

}  // namespace compaction::server
