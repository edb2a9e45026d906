// compaction-classify RESULT_DIR: labels a run's compaction pattern and prints the label and
// its features as JSON (docs/classifier.md). With --features it decides again from a run's stored
// features (a summary.json, a classification, or the features alone), without the bundle.
#include <cmath>
#include <fstream>
#include <iostream>
#include <stdexcept>
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
    "--features FILE decides from stored features: FILE (- for stdin) holds a summary.json,\n"
    "  a classification (an export's result, GET /jobs/ID's result.summary.classification) or the\n"
    "  features object; the fronts are not stored, so --fronts needs a bundle\n"
    "exit status: 0 classified (also \"unclassified\"), 1 unreadable bundle or features, 2 bad usage\n";

// The features object inside what --features reads: a summary, a classification or the features.
const nlohmann::json& features_in(const nlohmann::json& doc) {
  if (!doc.is_object()) throw std::invalid_argument("the features file must hold a JSON object");
  if (const auto c = doc.find("classification"); c != doc.end()) {
    if (c->is_null()) throw std::invalid_argument("classification is null: the run did not finish ok");
    if (!c->is_object()) throw std::invalid_argument("classification: must be an object");
    return features_in(*c);
  }
  if (const auto f = doc.find("features"); f != doc.end()) return *f;
  return doc;
}

nlohmann::json read_json_file(const std::string& path) {
  if (path == "-") return nlohmann::json::parse(std::cin);
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  return nlohmann::json::parse(in);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace compaction;
  std::string dir, features_file;
  bool fronts = false, compact = false;
  cli::CommandLine cl("compaction-classify", kAbout,
                      "[--fronts] [--compact] RESULT_DIR | --features FILE [--compact]");
  cl.positional("RESULT_DIR", dir,
                "a bundle written by compaction-run (summary.json, frames.csv, spacetime.npy)",
                /*required=*/false);
  cl.text("--features", features_file, "FILE",
          "decide from a run's stored features instead of a bundle (see below)", {},
          /*non_empty=*/true);
  cl.flag("--fronts", fronts, "also print every propagating front (origin, start, end, both speed readings, turns,\n"
          "the timing the two-sided rule reads, the leading-edge points the speeds use) and the unit\n"
          "cell in h0");
  cl.flag("--compact", compact, "one line of JSON instead of indented");
  cl.notes(kNotes);
  if (const auto code = cl.parse(argc, argv)) return *code;
  if (dir.empty() == features_file.empty() || (fronts && !features_file.empty())) {
    std::cerr << "compaction-classify: give either RESULT_DIR or --features FILE"
              << (fronts && !features_file.empty() ? " (--fronts needs RESULT_DIR)" : "")
              << "; --help shows the usage\n";
    return 2;
  }
  if (!features_file.empty()) {
    try {
      const classify::Features F = classify::features_from_json(features_in(read_json_file(features_file)));
      const nlohmann::json out = classify::to_json(classify::decide(F));
      std::cout << (compact ? out.dump() : out.dump(2)) << '\n';
      return 0;
    } catch (const std::exception& e) {
      std::cerr << "compaction-classify: " << features_file << ": " << e.what() << '\n';
      return 1;
    }
  }
  try {
    const Bundle b = read_bundle(dir);
    const classify::Settings settings;  // the classifier's own numbers (settings.hpp)
    const classify::Classification c = classify::classify(b.params, b.result, settings);
    nlohmann::json out = classify::to_json(c);
    out["status"] = to_string(b.result.status);
    if (fronts) {
      nlohmann::json list = nlohmann::json::array();
      const classify::Front* primary = classify::primary_front(c.tracks);
      const auto number = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
      for (const auto& fr : c.tracks.fronts) {
        if (!fr.propagating) continue;
        nlohmann::json turns = nlohmann::json::array();
        for (const auto& t : fr.turns) turns.push_back({{"eps", t.eps}, {"at", classify::to_string(t.where)}});
        const classify::FrontTiming timing = classify::front_timing(c.tracks, fr, settings.features);
        list.push_back({{"origin", classify::to_string(fr.origin)},
                        {"start_eps", fr.start_eps()},
                        {"end_eps", fr.end_eps()},
                        {"at_onset", timing.at_onset},
                        {"first_leg_end_eps", timing.first_leg_end_eps},
                        {"passes_middle_eps", timing.passes_middle_eps},
                        {"start_height", fr.path.front().centroid},
                        {"end_height", fr.path.back().centroid},
                        {"primary", &fr == primary},
                        {"speed_over_V", number(fr.speed)},
                        {"speed_error", number(fr.speed_error)},
                        {"transit_speed_over_V", number(fr.transit_speed)},
                        {"transit_error", number(fr.transit_error)},
                        {"leg_edge", fr.leg_edge},
                        {"n_reflections", fr.n_reflections},
                        {"turns", turns},
                        {"share_of_activity", c.tracks.total_mass > 0 ? fr.mass() / c.tracks.total_mass : 0.0}});
      }
      out["fronts"] = list;
      const classify::MapAxes axes = classify::map_axes(b.params, b.result);
      out["unit_cell_h0"] = axes.unit_cell / axes.h0;
    }
    std::cout << (compact ? out.dump() : out.dump(2)) << '\n';
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "compaction-classify: " << e.what() << '\n';
    return 1;
  }
}
