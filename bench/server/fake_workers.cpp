// Fake workers for bench/server/queue_bench.py: N threads, each a worker with the real worker's
// HTTP client (worker/api_client.cpp: the same requests and connections as compaction-worker,
// the next job asked for with each result) that leases a job and at once completes it with a
// minimal valid bundle (the leased scene's summary with a classification, and one 200-byte
// frames.csv), without the simulation. It counts the lease + complete cycles that start and end within a window of wall
// time and prints one JSON object:
//   {"cycles": N, "median_seconds": t, "idle": leases that found nothing, "errors": [...]}
//
// usage: queue_fake_workers --url URL --engine VERSION [--clients N] [--start UNIX_SECONDS]
//        [--seconds S] [--token T] [--separate-lease]
// Exit code 0 when every request was answered as a worker expects, 1 otherwise (the errors are
// in the JSON), 2 on bad flags.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "api_client.hpp"
#include "command_line.hpp"

namespace {

using nlohmann::json;
using compaction::worker::ApiClient;
using compaction::worker::Outcome;

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

// The bundle queue_bench.py's Python fake worker uploads: frames.csv of 15 rows.
std::string frames_csv() {
  std::string s = "eps,stress\n";
  char row[64];
  for (int i = 0; i < 15; ++i) {
    std::snprintf(row, sizeof row, "%.3f,%.6f\n", i / 100.0, i * 1e-4);
    s += row;
  }
  return s;
}

std::string summary_of(const json& scene, const std::string& engine) {
  return json{{"status", "ok"},
              {"params", scene},
              {"engine_version", engine},
              {"source_revision", "queue-bench"},
              {"eps_reached", scene.at("eps_end")},
              {"wall_seconds", 0.01},
              {"classification",
               {{"class", "a"},
                {"confidence", 0.9},
                {"runner_up", "b"},
                {"n_reflections", 2},
                {"band_speed_ratio", 1.7},
                {"features", {{"band_speed_ratio", 1.7}, {"band_speed_error", 0.01}}}}}}
      .dump();
}

struct Tally {
  std::int64_t cycles = 0;
  std::int64_t idle = 0;
  std::vector<double> times;
  std::vector<std::string> errors;
};

void worker(const std::string& url, const std::string& token, const std::string& engine,
            const std::string& name, double start, double end, bool next_lease, Tally& out) {
  ApiClient api(url, token);
  const compaction::worker::NextLease next{name, engine};
  const std::vector<compaction::worker::UploadFile> files = {{"frames.csv", frames_csv()}};
  while (now_seconds() < end && out.errors.size() < 5) {
    const double t0 = now_seconds();
    const auto lease = api.lease(name, engine);
    if (lease.outcome == Outcome::empty) {
      ++out.idle;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      continue;
    }
    if (lease.outcome != Outcome::ok) {
      out.errors.push_back("lease -> " + std::to_string(lease.status) + " " + lease.message);
      continue;
    }
    const auto id = lease.body.at("job_id").get<std::int64_t>();
    const auto token_of_lease = lease.body.at("lease_token").get<std::string>();
    const auto done = api.complete(id, token_of_lease, summary_of(lease.body.at("scene"), engine),
                                   files, next_lease ? std::optional(next) : std::nullopt);
    if (done.outcome != Outcome::ok) {
      out.errors.push_back("complete -> " + std::to_string(done.status) + " " + done.message);
      continue;
    }
    const double t1 = now_seconds();
    if (start <= t0 && t1 <= end) {
      ++out.cycles;
      out.times.push_back(t1 - t0);
    }
  }
  api.release_unclaimed();  // the job the last complete leased, which no cycle runs
}

}  // namespace

int main(int argc, char** argv) {
  compaction::cli::CommandLine cli(
      "queue_fake_workers", "Fake workers for bench/server/queue_bench.py: lease + complete cycles.",
      "--url URL --engine VERSION [options]");
  std::string url, token, engine;
  int clients = 1;
  double start = 0, seconds = 3;
  cli.text("--url", url, "URL", "the server, e.g. http://127.0.0.1:8080", {}, true);
  cli.integer("--clients", clients, {1, 1024}, "N", "workers, one thread each");
  cli.real("--start", start, {0, 1e11}, "SECONDS",
           "when counting starts, seconds since the epoch (0: at once)");
  cli.real("--seconds", seconds, {0.1, 3600}, "S", "how long counting lasts");
  cli.text("--token", token, "TOKEN", "the worker token");
  cli.text("--engine", engine, "VERSION", "the engine version the leases name", {}, true);
  bool separate_lease = false;
  cli.flag("--separate-lease", separate_lease,
           "lease with a request of its own after each complete, as compaction-worker did until "
           "2026-12-03, instead of asking for the next job in the complete");
  if (const auto code = cli.parse(argc, argv)) return *code;
  if (url.empty()) return cli.fail("--url", "is required");
  if (engine.empty()) return cli.fail("--engine", "is required");
  if (start == 0) start = now_seconds();

  const double end = start + seconds;
  std::vector<Tally> tallies(static_cast<std::size_t>(clients));
  std::vector<std::thread> threads;
  for (int i = 0; i < clients; ++i) {
    threads.emplace_back(worker, url, token, engine, "bench-" + std::to_string(i), start, end,
                         !separate_lease, std::ref(tallies[static_cast<std::size_t>(i)]));
  }
  for (auto& t : threads) t.join();

  json out = {{"cycles", 0}, {"idle", 0}, {"median_seconds", nullptr}, {"errors", json::array()}};
  std::vector<double> times;
  for (const Tally& t : tallies) {
    out["cycles"] = out["cycles"].get<std::int64_t>() + t.cycles;
    out["idle"] = out["idle"].get<std::int64_t>() + t.idle;
    times.insert(times.end(), t.times.begin(), t.times.end());
    for (const auto& e : t.errors) out["errors"].push_back(e);
  }
  if (!times.empty()) {
    std::nth_element(times.begin(), times.begin() + times.size() / 2, times.end());
    out["median_seconds"] = times[times.size() / 2];
  }
  std::puts(out.dump().c_str());
  return out["errors"].empty() ? 0 : 1;
}
