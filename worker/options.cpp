#include "options.hpp"

#include <unistd.h>

#include <climits>
#include <cstdlib>
#include <filesystem>

#include "command_line.hpp"
#include "scratch.hpp"

namespace compaction::worker {

namespace {

const char* kNotes =
    "SIGTERM or SIGINT: the run is stopped, it writes a checkpoint of its state, the worker\n"
    "uploads it and releases the lease (the job requeues at once, and the next worker that\n"
    "leases it goes on from the checkpoint), exit 0.\n"
    "Exit codes: 0 done (signal, --max-jobs, --idle-exit), 1 error (work folder, malformed answer),\n"
    "2 bad flags (also a runner that cannot say its version) or the server refused the worker\n"
    "(token), 3 the server never answered.\n"
    "The work folder is locked while the worker runs; at start the worker clears its leftovers and\n"
    "removes the default-named folders ($TMPDIR/compaction-worker-PID) of workers that are gone.\n"
    "Leases ask for the engine version the runner reports (compaction-run --version).\n";

std::string self_dir() {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string(".") : exe.parent_path().string();
}

// The flags, their ranges and defaults in one place: parsing and --help read them.
cli::CommandLine command_line(WorkerOptions& o) {
  cli::CommandLine cl("compaction-worker",
                      "leases jobs from compaction-server, runs each one with\n"
                      "compaction-run in a child process, heartbeats its progress and uploads the "
                      "result bundle.",
                      "[options]");
  cl.custom(
      "--server",
      [&o](const std::string& v) {
        if (v.rfind("http://", 0) != 0 && v.rfind("https://", 0) != 0) {
          throw cli::UsageError{"--server", "must be an http:// or https:// URL, got '" + v + "'"};
        }
        o.server = v;
        while (o.server.size() > 8 && o.server.back() == '/') o.server.pop_back();
      },
      "URL", "server base URL", o.server);
  cl.text("--token", o.token, "TOKEN", "worker token (env COMPACTION_WORKER_TOKEN)");
  cl.integer("--threads", o.threads, limits::threads, "N", "threads per run");
  cl.custom(
      "--max-jobs",
      [&o](const std::string& v) {
        long long n = 0;
        if (!cli::parse_int(v, n) || n < 0 || n > INT_MAX) {
          throw cli::UsageError{"--max-jobs", "expected a non-negative integer, got '" + v + "'"};
        }
        o.max_jobs = static_cast<int>(n);
      },
      "N", "exit after N jobs (0: no limit)", std::to_string(o.max_jobs));
  cl.real("--idle-exit", o.idle_exit, {0, 1e7}, "SECONDS",
          "exit after SECONDS without a job (0: never)");
  cl.text("--runner", o.runner, "PATH", "the runner", "compaction-run next to this executable");
  cl.text("--work-dir", o.work_dir, "DIR", "scratch folder for the runs, one per worker",
          "$TMPDIR/compaction-worker-PID", true);
  cl.custom(
      "--name",
      [&o](const std::string& v) {
        if (v.empty() || v.size() > 200) {
          throw cli::UsageError{"--name", "must be 1 to 200 characters, got " +
                                              std::to_string(v.size())};
        }
        o.name = v;
      },
      "NAME", "worker name shown by the server", "host:pid");
  cl.real("--poll-interval", o.poll_interval, {0.05, 3600}, "S",
          "wait between lease attempts when the queue is empty, seconds");
  cl.real("--checkpoint-every", o.checkpoint_every, compaction::kCheckpointEveryRange, "SECONDS",
          "wall time between checkpoints of a run, each uploaded to the server\n"
          "(0: only when the run is stopped)");
  cl.flag("--keep-work", o.keep_work, "keep each job's folder (scene.json, bundle, stderr.log)");
  cl.choice("--log-level", o.log_level, {"trace", "debug", "info", "warn", "error"}, "LEVEL",
            "log level");
  cl.notes(kNotes);
  return cl;
}

}  // namespace

std::string worker_usage() {
  WorkerOptions defaults;
  return command_line(defaults).help();
}

std::optional<WorkerOptions> parse_worker_options(int argc, const char* const* argv,
                                                  int& exit_code) {
  WorkerOptions o;
  if (const char* t = std::getenv("COMPACTION_WORKER_TOKEN")) o.token = t;
  cli::CommandLine cl = command_line(o);
  if (const auto code = cl.parse(argc, argv)) {
    exit_code = *code;
    return std::nullopt;
  }
  if (o.runner.empty()) o.runner = self_dir() + "/compaction-run";
  if (access(o.runner.c_str(), X_OK) != 0) {
    exit_code = cl.fail("--runner", o.runner + " is not an executable file");
    return std::nullopt;
  }
  if (o.work_dir.empty()) {
    o.work_dir = (std::filesystem::temp_directory_path() /
                  (std::string(default_scratch_prefix) + std::to_string(getpid())))
                     .string();
  }
  if (o.name.empty()) {
    char host[256] = {};
    gethostname(host, sizeof host - 1);
    o.name = std::string(host) + ":" + std::to_string(getpid());
  }
  exit_code = 0;
  return o;
}

}  // namespace compaction::worker
