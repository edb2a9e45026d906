// compaction-server: opens (and migrates) the database, starts the lease rescuer and serves the
// REST API, the metrics and the dashboard until SIGINT or SIGTERM.
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <thread>

#include <spdlog/spdlog.h>

#include "compaction/result.hpp"
#include "config/options.hpp"
#include "exchange/import_command.hpp"
#include "http/http_server.hpp"
#include "routes/app.hpp"
#include "store/lease_rescuer.hpp"

using namespace compaction::server;

int main(int argc, char** argv) {
  int exit_code = 0;
  const auto options = parse_server_options(argc, argv, exit_code);
  if (!options) return exit_code;
  spdlog::set_level(spdlog::level::from_str(options->log_level));
  spdlog::set_pattern("%Y-%m-%dT%H:%M:%S.%e %^%l%$ server: %v");
  if (!options->import_file.empty()) return run_import(*options, options->import_file);

  // Signals go to a dedicated thread (sigwait), never into the middle of a handler. A handler
  // is installed first: a signal ignored at start (a background job of a script) would
  // otherwise be discarded instead of waiting for sigwait.
  struct sigaction sa {};
  sa.sa_handler = [](int) {};
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  std::signal(SIGPIPE, SIG_IGN);

  try {
    const std::filesystem::path db_path(options->db);
    if (db_path.has_parent_path()) std::filesystem::create_directories(db_path.parent_path());

    StoreConfig config;
    config.lease_ms = static_cast<Millis>(options->lease_seconds * 1000);
    config.backoff_base_ms = static_cast<Millis>(options->retry_backoff_seconds * 1000);
    config.engine_version = compaction::engine_version();
    Store store(options->db, config);

    App app{store, *options, {}, {}, {}, {}, {}};
    app.limits.max_points = static_cast<std::size_t>(options->max_sweep_points);
    app.limits.max_bundle_bytes = static_cast<std::size_t>(options->max_upload_mb) << 20;

    ConnectionLimits connections;
    connections.max_threads = options->http_threads;
    connections.request_timeout_seconds = options->request_timeout_seconds;
    HttpServer server(connections);
    // The request guard refuses a body above its endpoint's limit before reading it; this is
    // the library's own cap, at the largest of those limits.
    server.set_payload_max_length(app.limits.max_bundle_bytes);
    register_all_routes(server, app);

    const int port = options->port == 0 ? server.bind_to_any_port(options->host)
                                        : (server.bind_to_port(options->host, options->port)
                                               ? options->port
                                               : -1);
    if (port < 0) {
      spdlog::error("cannot listen on {}:{}: {} (is another server using the port?)",
                    options->host, options->port, std::strerror(errno));
      return 1;
    }
    if (!options->port_file.empty()) {
      const std::string tmp = options->port_file + ".tmp";
      std::ofstream(tmp) << port << "\n";
      std::filesystem::rename(tmp, options->port_file);
    }

    // Adaptive sweeps whose last result was stored just before the server stopped plan on.
    app.adaptive.advance_all(store, app.limits, now_ms());
    LeaseRescuer rescuer(
        store.queue, std::chrono::milliseconds(static_cast<long>(options->rescue_interval_seconds * 1000)),
        [&app] { app.adaptive.advance_all(app.store, app.limits, now_ms()); });
    std::atomic<bool> signalled{false};
    std::thread signal_thread([&server, &signalled, signals] {
      int sig = 0;
      sigwait(&signals, &sig);
      signalled = true;
      spdlog::info("signal {}: stopping", sig);
      server.stop();
    });
    spdlog::info("listening on http://{}:{} db={} engine={} ({}) lease={}s tokens: submit={} worker={}",
                 options->host, port, options->db, compaction::engine_version(),
                 compaction::source_revision(), options->lease_seconds,
                 options->tokens.open(TokenKind::submit) ? "open" : "required",
                 options->tokens.open(TokenKind::worker) ? "open" : "required");
    const bool ok = server.listen_after_bind();
    if (!ok && server.is_running()) spdlog::error("the server stopped unexpectedly");
    // The listener ended on its own: wake the signal thread (SIGTERM is blocked elsewhere).
    if (!signalled) kill(getpid(), SIGTERM);
    signal_thread.join();
    spdlog::info("stopped");
    return 0;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
}
