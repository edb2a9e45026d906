// compaction-classify RESULT_DIR: labels a run's compaction pattern and prints the label and
// its features as JSON (docs/classifier.md).
#include <cmath>
#include <iostream>
#include <string>

#include "compaction/bundle.hpp"
#include "compaction/classify.hpp"

namespace {

const char* kHelp =
    "compaction-classify: label the compaction pattern (a)-(f) of a result bundle\n"
    "(Blatny et al., PRL 128, 228002, 2022) from what the run produced: the space-time map,\n"
    "the plate stresses and the strut diagnostics. S and R are never read.\n"
    "\n"
    "usage: compaction-classify [--fronts] [--compact] RESULT_DIR\n"
    "\n"
    "  RESULT_DIR   a bundle written by compaction-run (summary.json, frames.csv, spacetime.npy)\n"
    "  --fronts     also print every propagating front (origin, start, end, speed, turns)\n"
    "  --compact    one line of JSON instead of indented\n"
    "  -h, --help   this text\n"
    "\n"
    "output: {\"class\": \"a\"..\"f\" | \"unclassified\", \"confidence\", \"runner_up\",\n"
    "         \"n_reflections\", \"band_speed_ratio\", \"features\": {...}}\n"
    "exit status: 0 classified (also \"unclassified\"), 1 unreadable bundle, 2 bad usage\n";

}  // namespace

int main(int argc, char** argv) {
  using namespace compaction;
  std::string dir;
  bool fronts = false, compact = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") { std::cout << kHelp; return 0; }
    if (a == "--fronts") { fronts = true; continue; }
    if (a == "--compact") { compact = true; continue; }
    if (!a.empty() && a[0] == '-') {
      std::cerr << "error: unknown option " << a << "\nsee compaction-classify --help\n";
      return 2;
    }
    if (!dir.empty()) {
      std::cerr << "error: one RESULT_DIR expected, got " << dir << " and " << a
                << "\nsee compaction-classify --help\n";
      return 2;
    }
    dir = a;
  }
  if (dir.empty()) {
    std::cerr << "error: RESULT_DIR missing\nsee compaction-classify --help\n";
    return 2;
  }
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
    std::cerr << "error: " << e.what() << '\n';
    return 1;
  }
}
