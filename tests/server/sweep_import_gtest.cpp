// Exports and imports of sweeps (export_format.hpp, import_store.hpp) between real SQLite stores:
// the runs, results, artifacts and provenance arrive; a second import of the same file changes
// nothing; identical runs are recognised, a conflicting result is kept beside the stored one,
// a queued job takes the imported result; a malformed, truncated or edited file is refused
// naming its field and imports nothing; human labels travel with the runs.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <set>

#include "bundle_files.hpp"
#include "compaction/bundle.hpp"
#include "compaction/params_json.hpp"
#include "compaction/result.hpp"
#include "exchange/base64.hpp"
#include "exchange/export_format.hpp"
#include "exchange/import_command.hpp"
#include "exchange/result_intake.hpp"
#include "input/api_error.hpp"
#include "plan/planner.hpp"
#include "store/store.hpp"
#include "temp_dir.hpp"
#include "views/views.hpp"

using namespace compaction::server;
using nlohmann::json;

namespace {

constexpr Millis t0 = 1'700'000'000'000;

StoreConfig config() {
  StoreConfig c;
  c.engine_version = compaction::engine_version();
  return c;
}

json sweep_body(const std::string& name) {
  return {{"name", name},
          {"points", {{{"S", 0.05}, {"R", 1e-3}, {"phi", 0.4}}, {{"S", 0.02}, {"R", 1e-2}, {"phi", 0.4}}}},
          {"numerics", {{"cells_per_unit", 6}, {"eps_end", 0.02}}}};
}

std::int64_t create(Store& s, const std::string& name) {
  return s.sweeps.create(sweep_rows(plan_sweep(sweep_body(name)), compaction::engine_version()), t0).id;
}

// Leases every queued job and completes it with the engine's summary of its scene, labelled
// `cls`, through the checks of a worker's upload.
void run_all(Store& s, const std::string& cls, const std::string& worker = "w1") {
  while (const auto l = s.queue.lease(worker, compaction::engine_version(), t0 + 10)) {
    compaction::SceneParams p;
    ASSERT_TRUE(compaction::from_json(json::parse(l->scene), p).empty());
    compaction::RunResult run;
    run.eps_reached = 0.02;
    json summary = compaction::summary_json(p, run);
    summary["classification"] = {{"class", cls}, {"confidence", 0.75}, {"runner_up", "c"},
                                 {"n_reflections", 1}, {"band_speed_ratio", 2.5},
                                 {"features", {{"band_speed_error", 0.1}}}};
    ResultRecord r = intake_result(summary.dump(), l->scene, compaction::engine_version(),
                                   {{"frames.csv", "eps,sigma_top\n0.01,1\n"},
                                    {"spacetime.npy", test_files::npy(2, 3)},
                                    {"snapshot_0.200.png", test_files::png()},
                                    {"snapshot_0.200.npy", test_files::npy(4, 5)}});
    ASSERT_EQ(s.queue.complete(l->job_id, l->token, r, t0 + 20), LeaseCheck::ok);
  }
}

std::string export_of(Store& s, std::int64_t sweep) {
  return *export_sweep(s, sweep, "127.0.0.1:8080", t0 + 30);
}

json map_of(Store& s) { return json::parse(views::phase_map(0.4, s.reads.phase_map(0.4, std::nullopt))); }

struct ImportTest : ::testing::Test {
  TempDir dir;
  Store a{dir.file("a.db"), config()};
  Store b{dir.file("b.db"), config()};
};

}  // namespace

TEST(Base64, RoundTripsEveryLengthAndRefusesNonCanonicalText) {
  std::string bytes;
  for (int n = 0; n < 70; ++n) {
    EXPECT_EQ(base64_decode(base64_encode(bytes)), bytes) << n;
    bytes += static_cast<char>(n * 37 + 11);
  }
  EXPECT_EQ(base64_encode("foobar"), "Zm9vYmFy");
  EXPECT_EQ(base64_encode("fo"), "Zm8=");
  EXPECT_FALSE(base64_decode("Zm8"));     // not a multiple of 4
  EXPECT_FALSE(base64_decode("Zm9=Zm8=")); // padding inside
  EXPECT_FALSE(base64_decode("Zm9*"));    // outside the alphabet
  EXPECT_FALSE(base64_decode("Zm9="));    // the dropped bits are not zero
}

TEST_F(ImportTest, AnImportBringsTheRunsWithTheirResultsArtifactsAndProvenance) {
  const std::int64_t sa = create(a, "part A");
  run_all(a, "b");
  const json file = json::parse(export_of(a, sa));
  EXPECT_EQ(file["format"], "compaction-sweep-export");
  EXPECT_EQ(file["version"], 1);
  ASSERT_EQ(file["runs"].size(), 2u);
  EXPECT_EQ(file["runs"][0]["artifacts_left_out"], json::array({"snapshot_0.200.npy"}));

  const ImportOutcome o = b.imports.merge(read_export(file.dump()), t0 + 40);
  EXPECT_TRUE(o.sweep_created);
  EXPECT_EQ(o.added, 2);
  EXPECT_EQ(o.linked, 2);
  const json map = map_of(b);
  ASSERT_EQ(map["points"].size(), 2u);
  for (const json& p : map["points"]) {
    EXPECT_EQ(p["class"], "b");
    EXPECT_EQ(p["state"], "succeeded");
    EXPECT_EQ(p["band_speed_error"], 0.1);
  }
  const auto sweep = b.reads.sweep(o.sweep_id);
  ASSERT_TRUE(sweep);
  const json sv = views::sweep(*sweep);
  EXPECT_EQ(sv["imported"]["database"], a.imports.database_id());
  EXPECT_EQ(sv["imported"]["sweep"], sa);
  EXPECT_EQ(sv["counts"]["succeeded"], 2);
  EXPECT_EQ(sv["name"], "part A");

  const std::int64_t job = map["points"][0]["job_id"];
  const json detail = views::job_detail(*b.reads.job(job));
  EXPECT_EQ(detail["result"]["origin"]["database"], a.imports.database_id());
  EXPECT_EQ(detail["result"]["worker"], "w1");
  EXPECT_EQ(detail["result"]["created_at"], t0 + 20) << "the computing server's time";
  EXPECT_EQ(detail["result"]["summary"]["classification"]["class"], "b");
  EXPECT_EQ(b.reads.artifact(job, "frames.csv")->data, "eps,sigma_top\n0.01,1\n");
  EXPECT_EQ(b.reads.artifact(job, "spacetime.npy")->data, test_files::npy(2, 3));
  EXPECT_TRUE(b.reads.artifact(job, "snapshot_0.200.png"));
  EXPECT_FALSE(b.reads.artifact(job, "snapshot_0.200.npy")) << "particle snapshots stay home";
  // Imported sweeps never plan (an adaptive request is a record of what was asked).
  EXPECT_TRUE(b.reads.live_adaptive_sweeps().empty());
}

TEST_F(ImportTest, AnExportWithoutArtifactsBringsTheMapAndNoFile) {
  const std::int64_t sa = create(a, "part A");
  run_all(a, "b");
  const std::string text = *export_sweep(a, sa, "127.0.0.1:8080", t0 + 30, ExportArtifacts::none);
  const json file = json::parse(text);
  ASSERT_EQ(file["runs"].size(), 2u);
  EXPECT_EQ(file["runs"][0]["artifacts"], json::array());
  EXPECT_EQ(file["runs"][0]["artifacts_left_out"].size(), 4u) << "every file named";
  EXPECT_LT(text.size(), export_of(a, sa).size());

  const ImportOutcome o = b.imports.merge(read_export(text), t0 + 40);
  EXPECT_EQ(o.added, 2);
  const json map = map_of(b);
  ASSERT_EQ(map["points"].size(), 2u);
  for (const json& p : map["points"]) EXPECT_EQ(p["class"], "b");
  const std::int64_t job = map["points"][0]["job_id"];
  EXPECT_FALSE(b.reads.artifact(job, "frames.csv"));
  EXPECT_EQ(views::job_detail(*b.reads.job(job))["result"]["summary"]["classification"]["class"],
            "b") << "the summary travels without the files";
}

TEST_F(ImportTest, ASecondImportOfTheSameFileChangesNothing) {
  const std::int64_t sa = create(a, "part A");
  run_all(a, "a");
  const std::string text = export_of(a, sa);
  b.imports.merge(read_export(text), t0 + 40);
  const std::string before = b.reads.fingerprint();
  const ImportOutcome again = b.imports.merge(read_export(text), t0 + 50);
  EXPECT_FALSE(again.changed());
  EXPECT_FALSE(again.sweep_created);
  EXPECT_EQ(again.identical, 2);
  EXPECT_EQ(b.reads.fingerprint(), before);
}

TEST_F(ImportTest, RunsComputedOnBothServersAreRecognisedAndNotDuplicated) {
  const std::int64_t sa = create(a, "part A");
  run_all(a, "d");
  create(b, "mine");
  run_all(b, "d", "w-b");
  const ImportOutcome o = b.imports.merge(read_export(export_of(a, sa)), t0 + 40);
  EXPECT_EQ(o.identical, 2);
  EXPECT_EQ(o.added, 0);
  EXPECT_EQ(o.conflicts, 0);
  EXPECT_EQ(o.linked, 2) << "the imported sweep holds the local jobs";
  EXPECT_EQ(map_of(b)["points"].size(), 2u);
  const std::int64_t job = map_of(b)["points"][0]["job_id"];
  EXPECT_EQ(views::job_detail(*b.reads.job(job))["result"]["worker"], "w-b") << "the stored result stays";
}

TEST_F(ImportTest, AConflictingResultIsKeptBesideTheStoredOneOnceWithItsProvenance) {
  const std::int64_t sa = create(a, "part A");
  run_all(a, "b");
  create(b, "mine");
  run_all(b, "c");
  const std::string text = export_of(a, sa);
  const ImportOutcome o = b.imports.merge(read_export(text), t0 + 40);
  EXPECT_EQ(o.conflicts, 2);
  const json map = map_of(b);
  for (const json& p : map["points"]) {
    EXPECT_EQ(p["class"], "c") << "the result stored first stays the job's";
    const auto c = b.imports.conflicts(p["job_id"]);
    ASSERT_EQ(c.size(), 1u);
    const json conflict = json::parse(c[0]);
    EXPECT_EQ(conflict["class"], "b");
    EXPECT_EQ(conflict["database"], a.imports.database_id());
  }
  const ImportOutcome again = b.imports.merge(read_export(text), t0 + 50);
  EXPECT_EQ(again.conflicts, 0);
  EXPECT_EQ(again.conflicts_known, 2);
  EXPECT_FALSE(again.changed());
}

TEST_F(ImportTest, AJobQueuedHereTakesTheImportedResult) {
  const std::int64_t sa = create(a, "part A");
  run_all(a, "e");
  const std::int64_t sb = create(b, "queued here");
  const ImportOutcome o = b.imports.merge(read_export(export_of(a, sa)), t0 + 40);
  EXPECT_EQ(o.filled, 2);
  EXPECT_EQ(views::sweep(*b.reads.sweep(sb))["counts"]["succeeded"], 2);
  EXPECT_FALSE(b.queue.lease("w", compaction::engine_version(), t0 + 50)) << "nothing left to run";
}

TEST_F(ImportTest, AnImportedSweepExportedAgainKeepsWhereItWasComputed) {
  const std::int64_t sa = create(a, "part A");
  run_all(a, "f");
  const ImportOutcome ob = b.imports.merge(read_export(export_of(a, sa)), t0 + 40);
  TempDir other;
  Store c{other.file("c.db"), config()};
  const std::string from_b = export_of(b, ob.sweep_id);
  const ImportOutcome oc = c.imports.merge(read_export(from_b), t0 + 60);
  EXPECT_EQ(oc.added, 2);
  const json sv = views::sweep(*c.reads.sweep(oc.sweep_id));
  EXPECT_EQ(sv["imported"]["database"], a.imports.database_id());
  EXPECT_EQ(sv["imported"]["source"]["database"], b.imports.database_id()) << "exported by b";
  // b's file and a's file name the same source sweep: importing a's file into c adds nothing.
  EXPECT_FALSE(c.imports.merge(read_export(export_of(a, sa)), t0 + 70).changed());
  // Into a itself: its own runs and sweep, nothing new.
  EXPECT_FALSE(a.imports.merge(read_export(from_b), t0 + 80).changed());
}

namespace {

// The field a refused file names, "" when it is accepted.
std::string refused_field(const std::string& text) {
  try {
    read_export(text);
  } catch (const ApiError& e) {
    EXPECT_EQ(e.status, 422);
    return e.field;
  }
  return "";
}

}  // namespace

TEST_F(ImportTest, AMalformedTruncatedOrEditedFileIsRefusedNamingItsFieldAndImportsNothing) {
  const std::int64_t sa = create(a, "part A");
  run_all(a, "a");
  const std::string text = export_of(a, sa);
  const json good = json::parse(text);
  const std::string before = b.reads.fingerprint();

  EXPECT_EQ(refused_field(text.substr(0, text.size() / 2)), "file") << "truncated";
  EXPECT_EQ(refused_field(text.substr(0, text.size() - 1)), "file") << "the last brace missing";
  EXPECT_EQ(refused_field("[]"), "file");
  auto edited = [&](auto change) {
    json f = good;
    change(f);
    return refused_field(f.dump());
  };
  EXPECT_EQ(edited([](json& f) { f["format"] = "csv"; }), "format");
  EXPECT_EQ(edited([](json& f) { f["version"] = 2; }), "version");
  EXPECT_EQ(edited([](json& f) { f["source"]["database"] = "xyz"; }), "source.database");
  EXPECT_EQ(edited([](json& f) { f["sweep"].erase("name"); }), "sweep.name");
  EXPECT_EQ(edited([](json& f) { f["runs"] = json::object(); }), "runs");
  EXPECT_EQ(edited([](json& f) { f["runs"][1]["result"]["class"] = "c"; }), "runs[1].result.class");
  EXPECT_EQ(edited([](json& f) { f["runs"][1]["scene"]["S"] = 0.07; }), "runs[1].summary.params");
  EXPECT_EQ(edited([](json& f) { f["runs"][1]["scene"]["S"] = -1; }), "runs[1].scene.S");
  EXPECT_EQ(edited([](json& f) { f["runs"][0]["engine_version"] = "9.9"; }), "runs[0].summary.engine_version");
  EXPECT_EQ(edited([](json& f) { f["runs"][1]["summary"]["status"] = "maybe"; }), "runs[1].summary.status");
  EXPECT_EQ(edited([](json& f) { f["runs"][1]["artifacts"][0]["data"] = "@@@@"; }), "runs[1].artifacts[0].data");
  EXPECT_EQ(edited([](json& f) { f["runs"][1]["artifacts"][0]["size"] = 3; }), "runs[1].artifacts[0].data");
  EXPECT_EQ(edited([](json& f) { f["runs"][1]["artifacts"][0]["name"] = "../x.csv"; }), "runs[1].artifacts[../x.csv]");
  EXPECT_EQ(edited([](json& f) { f["runs"][1] = f["runs"][0]; }), "runs[1].scene");
  EXPECT_EQ(edited([](json& f) { f["runs"][0]["human_label"] = {{"label", "z"}, {"reason", "r"}, {"by", "x"}, {"at", 1}}; }),
            "runs[0].human_label.label");
  EXPECT_EQ(refused_field(text), "");
  EXPECT_EQ(b.reads.fingerprint(), before) << "a refused file stores nothing";
}

TEST_F(ImportTest, HumanLabelsTravelWithTheRunsAndALabelSetHereStays) {
  const std::int64_t sa = create(a, "part A");
  run_all(a, "a");
  const std::int64_t job = map_of(a)["points"][0]["job_id"];
  ASSERT_EQ(a.labels.set(job, {"b", "two reflections in the space-time map", "ana", t0 + 25, "open", std::nullopt}),
            LabelOutcome::ok);
  const json file = json::parse(export_of(a, sa));
  int labelled = 0;
  for (const json& r : file["runs"]) labelled += r["human_label"].is_object();
  EXPECT_EQ(labelled, 1);

  const ImportOutcome o = b.imports.merge(read_export(file.dump()), t0 + 40, "submit:carla");
  EXPECT_EQ(o.labels, 1);
  std::int64_t total = 0;
  const auto audit = b.labels.audit(std::nullopt, 10, 0, total);
  ASSERT_EQ(total, 1);
  EXPECT_EQ(audit[0].action, "imported");
  // Who imported it and when, beside what the source claims (never a date of the source's as
  // the audit's own).
  EXPECT_EQ(audit[0].by, "submit:carla");
  EXPECT_EQ(audit[0].at, t0 + 40);
  EXPECT_EQ(audit[0].token, "submit:carla");
  EXPECT_EQ(audit[0].claimed_by, "ana");
  EXPECT_EQ(audit[0].claimed_at, t0 + 25);
  EXPECT_EQ(audit[0].classifier_label, "a");
  int human_b = 0;
  const json map = map_of(b);
  for (const json& p : map["points"]) {
    if (p["human_label"] != "b") continue;
    ++human_b;
    const auto labelled = b.reads.job(p["job_id"]);
    ASSERT_TRUE(labelled && labelled->job.human_label);
    EXPECT_EQ(labelled->job.human_label->by, "ana");
    EXPECT_EQ(labelled->job.human_label->imported_at, t0 + 40);
  }
  EXPECT_EQ(human_b, 1);
}

namespace {

// The folders below a store's artifact root.
std::set<std::string> artifact_folders(const std::string& db) {
  std::set<std::string> out;
  for (const auto& e : std::filesystem::directory_iterator(db + ".artifacts")) {
    out.insert(e.path().filename().string());
  }
  return out;
}

// Imports through the streaming path (the file read from a FILE*, as the server reads its
// spooled body), checkpoints of filled jobs removed.
ImportOutcome import_text(Store& s, const std::string& text, const std::string& importer, Millis now) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(
      fmemopen(const_cast<char*>(text.data()), text.size(), "rb"), &std::fclose);
  return import_export(s, f.get(), importer, now);
}

}  // namespace

TEST_F(ImportTest, TheStreamingReadMergesWhatTheWholeFileReadDoes) {
  const std::int64_t sa = create(a, "part A");
  run_all(a, "b");
  const ImportOutcome o = import_text(b, export_of(a, sa), "submit:carla", t0 + 40);
  EXPECT_EQ(o.runs, 2);
  EXPECT_EQ(o.added, 2);
  const json map = map_of(b);
  ASSERT_EQ(map["points"].size(), 2u);
  const auto job = b.reads.job(map["points"][0]["job_id"]);
  ASSERT_TRUE(job);
  EXPECT_EQ(b.reads.artifact(job->job.id, "spacetime.npy")->data, test_files::npy(2, 3));
  EXPECT_EQ(artifact_folders(dir.file("b.db")).size(), 2u) << "one folder a run";
}

TEST_F(ImportTest, AFailedImportLeavesNoFileAndNoRow) {
  const std::int64_t sa = create(a, "part A");
  run_all(a, "a");
  json file = json::parse(export_of(a, sa));
  file["runs"][1]["result"]["class"] = "c";  // the last run fails its check, after the first's files
  const auto folders = artifact_folders(dir.file("b.db"));
  const std::string before = b.reads.fingerprint();
  EXPECT_THROW(import_text(b, file.dump(), "open", t0 + 40), ApiError);
  EXPECT_EQ(artifact_folders(dir.file("b.db")), folders) << "the first run's files are gone";
  EXPECT_EQ(b.reads.fingerprint(), before);
}

TEST_F(ImportTest, AJobFilledByAnImportLosesItsCheckpoint) {
  const std::int64_t sa = create(a, "part A");
  run_all(a, "e");
  create(b, "queued here");
  const auto lease = b.queue.lease("w", compaction::engine_version(), t0 + 5);
  ASSERT_TRUE(lease);
  ASSERT_EQ(b.checkpoints.put(lease->job_id, lease->token, "state", 10, 0.01, t0 + 6), LeaseCheck::ok);
  ASSERT_TRUE(b.checkpoints.find(lease->job_id));
  const ImportOutcome o = import_text(b, export_of(a, sa), "open", t0 + 40);
  EXPECT_EQ(o.filled, 2);
  EXPECT_FALSE(b.checkpoints.find(lease->job_id)) << "a succeeded job keeps no checkpoint";
  EXPECT_TRUE(std::filesystem::is_empty(dir.file("b.db") + ".checkpoints"));
}

TEST_F(ImportTest, ProvenanceThatNamesThisDatabaseMustBeTrueOfIt) {
  const std::int64_t sa = create(a, "part A");
  run_all(a, "a");
  const json from_a = json::parse(export_of(a, sa));
  const std::string own = a.imports.database_id();
  const std::string before = a.reads.fingerprint();
  auto refused = [&](const json& f) -> std::string {
    try {
      a.imports.merge(read_export(f.dump()), t0 + 40);
    } catch (const ApiError& e) {
      return e.field;
    }
    return "";
  };
  // b's own runs, claiming a's sweep: they would join a's sweep (and its adaptive budget).
  const std::int64_t sb = b.sweeps.create(
      sweep_rows(plan_sweep({{"name", "b's"}, {"points", {{{"S", 0.07}, {"R", 1e-3}, {"phi", 0.4}}}},
                             {"numerics", {{"cells_per_unit", 6}, {"eps_end", 0.02}}}}),
                 compaction::engine_version()),
      t0).id;
  run_all(b, "d");
  json forged = json::parse(export_of(b, sb));
  forged["sweep"]["origin"] = {{"database", own}, {"sweep", sa}};
  EXPECT_EQ(refused(forged), "runs[0]");
  forged["sweep"]["origin"] = {{"database", own}, {"sweep", 99}};
  EXPECT_EQ(refused(forged), "sweep.origin.sweep");
  // A run claiming to be a's job 1 with another scene.
  json claimed = json::parse(export_of(b, sb));
  claimed["runs"][0]["origin"] = {{"database", own}, {"job", 1}};
  EXPECT_EQ(refused(claimed), "runs[0].origin");
  // Two runs of one file claiming one origin.
  json twice = from_a;
  for (json& run : twice["runs"]) run["origin"] = {{"database", "0123456789abcdef0123456789abcdef"}, {"job", 5}};
  EXPECT_EQ(refused(twice), "runs[1].origin");
  EXPECT_EQ(a.reads.fingerprint(), before);
  // A round trip is still true of a: nothing new.
  EXPECT_FALSE(a.imports.merge(read_export(from_a.dump()), t0 + 50).changed());
}

TEST_F(ImportTest, AnOriginRunIsHereOnceAcrossImports) {
  const std::int64_t sa = create(a, "part A");
  run_all(a, "a");
  const json from_a = json::parse(export_of(a, sa));
  ASSERT_EQ(b.imports.merge(read_export(from_a.dump()), t0 + 40).added, 2);
  // Another file (another sweep of c's) claims a's first run for a run of another scene.
  TempDir other;
  Store c{other.file("c.db"), config()};
  const std::int64_t sc = c.sweeps.create(
      sweep_rows(plan_sweep({{"name", "c's"}, {"points", {{{"S", 0.08}, {"R", 1e-3}, {"phi", 0.4}}}},
                             {"numerics", {{"cells_per_unit", 6}, {"eps_end", 0.02}}}}),
                 compaction::engine_version()),
      t0).id;
  run_all(c, "d");
  json claims = json::parse(export_of(c, sc));
  claims["runs"][0]["origin"] = from_a["runs"][0]["origin"];
  const std::string before = b.reads.fingerprint();
  try {
    b.imports.merge(read_export(claims.dump()), t0 + 60);
    ADD_FAILURE() << "a second run of one origin was imported";
  } catch (const ApiError& e) {
    EXPECT_EQ(e.field, "runs[0].origin");
  }
  EXPECT_EQ(b.reads.fingerprint(), before);
}

TEST_F(ImportTest, ASweepsRequestIsBoundedAsASweepsBodyIs) {
  const std::int64_t sa = create(a, "part A");
  run_all(a, "a");
  json f = json::parse(export_of(a, sa));
  f["sweep"]["request"]["padding"] = std::string(2 << 20, 'x');
  try {
    read_export(f.dump());
    ADD_FAILURE() << "a 2 MB request was read";
  } catch (const ApiError& e) {
    EXPECT_EQ(e.field, "sweep.request.padding");
  }
  // Below the reader's bound of text, a request beyond a sweep body's limit.
  f["sweep"]["request"]["padding"] = std::string((1 << 20) + 100, 'x');
  try {
    read_export(f.dump());
    ADD_FAILURE() << "a request beyond 1 MiB was read";
  } catch (const ApiError& e) {
    EXPECT_EQ(e.field, "sweep.request");
  }
  // A file of many empty runs is refused at its first, without building the others.
  f = json::parse(export_of(a, sa));
  f.erase("runs");
  std::string text = f.dump();
  text.pop_back();
  text += R"(,"runs": [)";
  for (int i = 0; i < 100000; ++i) text += i ? ",{}" : "{}";
  text += "]}";
  try {
    read_export(text);
    ADD_FAILURE() << "empty runs were read";
  } catch (const ApiError& e) {
    EXPECT_EQ(e.field, "runs[0].job_id");
  }
}
