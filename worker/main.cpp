// compaction-worker: the headless loop. Lease a job, run it (job_runner.hpp), repeat; stop on
// SIGTERM/SIGINT (releasing the current lease), after --max-jobs, or after --idle-exit seconds
// without work. Never touches the database: everything goes through the server's HTTP API.
#include <signal.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>
#include <thread>

#include <spdlog/spdlog.h>

#include "api_client.hpp"
#include "job_runner.hpp"
#include "options.hpp"
#include "runner_version.hpp"
#include "scratch.hpp"

using namespace compaction::worker;

namespace {

// Exit codes a batch scheduler can read (also in --help).
constexpr int exit_done = 0;         // stopped by signal, --max-jobs or --idle-exit
constexpr int exit_error = 1;        // the work folder, a malformed answer
constexpr int exit_refused = 2;      // bad flags (or a runner without a version), or the server
                                     // refused the worker (token)
constexpr int exit_unreachable = 3;  // the server never answered

std::atomic<bool> stop_requested{false};

extern "C" void on_signal(int) { stop_requested = true; }

void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;  // no SA_RESTART: a blocking poll() returns at once
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  signal(SIGPIPE, SIG_IGN);
}

// Sleeps up to `seconds`, waking early when a stop is requested.
void nap(double seconds) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (!stop_requested && std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

}  // namespace

int main(int argc, char** argv) {
  // First: a SIGTERM while the worker starts (a batch system's scancel right after srun started
  // it, while the runner says its version) stops it as any other, instead of killing it.
  install_signal_handlers();
  int exit_code = 0;
  const auto options = parse_worker_options(argc, argv, exit_code);
  if (!options) return exit_code;
  spdlog::set_level(spdlog::level::from_str(options->log_level));
  spdlog::set_pattern("%Y-%m-%dT%H:%M:%S.%e %^%l%$ worker " + options->name + ": %v");
  RunnerVersion engine;  // what the runner runs, not what this worker was built with
  try {
    engine = ask_runner_version(options->runner);
  } catch (const std::exception& e) {
    if (stop_requested) {  // a batch system signals the runner it started for --version as well
      spdlog::info("stopped by signal while starting ({})", e.what());
      return exit_done;
    }
    std::cerr << "compaction-worker: --runner: " << e.what() << "\n";
    return exit_refused;
  }

  std::unique_ptr<ScratchFolder> scratch;
  try {
    scratch = std::make_unique<ScratchFolder>(options->work_dir);
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return exit_error;
  }
  if (const int n = scratch->remove_leftovers(); n > 0) {
    spdlog::info("removed {} job folder(s) left in {} by an earlier worker", n, options->work_dir);
  }
  if (const int n = scratch->remove_dead_siblings(); n > 0) {
    spdlog::info("removed {} work folder(s) of workers that are gone", n);
  }
  ApiClient client(options->server, options->token);
  JobRunner runner(*options, client, stop_requested);
  spdlog::info("started: server={} runner={} engine={} ({}) threads={} work_dir={}",
               options->server, options->runner, engine.engine_version, engine.source_revision,
               options->threads, options->work_dir);

  int jobs = 0;
  auto last_work = std::chrono::steady_clock::now();
  bool warned_unreachable = false;
  bool asked = false;    // the worker asked the server at least once (not when a signal came first)
  bool reached = false;  // the server answered at least once
  while (!stop_requested) {
    if (options->max_jobs > 0 && jobs >= options->max_jobs) {
      spdlog::info("done: {} job(s), the --max-jobs limit", jobs);
      break;
    }
    const Reply r = client.lease(options->name, engine.engine_version);
    asked = true;
    if (r.outcome != Outcome::unreachable) reached = true;
    if (r.outcome == Outcome::ok) {
      warned_unreachable = false;
      LeasedJob job;
      try {
        job.id = r.body.at("job_id").get<std::int64_t>();
        job.token = r.body.at("lease_token").get<std::string>();
        job.scene = r.body.at("scene");
        job.lease_seconds = r.body.at("lease_seconds").get<double>();
        job.attempt = r.body.at("attempt").get<int>();
        job.max_attempts = r.body.at("max_attempts").get<int>();
        job.checkpoint = r.body.value("checkpoint", nlohmann::json());
      } catch (const std::exception& e) {
        spdlog::error("malformed lease answer ({}): {}", e.what(),
                      r.body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace).substr(0, 500));
        return exit_error;
      }
      ++jobs;
      // Unless this is the last job (--max-jobs), the result's upload asks for the next one.
      std::optional<NextLease> next;
      if (options->max_jobs == 0 || jobs < options->max_jobs) {
        next = NextLease{options->name, engine.engine_version};
      }
      const JobEnd end = runner.run(job, next);
      spdlog::info("job {} ended: {}", job.id, to_string(end));
      last_work = std::chrono::steady_clock::now();
      continue;
    }
    if (r.outcome == Outcome::rejected || r.outcome == Outcome::not_found) {
      // A wrong token or a server that is not compaction-server: waiting will not help.
      spdlog::error("the server refused the lease request (HTTP {}): {}", r.status, r.message);
      return exit_refused;
    }
    if (r.outcome == Outcome::unreachable && !warned_unreachable) {
      spdlog::warn("server unreachable ({}); retrying every {} s", r.message, options->poll_interval);
      warned_unreachable = true;
    }
    const double idle =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - last_work).count();
    if (options->idle_exit > 0 && idle >= options->idle_exit) {
      spdlog::info("done: idle for {:.0f} s ({} job(s))", idle, jobs);
      break;
    }
    nap(options->poll_interval);
  }
  if (stop_requested) spdlog::info("stopped by signal after {} job(s)", jobs);
  client.release_unclaimed();  // a job the last upload leased, when a signal came before it ran
  if (!options->keep_work) scratch->remove_if_empty();
  if (asked && !reached) {
    spdlog::error("the server at {} never answered", options->server);
    return exit_unreachable;
  }
  return exit_done;
}
