// Checking a worker's upload against its job: the engine's own summary.json is accepted, with
// the classification when present; mismatched parameters, versions, statuses and file names
// are refused naming the field.
#include "exchange/result_intake.hpp"

#include <gtest/gtest.h>

#include "bundle_files.hpp"
#include "compaction/bundle.hpp"
#include "input/api_error.hpp"
#include "plan/planner.hpp"

using namespace compaction::server;
using nlohmann::json;

namespace {

compaction::SceneParams scene() {
  compaction::SceneParams p;
  p.S = 0.05;
  p.R = 1e-3;
  p.cells_per_unit = 6;
  p.eps_end = 0.02;
  return p;
}

// A summary as the engine writes it.
json engine_summary(compaction::RunStatus status = compaction::RunStatus::ok) {
  compaction::RunResult r;
  r.status = status;
  if (status == compaction::RunStatus::unstable) r.reason = "kinetic energy grew 1e6-fold";
  r.eps_reached = 0.02;
  compaction::SceneParams p = scene();
  p.threads = 2;  // the worker's choice: not part of the identity
  return compaction::summary_json(p, r);
}

std::string field_of(const std::string& summary, std::vector<UploadedFile> files = {}) {
  try {
    intake_result(summary, canonical_scene(scene()), compaction::engine_version(), std::move(files));
  } catch (const ApiError& e) {
    EXPECT_EQ(e.status, 422);
    return e.field;
  }
  return "accepted";
}

}  // namespace

TEST(ResultIntake, TheEnginesSummaryIsAccepted) {
  const ResultRecord r =
      intake_result(engine_summary().dump(), canonical_scene(scene()), compaction::engine_version(),
                    {{"frames.csv", test_files::frames_csv()},
                     {"spacetime.npy", test_files::npy(3, 4)},
                     {"snapshot_0.200.png", test_files::png()}});
  EXPECT_EQ(r.status, "ok");
  EXPECT_EQ(r.engine_version, compaction::engine_version());
  EXPECT_EQ(r.source_revision, compaction::source_revision());
  EXPECT_EQ(r.scene, canonical_scene(scene()));
  EXPECT_FALSE(r.cls) << "no classification in this summary: stored as null";
  ASSERT_EQ(r.artifacts.size(), 3u);
  EXPECT_EQ(r.artifacts[2].content_type, "image/png");
}

TEST(ResultIntake, AnUnstableRunIsAResultWithItsReason) {
  const ResultRecord r =
      intake_result(engine_summary(compaction::RunStatus::unstable).dump(),
                    canonical_scene(scene()), compaction::engine_version(), {});
  EXPECT_EQ(r.status, "unstable");
  EXPECT_EQ(r.reason, "kinetic energy grew 1e6-fold");
}

TEST(ResultIntake, TheClassificationIsStoredWhenPresent) {
  json s = engine_summary();
  s["classification"] = {{"class", "b"},         {"confidence", 0.8},
                         {"runner_up", "a"},     {"n_reflections", 2},
                         {"band_speed_ratio", 2.1}, {"features", {{"n_fronts", 1}}}};
  const ResultRecord r =
      intake_result(s.dump(), canonical_scene(scene()), compaction::engine_version(), {});
  EXPECT_EQ(r.cls, "b");
  EXPECT_EQ(r.confidence, 0.8);
  EXPECT_EQ(r.runner_up, "a");
  EXPECT_EQ(r.n_reflections, 2);
  EXPECT_EQ(r.band_speed_ratio, 2.1);
  EXPECT_EQ(json::parse(*r.features)["n_fronts"], 1);
}

TEST(ResultIntake, BadUploadsNameTheField) {
  EXPECT_EQ(field_of("not json"), "summary");
  EXPECT_EQ(field_of(engine_summary(compaction::RunStatus::cancelled).dump()), "summary.status");
  json s = engine_summary();
  s["params"]["phi"] = 0.5;
  EXPECT_EQ(field_of(s.dump()), "summary.params");
  s = engine_summary();
  s["params"]["phi"] = "x";
  EXPECT_EQ(field_of(s.dump()), "summary.params.phi");
  s = engine_summary();
  s["engine_version"] = "9.9.9";
  EXPECT_EQ(field_of(s.dump()), "summary.engine_version");
  s = engine_summary();
  s.erase("source_revision");
  EXPECT_EQ(field_of(s.dump()), "summary.source_revision");
  s = engine_summary();
  s["classification"] = {{"class", "z"}};
  EXPECT_EQ(field_of(s.dump()), "summary.classification.class");
  s["classification"] = {{"class", "a"}, {"confidence", 1.5}};
  EXPECT_EQ(field_of(s.dump()), "summary.classification.confidence");
  EXPECT_EQ(field_of(engine_summary().dump(), {{"../etc/passwd", "x"}}), "files[../etc/passwd]");
  EXPECT_EQ(field_of(engine_summary().dump(), {{"run.sh", "x"}}), "files[run.sh]");
  EXPECT_EQ(field_of(engine_summary().dump(), {{"a.csv", test_files::frames_csv()},
                                              {"a.csv", test_files::frames_csv()}}),
            "files[a.csv]");
}

TEST(ResultIntake, EveryFieldOfTheSummaryIsCheckedAgainstTheSchema) {
  // A status that is not a string: a 422 naming it (it was a 500).
  for (const json& status : {json::object(), json(nullptr), json(5), json::array(), json(true)}) {
    json s = engine_summary();
    s["status"] = status;
    EXPECT_EQ(field_of(s.dump()), "summary.status") << status;
  }
  json s = engine_summary();
  s["classification"] = {{"class", "a"}, {"runner_up", "rumour"}};
  EXPECT_EQ(field_of(s.dump()), "summary.classification.runner_up");
  s = engine_summary();
  s["eps_reached"] = 1.8e19;
  EXPECT_EQ(field_of(s.dump()), "summary.eps_reached");
  s = engine_summary();
  s["classification"] = {{"class", "a"}, {"features", {{"n_fronts", "many"}}}};
  EXPECT_EQ(field_of(s.dump()), "summary.classification.features.n_fronts");
  s["classification"] = {{"class", "a"}, {"features", {{"coherence", 7}}}};
  EXPECT_EQ(field_of(s.dump()), "summary.classification.features.coherence");
  s["classification"] = {{"class", "a"}, {"features", {{"a_new_feature", {{"deep", 1}}}}}};
  EXPECT_EQ(field_of(s.dump()), "summary.classification.features.a_new_feature");
  s = engine_summary();
  s["unknown_key"] = 1;
  EXPECT_EQ(field_of(s.dump()), "summary");
  s = engine_summary();
  s["wall_seconds"] = -1;
  EXPECT_EQ(field_of(s.dump()), "summary.wall_seconds");
}

TEST(ResultIntake, EveryFileIsParsedBeforeItIsStored) {
  const std::string summary = engine_summary().dump();
  // An .npy whose header claims 2^70 elements, or more or fewer bytes than its shape.
  std::string huge = test_files::npy(1, 1);
  huge.replace(huge.find("(1, 1)"), 6, "(1099511627776, 1073741824)");
  EXPECT_EQ(field_of(summary, {{"spacetime.npy", huge}}), "files[spacetime.npy]");
  EXPECT_EQ(field_of(summary, {{"spacetime.npy", test_files::npy(3, 4) + "x"}}), "files[spacetime.npy]");
  EXPECT_EQ(field_of(summary, {{"spacetime.npy", test_files::npy(3, 4).substr(0, 100)}}),
            "files[spacetime.npy]");
  // A CSV with a NUL byte, a ragged row, a field that is not a number.
  EXPECT_EQ(field_of(summary, {{"frames.csv", std::string("eps,s\n0.1,\0\n", 12)}}), "files[frames.csv]");
  EXPECT_EQ(field_of(summary, {{"frames.csv", "eps,s\n0.1\n"}}), "files[frames.csv]");
  EXPECT_EQ(field_of(summary, {{"frames.csv", "eps,s\n0.1,=HYPERLINK(1)\n"}}), "files[frames.csv]");
  // A PNG that is not one, a movie shorter than its frames.
  EXPECT_EQ(field_of(summary, {{"spacetime.png", "png bytes"}}), "files[spacetime.png]");
  EXPECT_EQ(field_of(summary, {{"movie.bin", test_files::movie(10, 2).substr(0, 120)}}), "files[movie.bin]");
  // The bundle's summary.json as a file is the summary field, or the upload is refused.
  EXPECT_EQ(field_of(summary, {{"summary.json", summary}}), "accepted");
  json other = engine_summary();
  other["wall_seconds"] = 99;
  EXPECT_EQ(field_of(summary, {{"summary.json", other.dump()}}), "files[summary.json]");
}

TEST(ResultIntake, TheMovieIsAnArtifactOfItsOwnType) {
  const ResultRecord r = intake_result(engine_summary().dump(), canonical_scene(scene()),
                                       compaction::engine_version(),
                                       {{"movie.bin", test_files::movie(10, 2)}});
  ASSERT_EQ(r.artifacts.size(), 1u);
  EXPECT_EQ(r.artifacts[0].content_type, "application/octet-stream");
  EXPECT_EQ(field_of(engine_summary().dump(), {{"movie.exe", "x"}}), "files[movie.exe]");
}

TEST(ResultIntake, AJobQueuedBeforeTheMovieKeyStandsForTheDefaultMovie) {
  // A scene stored before movie_d_eps existed: the same run as one with its default.
  json old_scene = json::parse(canonical_scene(scene()));
  old_scene.erase("movie_d_eps");
  const ResultRecord r = intake_result(engine_summary().dump(), old_scene.dump(),
                                       compaction::engine_version(), {});
  EXPECT_EQ(r.scene, old_scene.dump()) << "the job keeps its stored scene";
  // A run with another movie interval is another run.
  json s = engine_summary();
  s["params"]["movie_d_eps"] = 0.05;
  EXPECT_THROW(intake_result(s.dump(), old_scene.dump(), compaction::engine_version(), {}), ApiError);
}
