// compaction-classify RESULT_DIR: labels a run's compaction pattern and prints the label and
// its features as JSON (docs/classifier.md). Given the bundles of a point's replicates, it reads
// them together as the map does (compaction/point_vote.hpp). With --features it decides again
// from a run's stored features (a summary.json, a classification, or the features alone),
// without the bundle.
#include <cmath>
#include <fstream>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "compaction/bundle.hpp"
#include "compaction/classify.hpp"
#include "compaction/point_vote.hpp"

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
    "two or more RESULT_DIRs: the replicates of one point (scenes equal but for their seed),\n"
    "  read together as the phase map reads a point (docs/replicates.md):\n"
    "  {\"point\": {\"runs\", \"labelled\", \"class\", \"share\", \"robust\", \"probabilities\",\n"
    "   \"confidence\", \"runner_up\", \"band_speed_ratio\": {\"mean\", \"sd\", \"n\"}, ...},\n"
    "   \"runs\": [{\"dir\", \"seed\", \"status\", \"class\", ...}]}\n"
    "exit status: 0 classified (also \"unclassified\"), 1 unreadable bundle or features, or\n"
    "  bundles of different points, 2 bad usage\n";

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

// Every propagating front of a classification (--fronts).
nlohmann::json fronts_of(const compaction::classify::Classification& c,
                         const compaction::classify::Settings& settings) {
  using namespace compaction;
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
  return list;
}

// One bundle's classification as compaction-classify prints it (with --fronts: its fronts and
// the unit cell in h0).
nlohmann::json classify_bundle(const compaction::Bundle& b, bool fronts) {
  using namespace compaction;
  const classify::Settings settings;  // the classifier's own numbers (settings.hpp)
  const classify::Classification c = classify::classify(b.params, b.result, settings);
  nlohmann::json out = classify::to_json(c);
  out["status"] = to_string(b.result.status);
  if (fronts) {
    out["fronts"] = fronts_of(c, settings);
    const classify::MapAxes axes = classify::map_axes(b.params, b.result);
    out["unit_cell_h0"] = axes.unit_cell / axes.h0;
  }
  return out;
}

int classify_features(const std::string& features_file, bool compact) {
  using namespace compaction;
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

// A classification's vote: its label unless unclassified.
compaction::Vote vote_of(const nlohmann::json& c) {
  if (c["class"] == "unclassified") return {};
  return {c["class"].get<std::string>(), c["confidence"].get<double>(),
          c["runner_up"].get<std::string>()};
}

// A reading of a run's classification: band_speed_ratio and n_reflections at its top, the
// other band speeds among its features; none when null or missing.
std::optional<double> reading_of(const nlohmann::json& c, const std::string& key) {
  const nlohmann::json* v = c.contains(key) ? &c[key] : nullptr;
  if (!v && c.contains("features") && c["features"].contains(key)) v = &c["features"][key];
  if (!v || !v->is_number()) return std::nullopt;
  return v->get<double>();
}

nlohmann::json spread_json(const std::optional<compaction::Spread>& s) {
  if (!s) return nullptr;
  return {{"mean", s->mean}, {"sd", s->sd ? nlohmann::json(*s->sd) : nlohmann::json()}, {"n", s->n}};
}

// The bundles of one point's replicates read together: each classified, their votes counted
// (point_vote.hpp), each reading's spread over the runs that carry the majority's label, as the
// map's points (docs/replicates.md). Bundles of different points (another key than the seed, or
// another engine) are an error.
nlohmann::json classify_point(const std::vector<std::string>& dirs) {
  using namespace compaction;
  std::vector<Bundle> bundles;
  for (const std::string& dir : dirs) bundles.push_back(read_bundle(dir));
  for (std::size_t i = 1; i < bundles.size(); ++i) {
    const std::string tail = " than " + dirs[0] + ": not a replicate of the same point";
    if (const auto key = differs_beyond_seed(bundles[0].params, bundles[i].params)) {
      throw std::runtime_error(dirs[i] + " has another " + *key + tail);
    }
    if (bundles[i].summary.value("engine_version", "") != bundles[0].summary.value("engine_version", "")) {
      throw std::runtime_error(dirs[i] + " was run by another engine version" + tail);
    }
  }
  nlohmann::json runs = nlohmann::json::array();
  std::vector<Vote> votes;
  for (std::size_t i = 0; i < bundles.size(); ++i) {
    nlohmann::json c = classify_bundle(bundles[i], false);
    votes.push_back(vote_of(c));
    c["dir"] = dirs[i];
    c["seed"] = bundles[i].params.seed;
    runs.push_back(std::move(c));
  }
  const PointVote v = vote(votes, votes.size());
  nlohmann::json point = {{"runs", v.runs},
                          {"labelled", v.labelled},
                          {"class", v.label ? nlohmann::json(*v.label) : nlohmann::json("unclassified")},
                          {"share", v.share},
                          {"robust", v.robust},
                          {"probabilities", nlohmann::json::object()},
                          {"confidence", v.confidence},
                          {"runner_up", v.runner_up ? nlohmann::json(*v.runner_up) : nlohmann::json()}};
  for (const auto& [label, p] : v.probabilities) point["probabilities"][label] = p;
  for (const char* key : {"band_speed_ratio", "band_speed_early", "band_speed_lead", "band_speed_transit",
                          "n_reflections"}) {
    std::vector<double> values;
    for (std::size_t i = 0; i < votes.size(); ++i) {
      if (!v.label || votes[i].label != v.label) continue;
      if (const auto x = reading_of(runs[i], key)) values.push_back(*x);
    }
    point[key] = spread_json(spread(values));
  }
  return {{"point", point}, {"runs", runs}};
}

}  // namespace

int main(int argc, char** argv) {
  using namespace compaction;
  std::vector<std::string> dirs;
  std::string features_file;
  bool fronts = false, compact = false;
  cli::CommandLine cl("compaction-classify", kAbout,
                      "[--fronts] [--compact] RESULT_DIR | [--compact] RESULT_DIR RESULT_DIR... |\n"
                      "       --features FILE [--compact]");
  cl.positionals("RESULT_DIR", dirs,
                 "a bundle written by compaction-run (summary.json, frames.csv, spacetime.npy);\n"
                 "several: the replicates of one point, read together (see below)",
                 /*required=*/false);
  cl.text("--features", features_file, "FILE",
          "decide from a run's stored features instead of a bundle (see below)", {},
          /*non_empty=*/true);
  cl.flag("--fronts", fronts, "also print every propagating front (origin, start, end, both speed readings, turns,\n"
          "the timing the two-sided rule reads, the leading-edge points the speeds use) and the unit\n"
          "cell in h0 (one RESULT_DIR)");
  cl.flag("--compact", compact, "one line of JSON instead of indented");
  cl.notes(kNotes);
  if (const auto code = cl.parse(argc, argv)) return *code;
  if (dirs.empty() == features_file.empty()) {
    std::cerr << "compaction-classify: give either RESULT_DIR or --features FILE; --help shows the usage\n";
    return 2;
  }
  if (fronts && dirs.size() != 1) {
    std::cerr << "compaction-classify: --fronts needs one RESULT_DIR; --help shows the usage\n";
    return 2;
  }
  if (!features_file.empty()) return classify_features(features_file, compact);
  try {
    const nlohmann::json out = dirs.size() == 1 ? classify_bundle(read_bundle(dirs[0]), fronts)
                                                : classify_point(dirs);
    std::cout << (compact ? out.dump() : out.dump(2)) << '\n';
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "compaction-classify: " << e.what() << '\n';
    return 1;
  }
}
