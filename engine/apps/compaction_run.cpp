// compaction-run: runs one scene and writes its result bundle. See --help and docs/runner.md.
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <filesystem>
#include <cstdio>
#include <iostream>

#include "cli_args.hpp"
#include "compaction/bundle.hpp"
#include "compaction/params_json.hpp"
#include "compaction/classify.hpp"
#include "compaction/movie.hpp"
#include "compaction/simulation.hpp"

namespace {

std::atomic<bool> g_cancel{false};

extern "C" void on_signal(int) { g_cancel.store(true); }

void print_json_line(const nlohmann::json& j) {
  std::cout << j.dump() << '\n' << std::flush;
}

// Terminal progress bar on stderr, redrawn in place.
void draw_bar(const compaction::Progress& p) {
  const double f = p.eps_end > 0 ? p.eps / p.eps_end : 1.0;
  const int width = 30, filled = static_cast<int>(f * width + 0.5);
  const double eta = f > 0 ? p.wall_seconds * (1.0 - f) / f : 0.0;
  std::fprintf(stderr, "\r[%.*s%*s] eps %.4f/%.4f %5.1f%%  steps %lld  %.0fs  eta %.0fs ",
               filled, "##############################", width - filled, "", p.eps, p.eps_end,
               100.0 * f, static_cast<long long>(p.steps), p.wall_seconds, eta);
  std::fflush(stderr);
}

// The classifier's verdict for summary.json ("classification"): null for a run that is not ok.
nlohmann::json classification_of(const compaction::SceneParams& p, const compaction::RunResult& r) {
  if (r.status != compaction::RunStatus::ok) return nullptr;
  return compaction::classify::summary_json_of(compaction::classify::classify(p, r));
}

std::string number(const nlohmann::json& v, const char* format) {
  if (!v.is_number()) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, format, v.get<double>());
  return buf;
}

// What the run found, in one line: its class with confidence and runner-up, N_r, and the
// band's speed c_b/V with its error where there is a band.
std::string verdict_line(const compaction::RunResult& r, const nlohmann::json& c,
                         const std::string& out_dir) {
  using compaction::RunStatus;
  std::string s = "compaction-run: ";
  if (r.status != RunStatus::ok) {
    s += std::string(compaction::to_string(r.status)) + " at eps " + number(r.eps_reached, "%.4f");
    if (!r.reason.empty()) s += " (" + r.reason + ")";
    return s + ", not classified; bundle " + out_dir;
  }
  const nlohmann::json& f = c.value("features", nlohmann::json::object());
  if (c["class"].is_string()) {
    s += "class " + c["class"].get<std::string>() + " (confidence " +
         number(c["confidence"], "%.2f") + ", runner-up " +
         (c["runner_up"].is_string() ? c["runner_up"].get<std::string>() : "-") + ")";
  } else {
    s += "unclassified (runner-up " +
         (c["runner_up"].is_string() ? c["runner_up"].get<std::string>() : "-") + ")";
  }
  s += ", N_r " + (c["n_reflections"].is_number() ? std::to_string(c["n_reflections"].get<int>()) : "-");
  if (c["band_speed_ratio"].is_number()) {
    s += ", c_b/V " + number(c["band_speed_ratio"], "%.3f") + " +- " +
         number(f.value("band_speed_error", nlohmann::json()), "%.3f") + " (1/(1 - phi) = " +
         number(f.value("nonreflecting_speed", nlohmann::json()), "%.3f") + ")";
  }
  return s + "; bundle " + out_dir;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace compaction;
  auto log = spdlog::stderr_color_mt("run");
  spdlog::set_default_logger(log);

  cli::Options opt;
  if (const auto code = cli::parse(argc, argv, opt)) return *code;

  if (opt.check) {
    nlohmann::json scene = to_json(opt.params);
    scene["grid"] = {{"cells_per_unit", opt.params.grid_cells_per_unit()},
                     {"cells_per_strut", opt.params.grid_cells_per_strut()},
                     {"pore_contact", to_string(resolved_pore_contact(opt.params))}};
    std::cout << scene.dump() << '\n';
    return 0;
  }

  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);

  const SceneParams& p = opt.params;
  auto mode = opt.progress;
  if (mode == cli::ProgressMode::automatic) {
    mode = isatty(STDERR_FILENO) ? cli::ProgressMode::bar : cli::ProgressMode::log;
  }
  if (mode == cli::ProgressMode::json) log->set_level(spdlog::level::warn);

  log->info("scene S={} R={} phi={} geometry={} preset={}{} cells_per_unit={} cells_per_strut={:.3g} "
            "pore_contact={} eps_end={} out={}", p.S, p.R, p.phi, to_string(p.geometry),
            opt.preset, opt.overridden.empty() ? "" : " overridden=" + opt.overridden.dump(),
            p.grid_cells_per_unit(), p.grid_cells_per_strut(),
            to_string(resolved_pore_contact(p)), p.eps_final(), opt.out_dir);

  RunControl control;
  control.cancel = &g_cancel;
  control.checkpoint_file = opt.checkpoint_file;
  control.checkpoint_every = opt.checkpoint_every;
  control.resume_file = opt.resume_file;
  // A checkpoint written or resumed, as a JSON line or a log line.
  auto report_checkpoint = [&](const char* event, const CheckpointInfo& c) {
    if (mode == cli::ProgressMode::json) {
      print_json_line({{"event", event},
                       {"file", std::string(event) == "checkpoint" ? opt.checkpoint_file
                                                                   : opt.resume_file},
                       {"step", c.step},
                       {"eps", c.eps},
                       {"bytes", c.bytes},
                       {"write_seconds", c.write_seconds}});
    } else {
      log->info("{} step={} eps={:.5f} bytes={} write={:.3f}s", event, c.step, c.eps, c.bytes,
                c.write_seconds);
    }
  };
  control.on_checkpoint = [&](const CheckpointInfo& c) { report_checkpoint("checkpoint", c); };
  control.on_resume = [&](const CheckpointInfo& c) {
    if (c.threads != p.threads) {
      log->warn("resuming a checkpoint of {} thread(s) with {}: the result differs in round-off "
                "from an uninterrupted run", c.threads, p.threads);
    }
    report_checkpoint("resumed", c);
  };
  double next_log = 0.1;
  control.on_progress = [&](const Progress& pr) {
    switch (mode) {
      case cli::ProgressMode::json:
        print_json_line({{"event", "progress"},
                         {"eps", pr.eps},
                         {"eps_end", pr.eps_end},
                         {"steps", pr.steps},
                         {"wall_seconds", pr.wall_seconds}});
        break;
      case cli::ProgressMode::bar:
        draw_bar(pr);
        break;
      case cli::ProgressMode::log:
        if (pr.eps >= next_log * pr.eps_end - 1e-12) {
          log->info("progress eps={:.4f}/{:.4f} steps={} wall={:.1f}s", pr.eps, pr.eps_end,
                    pr.steps, pr.wall_seconds);
          while (next_log * pr.eps_end <= pr.eps + 1e-12) next_log += 0.1;
        }
        break;
      default:
        break;
    }
  };
  // The movie is written into the bundle as the run goes; a stale one of an earlier run into
  // the same folder is removed, so that only a summary's own movie sits beside it.
  const std::filesystem::path movie_file = std::filesystem::path(opt.out_dir) / movie::kFileName;
  std::error_code fs_error;
  std::filesystem::remove(movie_file, fs_error);
  if (p.movie_d_eps > 0.0) {
    std::filesystem::create_directories(opt.out_dir, fs_error);
    control.movie_file = movie_file.string();
  }
  if (mode == cli::ProgressMode::json) {
    print_json_line({{"event", "start"}, {"eps_end", p.eps_final()}});
  }

  try {
    const RunResult r = run_scene(p, control);
    if (mode == cli::ProgressMode::bar) std::fputc('\n', stderr);
    const nlohmann::json classification = classification_of(p, r);
    write_bundle(opt.out_dir, p, r,
                 {{"classification", classification},
                  {"numerics", {{"preset", opt.preset}, {"overridden", opt.overridden}}}});
    log->info("done status={} steps={} particles={} wall={:.2f}s ns/particle-step={:.1f}{}{}",
              to_string(r.status), r.steps, r.n_particles, r.wall_seconds,
              r.ns_per_particle_step, r.reason.empty() ? "" : " reason=", r.reason);
    if (mode == cli::ProgressMode::json) {
      print_json_line({{"event", "done"},
                       {"status", to_string(r.status)},
                       {"reason", r.reason},
                       {"classification", classification},
                       {"out", opt.out_dir}});
    } else {
      std::cout << verdict_line(r, classification, opt.out_dir) << '\n' << std::flush;
    }
    return r.status == RunStatus::cancelled ? 3 : 0;
  } catch (const CheckpointRefused& e) {
    std::cerr << "compaction-run: --resume: " << e.what() << '\n';
    return 4;
  } catch (const std::exception& e) {
    std::cerr << "compaction-run: " << e.what() << '\n';
    return 1;
  }
}
