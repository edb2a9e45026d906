#include "options.hpp"

#include "compaction/text_numbers.hpp"
#include "scratch.hpp"

#include <unistd.h>

#include <climits>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <set>

namespace compaction::worker {

namespace {

const char* usage = R"(compaction-worker: leases jobs from compaction-server, runs each one with
compaction-run in a child process, heartbeats its progress and uploads the result bundle.

usage: compaction-worker [options]

  --server URL            server base URL (default http://127.0.0.1:8080)
  --token TOKEN           worker token (env COMPACTION_WORKER_TOKEN)
  --threads N             threads per run (default 1)
  --max-jobs N            exit after N jobs (default 0: no limit)
  --idle-exit SECONDS     exit after SECONDS without a job (default 0: never)
  --runner PATH           the runner (default: compaction-run next to this executable)
  --work-dir DIR          scratch folder for the runs, one per worker
                          (default: $TMPDIR/compaction-worker-PID)
  --name NAME             worker name shown by the server (default: host:pid)
  --poll-interval S       wait between lease attempts when the queue is empty (default 2)
  --keep-work             keep each job's folder (scene.json, bundle, stderr.log)
  --log-level LEVEL       trace, debug, info, warn, error (default info)
  --help                  this text

SIGTERM or SIGINT: the run is stopped, the lease released (the job requeues at once), exit 0.
Exit codes: 0 done (signal, --max-jobs, --idle-exit), 1 error (work folder, malformed answer),
2 bad flags or the server refused the worker (token), 3 the server never answered.
The work folder is locked while the worker runs; at start the worker clears its leftovers and
removes the default-named folders ($TMPDIR/compaction-worker-PID) of workers that are gone.
)";

using compaction::parse_int;
bool parse_double(const std::string& s, double& out) { return compaction::parse_finite_real(s, out); }

std::string self_dir() {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string(".") : exe.parent_path().string();
}

}  // namespace

std::optional<WorkerOptions> parse_worker_options(int argc, char** argv, int& exit_code) {
  WorkerOptions o;
  if (const char* t = std::getenv("COMPACTION_WORKER_TOKEN")) o.token = t;
  auto error = [&](const std::string& flag, const std::string& message) {
    std::cerr << "compaction-worker: " << flag << ": " << message << "\n";
    exit_code = 2;
    return std::nullopt;
  };
  static const std::set<std::string> valued = {
      "--server", "--token", "--threads", "--max-jobs", "--idle-exit", "--runner",
      "--work-dir", "--name", "--poll-interval", "--log-level"};
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    if (flag == "--help" || flag == "-h") {
      std::cout << usage;
      exit_code = 0;
      return std::nullopt;
    }
    if (flag == "--keep-work") {
      o.keep_work = true;
      continue;
    }
    if (!valued.count(flag)) return error(flag, "unknown option (see --help)");
    if (i + 1 >= argc) return error(flag, "needs a value");
    const std::string v = argv[++i];
    double d = 0;
    int n = 0;
    if (flag == "--server") {
      if (v.rfind("http://", 0) != 0 && v.rfind("https://", 0) != 0) {
        return error(flag, "must be an http:// or https:// URL, got \"" + v + "\"");
      }
      o.server = v;
      while (o.server.size() > 8 && o.server.back() == '/') o.server.pop_back();
    } else if (flag == "--token") {
      o.token = v;
    } else if (flag == "--threads") {
      if (!parse_int(v, n) || n < 1 || n > 256) return error(flag, "must be an integer in [1, 256]");
      o.threads = n;
    } else if (flag == "--max-jobs") {
      if (!parse_int(v, n) || n < 0) return error(flag, "must be a non-negative integer");
      o.max_jobs = n;
    } else if (flag == "--idle-exit") {
      if (!parse_double(v, d) || d < 0 || d > 1e7) return error(flag, "must be seconds >= 0");
      o.idle_exit = d;
    } else if (flag == "--runner") {
      o.runner = v;
    } else if (flag == "--work-dir") {
      if (v.empty()) return error(flag, "must not be empty");
      o.work_dir = v;
    } else if (flag == "--name") {
      if (v.empty() || v.size() > 200) return error(flag, "must be 1 to 200 characters");
      o.name = v;
    } else if (flag == "--poll-interval") {
      if (!parse_double(v, d) || d < 0.05 || d > 3600) return error(flag, "must be seconds in [0.05, 3600]");
      o.poll_interval = d;
    } else if (flag == "--log-level") {
      if (v != "trace" && v != "debug" && v != "info" && v != "warn" && v != "error") {
        return error(flag, "must be trace, debug, info, warn or error");
      }
      o.log_level = v;
    }
  }
  if (o.runner.empty()) o.runner = self_dir() + "/compaction-run";
  if (access(o.runner.c_str(), X_OK) != 0) {
    return error("--runner", o.runner + " is not an executable file");
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
