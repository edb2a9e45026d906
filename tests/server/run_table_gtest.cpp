// The run table's rows (migration 0012, store/run_table.hpp) against the tables that own their
// values: the triggers keep every row as the backfill of an existing database reads it, through
// every write of a job's life (insert, lease, result, failure, a person's label set, changed and
// cleared, a second sweep, an import); a run's preset is the one its scene was made from (the
// contact "auto" resolved), not one it merely resembles; the label
// is the one that counts (counted_label).
#include <gtest/gtest.h>

#include "compaction/presets.hpp"
#include "plan/counted_label.hpp"
#include "run_table_fill.hpp"
#include "store/migrations.hpp"

using namespace compaction::server;
using namespace compaction::server::run_table_fill;
using nlohmann::json;

namespace {

StoreConfig config() {
  StoreConfig c;
  c.engine_version = compaction::engine_version();
  return c;
}

// Every row of run_rows, every column, as text.
std::vector<std::string> dump(const std::string& path) {
  sqlite::Database db(path);
  auto q = db.prepare(
      "SELECT quote(job_id) || ',' || quote(sweep) || ',' || quote(state) || ',' || quote(S) || ','"
      " || quote(R) || ',' || quote(phi) || ',' || quote(cells_per_unit) || ',' || quote(point_id)"
      " || ',' || quote(seed) || ',' || quote(preset) || ',' || quote(status) || ',' || quote(class) || ',' || quote(confidence) || ','"
      " || quote(runner_up) || ',' || quote(n_reflections) || ',' || quote(band_speed_ratio)"
      " || ',' || quote(source_database) || ',' || quote(source_job) || ',' || quote(human_label)"
      " || ',' || quote(label) || ',' || quote(geometry) || ',' || quote(eps_reached)"
      " || ',' || quote(wall_seconds) || ',' || quote(deflection_before_yield)"
      " || ',' || quote(coherence) || ',' || quote(n_fronts) || ',' || quote(stress_ratio)"
      " || ',' || quote(peak_jump) FROM run_rows ORDER BY job_id");
  std::vector<std::string> rows;
  while (q.step()) rows.push_back(q.text(0));
  return rows;
}

RunQuery all_rows() {
  RunQuery q;
  q.limit = 1000;
  return q;
}

std::size_t column(const char* name) { return *run_column(name); }

}  // namespace

TEST(RunTable, TheTriggersKeepEachRowAsTheBackfillReadsItFromItsOwners) {
  TempDir dir;
  const std::string path = dir.file("runs.db");
  {
    Store s(path, config());
    fill(s, dir);
    s.labels.set(3, {"b", "no, two", "ana", t0 + 80, "open", std::nullopt});
    s.labels.clear(3, "the classifier was right", "ana", "open", t0 + 81);
    s.labels.set(4, {"e", "slow band", "ben", t0 + 82, "open", std::nullopt});
  }
  const std::vector<std::string> kept = dump(path);
  ASSERT_EQ(kept.size(), 16u);
  {
    // Back to a database of 0011 with the same rows: no run table, no triggers, no record.
    sqlite::Database db(path);
    db.exec_script(
        "DROP TRIGGER run_rows_job; DROP TRIGGER run_rows_point; DROP TRIGGER run_rows_state;"
        "DROP TRIGGER run_rows_sweep; DROP TRIGGER run_rows_result; DROP TRIGGER run_rows_label_set;"
        "DROP TRIGGER run_rows_label_changed; DROP TRIGGER run_rows_label_cleared;"
        "DROP TRIGGER run_rows_geometry;"
        "DROP TABLE run_rows; DELETE FROM schema_migrations WHERE version IN (12, 14, 15);");
  }
  { Store again(path, config()); }  // applies 0012, 0014 and 0015: the backfill
  EXPECT_EQ(dump(path), kept);
}

TEST(RunTable, TheRowsHoldWhatTheOwnersSay) {
  TempDir dir;
  Store s(dir.file("runs.db"), config());
  const Filled f = fill(s, dir);
  const RunPage<RunRow> page = s.runs.page(all_rows());
  ASSERT_EQ(page.total, 16);
  const auto value = [&](std::int64_t id, const char* name) { return page.items.at(id - 1).values[column(name)]; };
  EXPECT_EQ(value(1, "sweep"), RunValue(f.fast)) << "the first sweep of a run two sweeps hold";
  EXPECT_EQ(value(1, "state"), RunValue("succeeded"));
  EXPECT_EQ(value(1, "class"), RunValue("a"));
  EXPECT_EQ(value(5, "status"), RunValue("unstable"));
  EXPECT_EQ(value(2, "human_label"), RunValue("d")) << "the changed label";
  EXPECT_EQ(value(11, "state"), RunValue("failed"));
  EXPECT_EQ(value(12, "state"), RunValue("running"));
  EXPECT_EQ(value(13, "state"), RunValue("queued"));
  EXPECT_EQ(value(13, "class"), RunValue());
  EXPECT_EQ(value(7, "point_id"), value(8, "point_id")) << "replicates of one point";
  EXPECT_NE(value(7, "point_id"), value(10, "point_id"));
  EXPECT_EQ(value(9, "seed"), RunValue(std::int64_t{3}));
  EXPECT_EQ(value(15, "source_database"), RunValue(f.source));
  EXPECT_EQ(value(15, "source_job"), RunValue(std::int64_t{1}));
  EXPECT_EQ(value(15, "sweep"), RunValue(f.imported));
  EXPECT_EQ(value(1, "source_database"), RunValue());
  // The classifier's features (run_table_fill::features_of): numbers and integers as they are,
  // null as no value; none before a result.
  // (Through a JSON text and SQLite's reading of it: equal to the last bit or two.)
  EXPECT_DOUBLE_EQ(std::get<double>(value(1, "deflection_before_yield")), 0.1 / 10.0);
  EXPECT_DOUBLE_EQ(std::get<double>(value(1, "coherence")), 1.0 - 0.1);
  EXPECT_EQ(value(2, "n_fronts"), RunValue(std::int64_t{2}));
  EXPECT_EQ(value(2, "stress_ratio"), RunValue(0.5));
  EXPECT_EQ(value(1, "stress_ratio"), RunValue()) << "null (NaN) in the features";
  EXPECT_EQ(value(3, "peak_jump"), RunValue(2.0)) << "an integer in a number column";
  EXPECT_EQ(value(1, "eps_reached"), RunValue(0.05));
  EXPECT_EQ(value(13, "deflection_before_yield"), RunValue());
  const double cells_per_strut = std::get<double>(value(13, "cells_per_strut"));
  EXPECT_DOUBLE_EQ(cells_per_strut, 10 * compaction::strut_fraction(0.3));
}

TEST(RunTable, ARunsPresetIsTheOneItsSceneWasMadeFrom) {
  TempDir dir;
  Store s(dir.file("runs.db"), config());
  std::map<std::int64_t, json> expected;  // job id -> preset name or null
  for (const compaction::Preset& p : compaction::presets()) {
    create(s, {{"name", p.name}, {"phi", 0.4}, {"S", 0.01}, {"R", 1e-3}, {"numerics", numerics({{"preset", p.name}})}});
    expected[static_cast<std::int64_t>(expected.size()) + 1] = p.name;
    create(s, {{"name", p.name + " with another cfl"}, {"phi", 0.4}, {"S", 0.01}, {"R", 1e-3},
               {"numerics", numerics({{"preset", p.name}, {"cfl", 0.3}})}});
    expected[static_cast<std::int64_t>(expected.size()) + 1] = nullptr;
    create(s, {{"name", p.name + " on a grid of its own"}, {"phi", 0.4}, {"S", 0.01}, {"R", 1e-3},
               {"numerics", numerics({{"preset", p.name}, {"cells_per_unit", 12}})}});
    expected[static_cast<std::int64_t>(expected.size()) + 1] = nullptr;
  }
  // "auto" contact resolved for the scene: single field under PIC/FLIP, still the default preset;
  // the default's numerics with the single field asked for where "auto" splits: numerics of
  // their own.
  create(s, {{"name", "default, pic/flip"}, {"phi", 0.4}, {"S", 0.01}, {"R", 1e-3},
             {"numerics", numerics({{"preset", "default"}, {"transfer", "pic_flip"}})}});
  expected[static_cast<std::int64_t>(expected.size()) + 1] = "default";
  create(s, {{"name", "default, one field"}, {"phi", 0.4}, {"S", 0.01}, {"R", 1e-3},
             {"numerics", numerics({{"preset", "default"}, {"pore_contact", "single_field"}})}});
  expected[static_cast<std::int64_t>(expected.size()) + 1] = nullptr;
  const RunPage<RunRow> page = s.runs.page(all_rows());
  ASSERT_EQ(page.items.size(), expected.size());
  for (const RunRow& r : page.items) {
    const RunValue& preset = r.values[column("preset")];
    if (expected[r.id()].is_null()) {
      EXPECT_EQ(preset, RunValue()) << r.id();
    } else {
      EXPECT_EQ(preset, RunValue(expected[r.id()].get<std::string>())) << r.id();
    }
  }
  // The filter keeps the same runs.
  for (const compaction::Preset& p : compaction::presets()) {
    RunQuery q = all_rows();
    q.filter.preset.values = {p.name};
    const RunPage<RunRow> one = s.runs.page(q);
    std::size_t n = 0;
    for (const auto& [id, name] : expected) n += name == p.name;
    EXPECT_EQ(one.items.size(), n) << p.name;
    for (const RunRow& r : one.items) EXPECT_EQ(expected[r.id()], p.name);
  }
  RunQuery none = all_rows();
  none.filter.preset.none = true;
  EXPECT_EQ(s.runs.page(none).total, 7);
}

TEST(RunTable, ARowHasItsScenesGeometryAndItsStrutByThatGeometrysRule) {
  TempDir dir;
  Store s(dir.file("runs.db"), config());
  create(s, {{"name", "2D"}, {"phi", 0.4}, {"S", 0.01}, {"R", 1e-3}, {"numerics", numerics({{"cells_per_unit", 8}})}});
  create(s, {{"name", "3D"}, {"phi", 0.4}, {"S", 0.01}, {"R", 1e-3},
             {"numerics", numerics({{"cells_per_unit", 8}, {"geometry", "pseudo1d_3d"}})}});
  create(s, {{"name", "full"}, {"phi", 0.4}, {"S", 0.01}, {"R", 1e-3},
             {"numerics", numerics({{"cells_per_unit", 8}, {"geometry", "full2d"}})}});
  const RunPage<RunRow> page = s.runs.page(all_rows());
  ASSERT_EQ(page.items.size(), 3u);
  const auto geometry = [&](std::size_t i) { return page.items[i].values[column("geometry")]; };
  const auto strut = [&](std::size_t i) { return std::get<double>(page.items[i].values[column("cells_per_strut")]); };
  EXPECT_EQ(geometry(0), RunValue("pseudo1d"));
  EXPECT_EQ(geometry(1), RunValue("pseudo1d_3d"));
  EXPECT_EQ(geometry(2), RunValue("full2d"));
  // 8 (1 - sqrt(0.6)) = 1.803 across the square hole's strut, 8 (1 - 0.6^(1/3)) = 1.253 across
  // the cubic hole's (the strut the engine meshes, SceneParams::grid_cells_per_strut).
  EXPECT_NEAR(strut(0), 1.803, 5e-4);
  EXPECT_NEAR(strut(1), 1.253, 5e-4);
  EXPECT_NEAR(strut(2), 1.803, 5e-4);
  compaction::SceneParams p3 = compaction::scene_defaults(compaction::Geometry::pseudo1d_3d);
  p3.phi = 0.4;
  p3.cells_per_unit = 8;
  EXPECT_DOUBLE_EQ(strut(1), p3.grid_cells_per_strut());

  RunQuery q = all_rows();
  q.filter.geometries = {"pseudo1d_3d", "full2d"};
  const RunPage<RunRow> some = s.runs.page(q);
  ASSERT_EQ(some.total, 2);
  EXPECT_EQ(some.items[0].id(), page.items[1].id());
  EXPECT_EQ(some.items[1].id(), page.items[2].id());
  q.filter.geometries = {"pseudo1d"};
  EXPECT_EQ(s.runs.page(q).total, 1);
}

TEST(RunTable, TheLabelIsTheOneThatCounts) {
  TempDir dir;
  Store s(dir.file("runs.db"), config());
  fill(s, dir);
  for (const RunRow& r : s.runs.page(all_rows()).items) {
    const auto text = [&](const char* name) -> std::optional<std::string> {
      const RunValue& v = r.values[column(name)];
      return std::holds_alternative<std::string>(v) ? std::optional(std::get<std::string>(v)) : std::nullopt;
    };
    const adaptive::Labelled counted = counted_label({0, 0}, text("human_label"), text("class"), 0.5, std::nullopt);
    EXPECT_EQ(text("label"), counted.label) << r.id();
  }
}
