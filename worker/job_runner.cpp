#include "job_runner.hpp"

#include <algorithm>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <spdlog/spdlog.h>


namespace compaction::worker {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

const char* to_string(JobEnd e) {
  switch (e) {
    case JobEnd::succeeded: return "succeeded";
    case JobEnd::failed: return "failed";
    case JobEnd::lease_lost: return "lease_lost";
    case JobEnd::released: return "released";
    case JobEnd::not_reported: return "not_reported";
  }
  return "unknown";
}

namespace {

std::string read_file(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// Retries a report while the server is unreachable, for at most `patience` seconds.
template <typename Call>
Reply with_patience(Call call, double patience, const std::atomic<bool>& stop, bool give_up_on_stop) {
  const auto start = Clock::now();
  double wait = 0.5;
  for (;;) {
    Reply r = call();
    if (r.outcome != Outcome::unreachable || seconds_since(start) > patience) return r;
    if (give_up_on_stop && stop) return r;
    spdlog::warn("server unreachable ({}); retrying in {:.1f} s", r.message, wait);
    std::this_thread::sleep_for(std::chrono::duration<double>(wait));
    wait = std::min(wait * 2, 5.0);
  }
}

}  // namespace

JobRunner::JobRunner(const WorkerOptions& options, ApiClient& client, const std::atomic<bool>& stop)
    : options_(options), client_(client), stop_(stop) {}

JobEnd JobRunner::run(const LeasedJob& job, const std::optional<NextLease>& next) {
  const fs::path dir = fs::path(options_.work_dir) /
                       ("job-" + std::to_string(job.id) + "-a" + std::to_string(job.attempt));
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::create_directories(dir);
  struct Cleanup {
    fs::path dir;
    bool keep;
    ~Cleanup() {
      std::error_code e;
      if (!keep) fs::remove_all(dir, e);
    }
  } cleanup{dir, options_.keep_work};

  json scene = job.scene;
  scene["threads"] = options_.threads;
  std::ofstream(dir / "scene.json") << scene.dump(2) << "\n";
  const std::string out_dir = (dir / "out").string();
  const std::string stderr_file = (dir / "stderr.log").string();
  checkpoint_ = {(dir / "checkpoint.bin").string()};
  resume_report_ = nullptr;
  std::string resume = fetch_checkpoint(job, dir.string());

  for (;;) {
    std::vector<std::string> argv = {options_.runner, "--scene", (dir / "scene.json").string(),
                                     "--out", out_dir, "--progress", "json",
                                     "--checkpoint", checkpoint_.file, "--checkpoint-every",
                                     json(options_.checkpoint_every).dump()};
    if (!resume.empty()) argv.insert(argv.end(), {"--resume", resume});
    std::unique_ptr<ChildProcess> child;
    try {
      child = std::make_unique<ChildProcess>(argv, stderr_file);
    } catch (const std::exception& e) {
      return report_failure(job, std::string("cannot start the runner: ") + e.what(), true);
    }
    spdlog::info("job {} started: S={} R={} phi={} cells_per_unit={} attempt {}/{} pid={}{}",
                 job.id, scene.value("S", 0.0), scene.value("R", 0.0), scene.value("phi", 0.0),
                 scene.value("cells_per_unit", 0), job.attempt, job.max_attempts, child->pid(),
                 resume.empty() ? "" : " (resuming)");
    const Watched w = watch(job, *child);
    if (w.end) return *w.end;
    if (!resume.empty() && !w.exit.signaled && w.exit.code == 4) {
      spdlog::warn("job {}: the runner refused the checkpoint ({}); running from the start",
                   job.id, tail_of_file(stderr_file, 500));
      resume.clear();
      continue;
    }
    return conclude(job, w, out_dir, stderr_file, next);
  }
}

std::string JobRunner::fetch_checkpoint(const LeasedJob& job, const std::string& dir) {
  if (!job.checkpoint.is_object()) return {};
  std::string bytes;
  const Reply r = client_.download_checkpoint(job.id, bytes);
  if (r.outcome != Outcome::ok) {
    spdlog::warn("job {}: cannot download its checkpoint ({}); running from the start", job.id,
                 r.message.empty() ? "HTTP " + std::to_string(r.status) : r.message);
    return {};
  }
  const std::string path = (fs::path(dir) / "resume.bin").string();
  std::ofstream(path, std::ios::binary) << bytes;
  spdlog::info("job {}: going on from the checkpoint at step {} (eps {}) of {}, {} bytes", job.id,
               job.checkpoint.value("step", 0), job.checkpoint.value("eps", 0.0),
               job.checkpoint.value("worker", std::string("?")), bytes.size());
  return path;
}

void JobRunner::upload_checkpoint(const LeasedJob& job) {
  if (checkpoint_.step < 0 || checkpoint_.uploaded) return;
  const std::string bytes = read_file(checkpoint_.file);
  if (bytes.empty()) {
    spdlog::warn("job {}: the checkpoint {} is missing", job.id, checkpoint_.file);
    return;
  }
  const Reply r = client_.upload_checkpoint(job.id, job.token, checkpoint_.step, checkpoint_.eps,
                                            bytes);
  if (r.outcome == Outcome::ok) {
    checkpoint_.uploaded = true;
    spdlog::info("job {}: checkpoint at step {} (eps {:.4f}) uploaded, {} bytes", job.id,
                 checkpoint_.step, checkpoint_.eps, bytes.size());
  } else {
    spdlog::warn("job {}: checkpoint upload failed ({})", job.id, r.message);
  }
}

void JobRunner::handle_line(const LeasedJob& job, const std::string& line, double& eps,
                            Watched& w) {
  const json ev = json::parse(line, nullptr, false);
  if (!ev.is_object()) {
    spdlog::debug("job {} runner: {}", job.id, line);
    return;
  }
  const std::string kind = ev.value("event", std::string());
  if (kind == "progress" && ev.contains("eps") && ev["eps"].is_number()) {
    eps = std::clamp(ev["eps"].get<double>(), 0.0, 1.0);
  } else if (kind == "checkpoint" && ev.contains("step") && ev["step"].is_number_integer()) {
    checkpoint_.step = ev["step"].get<std::int64_t>();
    checkpoint_.eps = std::clamp(ev.value("eps", 0.0), 0.0, 1.0);
    checkpoint_.uploaded = false;
    if (!stop_) upload_checkpoint(job);  // when stopping, after the runner has exited
  } else if (kind == "resumed" && ev.contains("step") && ev["step"].is_number_integer()) {
    resume_report_ = {{"step", ev["step"].get<std::int64_t>()},
                      {"eps", std::clamp(ev.value("eps", 0.0), 0.0, 1.0)}};
    eps = resume_report_["eps"].get<double>();
  } else if (kind == "done") {
    w.done_status = ev.value("status", std::string());
    w.done_reason = ev.value("reason", std::string());
  }
}

JobRunner::Watched JobRunner::watch(const LeasedJob& job, ChildProcess& child) {
  const double hb_interval = std::clamp(job.lease_seconds / 3.0, 0.2, 10.0);
  auto last_hb = Clock::now();
  double eps = 0.0, reported_eps = 0.0;
  Watched w;
  for (;;) {
    for (const std::string& line : child.read_lines(200)) handle_line(job, line, eps, w);
    if (stop_) {
      // The runner writes its final checkpoint when SIGTERM stops it; its line is read after.
      child.terminate(5000);
      while (!child.eof()) {
        for (const std::string& line : child.read_lines(200)) handle_line(job, line, eps, w);
      }
      spdlog::info("job {}: stopping (signal); run stopped at eps={:.4f}", job.id, eps);
      upload_checkpoint(job);
      w.end = release(job);
      return w;
    }
    const double since = seconds_since(last_hb);
    if (since >= hb_interval || !resume_report_.is_null() ||
        (eps > reported_eps && since >= std::min(1.0, hb_interval))) {
      const Reply r = client_.heartbeat(job.id, job.token, eps, resume_report_);
      last_hb = Clock::now();
      if (r.outcome == Outcome::ok) {
        if (!resume_report_.is_null()) {
          spdlog::info("job {}: resume reported", job.id);
          resume_report_ = nullptr;
        }
        reported_eps = eps;
      } else if (r.outcome == Outcome::lease_lost || r.outcome == Outcome::not_found) {
        child.terminate(2000);
        spdlog::warn("job {}: lease lost ({}); run stopped, nothing reported", job.id, r.message);
        w.end = JobEnd::lease_lost;
        return w;
      } else {
        spdlog::warn("job {}: heartbeat failed ({}); the run goes on", job.id, r.message);
      }
    }
    if (child.eof()) {
      if (const auto exit = child.poll_exit()) {
        w.exit = *exit;
        return w;
      }
    }
  }
}

JobEnd JobRunner::conclude(const LeasedJob& job, const Watched& w, const std::string& out_dir,
                           const std::string& stderr_file, const std::optional<NextLease>& next) {
  const std::string err_tail = tail_of_file(stderr_file, 2000);
  // The runner exits 3 when a SIGTERM or SIGINT that this worker did not send stops it (before
  // its handler is installed, the signal kills it). A batch system sends one to every process
  // of the job at its time limit or on scancel, and the worker's own signal may come a moment
  // later: the run did not fail, so the job goes back to the queue without counting the attempt.
  if ((!w.exit.signaled && w.exit.code == 3) ||
      (w.exit.signaled && (w.exit.code == SIGTERM || w.exit.code == SIGINT))) {
    spdlog::info("job {}: the runner was stopped from outside ({})", job.id, w.exit.describe());
    upload_checkpoint(job);
    return release(job);
  }
  if (w.exit.signaled) {
    return report_failure(job, "runner crashed: " + w.exit.describe() +
                                   (err_tail.empty() ? "" : "; stderr: " + err_tail),
                          true);
  }
  switch (w.exit.code) {
    case 0:
      spdlog::info("job {}: run ended status={}{}", job.id,
                   w.done_status.empty() ? "?" : w.done_status,
                   w.done_reason.empty() ? "" : " (" + w.done_reason + ")");
      return upload(job, out_dir, next);
    case 2:
      return report_failure(job, "invalid input: " + err_tail, false);
    default:
      return report_failure(job, "runner failed with " + w.exit.describe() +
                                     (err_tail.empty() ? "" : ": " + err_tail),
                            true);
  }
}

JobEnd JobRunner::upload(const LeasedJob& job, const std::string& out_dir,
                         const std::optional<NextLease>& next) {
  const fs::path summary_path = fs::path(out_dir) / "summary.json";
  if (!fs::exists(summary_path)) {
    return report_failure(job, "the runner exited 0 without writing summary.json", true);
  }
  const std::string summary = read_file(summary_path);
  std::vector<UploadFile> files;
  std::size_t bytes = 0;
  for (const auto& entry : fs::directory_iterator(out_dir)) {
    if (!entry.is_regular_file()) continue;
    files.push_back({entry.path().filename().string(), read_file(entry.path())});
    bytes += files.back().data.size();
  }
  std::sort(files.begin(), files.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  const Reply r = with_patience([&] { return client_.complete(job.id, job.token, summary, files, next); },
                                job.lease_seconds, stop_, false);
  switch (r.outcome) {
    case Outcome::ok:
      spdlog::info("job {}: result uploaded ({} files, {} bytes)", job.id, files.size(), bytes);
      return JobEnd::succeeded;
    case Outcome::lease_lost:
    case Outcome::not_found:
      spdlog::warn("job {}: lease lost before the upload ({}); result discarded", job.id, r.message);
      return JobEnd::lease_lost;
    case Outcome::rejected:
      return report_failure(job, "the server refused the result: " + r.message, false);
    default:
      spdlog::error("job {}: could not upload the result ({}); the lease will expire", job.id,
                    r.message);
      return JobEnd::not_reported;
  }
}

JobEnd JobRunner::report_failure(const LeasedJob& job, const std::string& reason, bool retryable) {
  spdlog::warn("job {} failed (retryable={}): {}", job.id, retryable, reason);
  const Reply r = with_patience([&] { return client_.fail(job.id, job.token, reason, retryable); },
                                job.lease_seconds, stop_, false);
  if (r.outcome == Outcome::ok) return JobEnd::failed;
  if (r.outcome == Outcome::lease_lost || r.outcome == Outcome::not_found) return JobEnd::lease_lost;
  spdlog::error("job {}: could not report the failure ({})", job.id, r.message);
  return JobEnd::not_reported;
}

JobEnd JobRunner::release(const LeasedJob& job) {
  const Reply r = with_patience([&] { return client_.release(job.id, job.token); }, 5.0, stop_, false);
  if (r.outcome == Outcome::ok) {
    spdlog::info("job {}: lease released, the job is queued again", job.id);
    return JobEnd::released;
  }
  spdlog::warn("job {}: release failed ({}); the lease will expire", job.id, r.message);
  return r.outcome == Outcome::lease_lost ? JobEnd::lease_lost : JobEnd::not_reported;
}

}  // namespace compaction::worker
