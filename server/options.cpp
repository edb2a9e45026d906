#include "options.hpp"

#include "compaction/text_numbers.hpp"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <map>

namespace compaction::server {

std::string server_usage() {
  return R"(compaction-server: the sweep service (REST API over SQLite, job queue, dashboard).

usage: compaction-server [options]

  --db FILE                  SQLite database, created with its folder (default ./data/compaction.db)
  --host ADDR                address to listen on (default 127.0.0.1)
  --port N                   TCP port, 0 picks a free one (default 8080)
  --port-file FILE           write the bound port to FILE once listening
  --submit-token TOKEN       token to create and cancel sweeps (env COMPACTION_SUBMIT_TOKEN)
  --worker-token TOKEN       token of the worker endpoints (env COMPACTION_WORKER_TOKEN)
                             Both tokens are mandatory when --host is not a loopback address;
                             reading endpoints stay open. Clients send "Authorization: Bearer TOKEN".
  --web-dir DIR              static files of the dashboard (default: the source tree's web/)
  --lease-seconds S          lease length, renewed by each heartbeat (default 60)
  --rescue-interval S        how often expired leases are requeued (default 5)
  --retry-backoff S          delay before the first retry, doubling per attempt (default 5)
  --max-sweep-points N       largest sweep accepted (default 2000)
  --max-upload-mb N          largest result upload a worker may send, in MiB (default 256);
                             sweeps whose results could not fit are refused at submission
  --http-threads N           connections served at once; handler threads start on demand
                             (default 128, at most 1024)
  --request-timeout S        longest exchange of one request, body and answer (default 300);
                             headers must arrive within 10 s, a silence of 10 s ends a request
  --log-level LEVEL          trace, debug, info, warn, error (default info)
  --help                     this text

API: /api/v1 (OpenAPI at /api/v1/openapi.yaml), metrics at /metrics, dashboard at /.
)";
}

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

using compaction::parse_int;
bool parse_number(const std::string& s, double& out) { return compaction::parse_finite_real(s, out); }

}  // namespace

std::optional<ServerOptions> parse_server_options(int argc, char** argv, int& exit_code) {
  ServerOptions o;
#ifdef COMPACTION_SOURCE_DIR
  o.web_dir = std::string(COMPACTION_SOURCE_DIR) + "/web";
#endif
  if (const char* t = std::getenv("COMPACTION_SUBMIT_TOKEN")) o.submit_token = t;
  if (const char* t = std::getenv("COMPACTION_WORKER_TOKEN")) o.worker_token = t;

  auto error = [&](const std::string& flag, const std::string& message) {
    std::cerr << "compaction-server: " << flag << ": " << message << "\n";
    exit_code = 2;
    return std::nullopt;
  };
  auto range = [](double v, double lo, double hi) { return v >= lo && v <= hi; };

  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    if (flag == "--help" || flag == "-h") {
      std::cout << server_usage();
      exit_code = 0;
      return std::nullopt;
    }
    static const std::map<std::string, int> with_value = {
        {"--db", 1}, {"--host", 1}, {"--port", 1}, {"--port-file", 1}, {"--submit-token", 1},
        {"--worker-token", 1}, {"--web-dir", 1}, {"--lease-seconds", 1},
        {"--rescue-interval", 1}, {"--retry-backoff", 1}, {"--max-sweep-points", 1},
        {"--max-upload-mb", 1}, {"--http-threads", 1}, {"--request-timeout", 1},
        {"--log-level", 1}};
    if (!with_value.count(flag)) return error(flag, "unknown option (see --help)");
    if (i + 1 >= argc) return error(flag, "needs a value");
    const std::string v = argv[++i];
    double d = 0;
    int n = 0;
    if (flag == "--db") {
      if (v.empty()) return error(flag, "must not be empty");
      o.db = v;
    } else if (flag == "--host") {
      if (v.empty()) return error(flag, "must not be empty");
      o.host = v;
    } else if (flag == "--port") {
      if (!parse_int(v, n) || !range(n, 0, 65535)) return error(flag, "must be in [0, 65535]");
      o.port = n;
    } else if (flag == "--port-file") {
      o.port_file = v;
    } else if (flag == "--submit-token") {
      o.submit_token = v;
    } else if (flag == "--worker-token") {
      o.worker_token = v;
    } else if (flag == "--web-dir") {
      o.web_dir = v;
    } else if (flag == "--lease-seconds") {
      if (!parse_number(v, d) || !range(d, 0.5, 86400)) {
        return error(flag, "must be a number of seconds in [0.5, 86400]");
      }
      o.lease_seconds = d;
    } else if (flag == "--rescue-interval") {
      if (!parse_number(v, d) || !range(d, 0.05, 3600)) {
        return error(flag, "must be a number of seconds in [0.05, 3600]");
      }
      o.rescue_interval_seconds = d;
    } else if (flag == "--retry-backoff") {
      if (!parse_number(v, d) || !range(d, 0, 3600)) {
        return error(flag, "must be a number of seconds in [0, 3600]");
      }
      o.retry_backoff_seconds = d;
    } else if (flag == "--max-sweep-points") {
      if (!parse_int(v, n) || !range(n, 1, 1000000)) {
        return error(flag, "must be an integer in [1, 1000000]");
      }
      o.max_sweep_points = n;
    } else if (flag == "--max-upload-mb") {
      if (!parse_int(v, n) || !range(n, 1, 4096)) {
        return error(flag, "must be an integer in [1, 4096], got \"" + v + "\"");
      }
      o.max_upload_mb = n;
    } else if (flag == "--http-threads") {
      if (!parse_int(v, n) || !range(n, 1, 1024)) {
        return error(flag, "must be an integer in [1, 1024], got \"" + v + "\"");
      }
      o.http_threads = n;
    } else if (flag == "--request-timeout") {
      if (!parse_number(v, d) || !range(d, 1, 86400)) {
        return error(flag, "must be a number of seconds in [1, 86400], got \"" + v + "\"");
      }
      o.request_timeout_seconds = d;
    } else if (flag == "--log-level") {
      if (v != "trace" && v != "debug" && v != "info" && v != "warn" && v != "error") {
        return error(flag, "must be trace, debug, info, warn or error");
      }
      o.log_level = v;
    }
  }
  if (!is_loopback_host(o.host) && (o.submit_token.empty() || o.worker_token.empty())) {
    return error("--host", "listening on " + o.host +
                               " (not a loopback address, or a name that does not resolve)"
                               " needs --submit-token and --worker-token");
  }
  exit_code = 0;
  return o;
}

}  // namespace compaction::server
