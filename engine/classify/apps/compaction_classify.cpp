// compaction-classify RESULT_DIR: labels a run's compaction pattern and prints the label and
// its features as JSON (docs/classifier.md).
#include <cmath>
#include <iostream>
#include <string>

#include "command_line.hpp"
#include "compaction/bundle.hpp"
#include "compaction/classify.hpp"

namespace {

const char* kAbout =
    "label the compaction pattern (a)-(f) of a result bundle\n"
    "(Blatny et al., PRL 128, 228002, 2022) from what the run produced: the space-time map,\n"
    "the plate stresses and the strut diagnostics. S and R are never read.";

const char* kNotes =
    "output: {\"class\": \"a\"..\"f\" | \"unclassified\", \"confidence\", \"runner_up\",\n"
    "         \"n_reflections\", \"band_speed_ratio\", \"features\": {...}}\n"
    "exit status: 0 classified (also \"unclassified\"), 1 unreadable bundle, 2 bad usage\n";

}  // namespace

int main(int argc, char** argv) {
  using namespace compaction;
  std::string dir;
  bool fronts = false, compact = false;
  cli::CommandLine cl("compaction-classify", kAbout, "[--fronts] [--compact] RESULT_DIR");
  cl.positional("RESULT_DIR", dir,
                "a bundle written by compaction-run (summary.json, frames.csv, spacetime.npy)");
  cl.flag("--fronts", fronts, "also print every propagating front (origin, start, end, speed, turns)");
  cl.flag("--compact", compact, "one line of JSON instead of indented");
  cl.notes(kNotes);
  if (const auto code = cl.parse(argc, argv)) return *code;
  try {
    const Bundle b = read_bundle(dir);
    const classify::Classification c = classify::classify(b.params, b.result);
    nlohmann::json out = classify::to_json(c);
    out["status"] = to_string(b.result.status);
    if (fronts) {
      nlohmann::json list = nlohmann::json::array();
      for (const auto& fr : c.tracks.fronts) {
        if (!fr.propagating) continue;
        nlohmann::json turns = nlohmann::json::array();
        for (const auto& t : fr.turns) turns.push_back({{"eps", t.eps}, {"at", classify::to_string(t.where)}});
        list.push_back({{"origin", classify::to_string(fr.origin)},
                        {"start_eps", fr.start_eps()},
                        {"end_eps", fr.end_eps()},
                        {"start_height", fr.path.front().centroid},
                        {"end_height", fr.path.back().centroid},
                        {"speed_over_V", std::isfinite(fr.speed) ? nlohmann::json(fr.speed) : nlohmann::json()},
                        {"n_reflections", fr.n_reflections},
                        {"turns", turns},
                        {"share_of_activity", c.tracks.total_mass > 0 ? fr.mass() / c.tracks.total_mass : 0.0}});
      }
      out["fronts"] = list;
    }
    std::cout << (compact ? out.dump() : out.dump(2)) << '\n';
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "compaction-classify: " << e.what() << '\n';
    return 1;
  }
}
