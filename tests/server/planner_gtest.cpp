// Sweep planning: grids (log, linear, lists), points, presets, numerics, limits and the
// field named by each error.
#include "plan/planner.hpp"

#include <gtest/gtest.h>

#include <set>

#include "input/api_error.hpp"

using namespace compaction::server;
using nlohmann::json;

namespace {

// The error a body raises: {status, field}.
std::pair<int, std::string> error_of(const json& body, PlannerLimits limits = {}) {
  try {
    plan_sweep(body, limits);
  } catch (const ApiError& e) {
    return {e.status, e.field};
  }
  return {0, "no error"};
}

json grid() {
  return {{"name", "g"},
          {"S", {{"min", 1e-3}, {"max", 1e-1}, {"n", 3}, {"scale", "log"}}},
          {"R", json::array({1e-5, 1e-3})},
          {"phi", 0.4},
          {"numerics", {{"preset", "fast"}, {"eps_end", 0.05}}}};
}

}  // namespace

TEST(Planner, ALogGridHitsTheDecadesExactly) {
  const auto v = expand_axis({{"min", 1e-3}, {"max", 1e-1}, {"n", 5}, {"scale", "log"}}, "S", 100);
  ASSERT_EQ(v.size(), 5u);
  EXPECT_EQ(v[0], 1e-3);
  EXPECT_EQ(v[2], 0.01) << "10^-2 must be the same double as the literal, for reuse";
  EXPECT_EQ(v[4], 0.1);
  EXPECT_NEAR(v[1], std::sqrt(1e-3 * 1e-2), 1e-12 * v[1]) << "rounded to 12 significant digits";
}

TEST(Planner, ALinearGridIsEvenlySpaced) {
  const auto v = expand_axis({{"min", 0.3}, {"max", 0.5}, {"n", 3}}, "phi", 100);
  EXPECT_EQ(v, (std::vector<double>{0.3, 0.4, 0.5}));
}

TEST(Planner, AGridIsTheProductOfItsAxesWithThePresetsNumerics) {
  const SweepPlan p = plan_sweep(grid());
  ASSERT_EQ(p.scenes.size(), 6u);
  EXPECT_EQ(p.preset, "fast");
  for (const auto& s : p.scenes) {
    EXPECT_EQ(s.cells_per_strut, 1.8);
    EXPECT_EQ(s.grid_cells_per_unit(), 8);
    EXPECT_DOUBLE_EQ(s.eps_end, 0.05);
    EXPECT_EQ(s.phi, 0.4);
  }
  EXPECT_EQ(p.scenes[0].S, 1e-3);
  EXPECT_EQ(p.scenes[0].R, 1e-5);
  EXPECT_EQ(p.scenes[5].S, 0.1);
  EXPECT_EQ(p.scenes[5].R, 1e-3);
}

TEST(Planner, ExplicitNumericsOverrideThePreset) {
  json b = grid();
  b["numerics"]["cells_per_unit"] = 6;
  EXPECT_EQ(plan_sweep(b).scenes[0].grid_cells_per_unit(), 6);
  b["numerics"].erase("preset");
  b["numerics"].erase("cells_per_unit");
  EXPECT_EQ(plan_sweep(b).scenes[0].cells_per_strut, 4.5) << "the default preset";
  EXPECT_EQ(plan_sweep(b).scenes[0].grid_cells_per_unit(), 20) << "the default preset";
}

// The default and reference presets ask for pore_contact auto; a job's scene names what it runs
// with, so equal computations share one identity however they were asked for.
TEST(Planner, ThePresetsPoreContactIsResolvedPerJob) {
  using compaction::PoreContact;
  json b = grid();
  b["numerics"] = {{"preset", "default"}};
  for (const compaction::SceneParams& s : plan_sweep(b).scenes) {
    EXPECT_EQ(s.pore_contact, PoreContact::split_fields);
  }
  json split = b;
  split["numerics"]["pore_contact"] = "split_fields";
  EXPECT_EQ(job_identity(plan_sweep(b).scenes[0], "v1"),
            job_identity(plan_sweep(split).scenes[0], "v1"));
  b["numerics"]["cells_per_unit"] = 12;  // 2.7 cells across the strut: one field
  EXPECT_EQ(plan_sweep(b).scenes[0].pore_contact, PoreContact::single_field);
  split["numerics"]["cells_per_unit"] = 12;  // asked for explicitly: refused with its reason
  EXPECT_EQ(error_of(split), std::make_pair(422, std::string("numerics.pore_contact")));
  b["numerics"] = {{"preset", "default"}, {"structure", "random"}};  // 2.25 cells: one field
  EXPECT_EQ(plan_sweep(b).scenes[0].pore_contact, PoreContact::single_field);
  b["numerics"]["preset"] = "reference";  // 4.5 cells across the thinnest random strut
  EXPECT_EQ(plan_sweep(b).scenes[0].pore_contact, PoreContact::split_fields);
  b["numerics"]["preset"] = "fast";
  b["numerics"].erase("structure");
  EXPECT_EQ(plan_sweep(b).scenes[0].pore_contact, PoreContact::single_field);
}

TEST(Planner, APresetGivesTheSameCellsPerStrutAtEveryPhi) {
  json b = grid();
  b["numerics"] = {{"preset", "default"}};
  b["phi"] = json::array({0.25, 0.4, 0.6, 0.75});
  for (const compaction::SceneParams& s : plan_sweep(b).scenes) {
    // The fewest whole cells per unit cell that reach 4.5 across the strut: one cell fewer
    // would miss it by the strut's share of a cell.
    EXPECT_GE(s.grid_cells_per_strut(), 4.5) << "phi " << s.phi;
    EXPECT_LT(s.grid_cells_per_strut() - s.strut_fraction(), 4.5) << "phi " << s.phi;
  }
}

TEST(Planner, TheIssuesExampleBodyWorks) {
  const json body = json::parse(R"({"name": "demo", "points": [{"S": 0.05, "R": 0.001,
      "phi": 0.4}], "numerics": {"cells_per_unit": 8, "eps_end": 0.05}})");
  const SweepPlan p = plan_sweep(body);
  ASSERT_EQ(p.scenes.size(), 1u);
  EXPECT_EQ(p.scenes[0].S, 0.05);
  EXPECT_EQ(p.priority, 0);
  EXPECT_EQ(p.max_attempts, 3);
}

TEST(Planner, DuplicatePointsCollapse) {
  json b = {{"name", "d"},
            {"points", {{{"S", 0.05}, {"R", 1e-3}, {"phi", 0.4}},
                        {{"S", 0.05}, {"R", 1e-3}, {"phi", 0.4}}}}};
  EXPECT_EQ(plan_sweep(b).scenes.size(), 1u);
}

TEST(Planner, ErrorsNameTheFieldAtFault) {
  auto pts = [](json point) {
    return json{{"name", "p"}, {"points", json::array({{{"S", 0.05}, {"R", 1e-3}, {"phi", 0.4}}, point})}};
  };
  EXPECT_EQ(error_of(pts({{"S", 0.05}, {"R", 1e-3}, {"phi", 0.95}})),
            std::make_pair(422, std::string("points[1].phi")));
  EXPECT_EQ(error_of(pts({{"S", "0.05"}, {"R", 1e-3}, {"phi", 0.4}})),
            std::make_pair(422, std::string("points[1].S")));
  EXPECT_EQ(error_of(pts({{"S", -1}, {"R", 1e-3}, {"phi", 0.4}})),
            std::make_pair(422, std::string("points[1].S")));
  EXPECT_EQ(error_of(pts({{"S", 0.05}, {"phi", 0.4}})),
            std::make_pair(422, std::string("points[1].R")));
  EXPECT_EQ(error_of(pts({{"S", 0.05}, {"R", 1e-3}, {"phi", 0.4}, {"T", 1}})),
            std::make_pair(422, std::string("points[1].T")));

  json b = grid();
  b["S"]["min"] = 0;
  EXPECT_EQ(error_of(b), std::make_pair(422, std::string("S.min"))) << "log scale needs min > 0";
  b = grid();
  b["S"]["n"] = 2.5;
  EXPECT_EQ(error_of(b), std::make_pair(422, std::string("S.n")));
  b = grid();
  b["R"] = json::array({1e-3, 2.0});
  EXPECT_EQ(error_of(b).second, "R");
  b = grid();
  b["numerics"]["preset"] = "turbo";
  EXPECT_EQ(error_of(b), std::make_pair(422, std::string("numerics.preset")));
  b = grid();
  b["numerics"]["cfl"] = "big";
  EXPECT_EQ(error_of(b), std::make_pair(422, std::string("numerics.cfl")));
  b = grid();
  b["numerics"]["threads"] = 4;
  EXPECT_EQ(error_of(b), std::make_pair(422, std::string("numerics.threads")));
  b = grid();
  b["numerics"]["cells_per_unit"] = 3;  // struts of phi = 0.4 thinner than a cell
  EXPECT_EQ(error_of(b), std::make_pair(422, std::string("numerics.cells_per_unit")));
  b = grid();
  b["priority"] = 1e6;
  EXPECT_EQ(error_of(b), std::make_pair(422, std::string("priority")));
  b = grid();
  b.erase("name");
  EXPECT_EQ(error_of(b), std::make_pair(422, std::string("name")));
  b = grid();
  b["points"] = json::array();
  EXPECT_EQ(error_of(b), std::make_pair(422, std::string("points")));
  EXPECT_EQ(error_of(json::array()).first, 400);
}

TEST(Planner, OversizedSweepsAreRefusedWith413) {
  PlannerLimits limits;
  limits.max_points = 10;
  json b = grid();  // 6 points: fine
  EXPECT_EQ(error_of(b, limits).first, 0);
  b["R"] = {{"min", 1e-5}, {"max", 1e-3}, {"n", 2}, {"scale", "log"}};
  b["phi"] = json::array({0.4, 0.5});  // 3 x 2 x 2 = 12
  EXPECT_EQ(error_of(b, limits).first, 413);
  b["S"]["n"] = 1'000'000'000;
  EXPECT_EQ(error_of(b, limits), std::make_pair(413, std::string("S.n")));
  json pts = {{"name", "p"}, {"points", json::array()}};
  for (int i = 0; i < 11; ++i) pts["points"].push_back({{"S", 0.01 + i * 0.001}, {"R", 1e-3}, {"phi", 0.4}});
  EXPECT_EQ(error_of(pts, limits), std::make_pair(413, std::string("points")));
}

TEST(Planner, TheIdentityIgnoresThreadsButNotNumerics) {
  compaction::SceneParams a, b;
  b.threads = 8;
  EXPECT_EQ(job_identity(a, "v1"), job_identity(b, "v1"));
  b.cells_per_unit = 8;
  EXPECT_NE(job_identity(a, "v1"), job_identity(b, "v1"));
  EXPECT_NE(job_identity(a, "v1"), job_identity(a, "v2"));
}

TEST(Planner, TheIdentityHoldsTheStructureAndItsSeed) {
  compaction::SceneParams a, b;
  b.structure = compaction::Structure::random;
  EXPECT_NE(job_identity(a, "v1"), job_identity(b, "v1"));
  EXPECT_NE(canonical_scene(b).find("\"structure\":\"random\""), std::string::npos);
  compaction::SceneParams c = b;
  c.seed = 2;
  EXPECT_NE(job_identity(b, "v1"), job_identity(c, "v1"));
}

// Seeds as a parsed body holds them (non-negative integers parse as unsigned, which is what
// compaction::from_json takes for seed): json::parse, or 1u in code.
TEST(Planner, RandomStructuresRunEveryPointOncePerSeed) {
  json b = grid();
  b["numerics"] = {{"preset", "default"}, {"eps_end", 0.05}, {"structure", "random"},
                   {"seeds", json::parse("[5, 1, 9]")}};
  const SweepPlan p = plan_sweep(b);
  ASSERT_EQ(p.scenes.size(), 18u);  // 3 S x 2 R x 3 seeds
  std::set<std::string> identities;
  for (std::size_t i = 0; i < p.scenes.size(); ++i) {
    EXPECT_EQ(p.scenes[i].structure, compaction::Structure::random);
    EXPECT_EQ(p.scenes[i].seed, (std::vector<std::uint64_t>{5, 1, 9})[i % 3]) << i;
    identities.insert(job_identity(p.scenes[i], "v1"));
  }
  EXPECT_EQ(identities.size(), 18u);
  EXPECT_EQ(p.scenes[0].S, p.scenes[2].S);  // the seeds of a point follow one another
  b["numerics"].erase("seeds");
  b["numerics"]["seed"] = 4u;
  const SweepPlan one = plan_sweep(b);
  ASSERT_EQ(one.scenes.size(), 6u);
  EXPECT_EQ(one.scenes[0].seed, 4u);
}

TEST(Planner, StructureAndSeedsAreValidatedWithTheirField) {
  auto with = [](json numerics) {
    json b = grid();
    numerics["preset"] = "default";
    b["numerics"] = numerics;
    return b;
  };
  const auto bad = [&](json numerics, const char* field) {
    EXPECT_EQ(error_of(with(numerics)), std::make_pair(422, std::string(field))) << numerics.dump();
  };
  bad({{"structure", "voronoi"}}, "numerics.structure");
  bad({{"structure", "random"}, {"seeds", "1,2"}}, "numerics.seeds");
  bad({{"structure", "random"}, {"seeds", json::array()}}, "numerics.seeds");
  const json two = json::parse("[1, 2]");
  bad({{"structure", "random"}, {"seeds", json::parse("[1, -2]")}}, "numerics.seeds[1]");
  bad({{"structure", "random"}, {"seeds", json::parse("[1, 2.5]")}}, "numerics.seeds[1]");
  bad({{"structure", "random"}, {"seeds", json::parse("[3, 3]")}}, "numerics.seeds[1]");
  bad({{"structure", "random"}, {"seeds", two}, {"seed", 1u}}, "numerics.seeds");
  bad({{"seeds", two}}, "numerics.seeds");  // a regular structure: the seed changes nothing
  bad({{"structure", "random"}, {"seed", -1}}, "numerics.seed");
  json fast = grid();  // the fast preset leaves the thinnest random strut under a cell
  fast["numerics"]["structure"] = "random";
  EXPECT_EQ(error_of(fast), std::make_pair(422, std::string("numerics.cells_per_strut")));
  json many = with({{"structure", "random"}, {"seeds", json::array()}});
  for (std::size_t i = 0; i <= kMaxSeeds; ++i) many["numerics"]["seeds"].push_back(i);
  EXPECT_EQ(error_of(many), std::make_pair(422, std::string("numerics.seeds")));
  // A regular structure with a perturbation has seeds that matter.
  EXPECT_EQ(error_of(with({{"seeds", two}, {"perturbation", 0.1}})).first, 0);
  PlannerLimits limits;
  limits.max_points = 10;  // 6 points x 2 seeds
  EXPECT_EQ(error_of(with({{"structure", "random"}, {"seeds", two}}), limits),
            std::make_pair(413, std::string("numerics.seeds")));
  json adaptive = json::parse(R"({"name": "map", "phi": 0.4,
      "numerics": {"preset": "default", "structure": "random", "seeds": [1, 2]},
      "adaptive": {"S": {"min": 1e-3, "max": 1e-1}, "R": {"min": 1e-5, "max": 1e-1},
                   "initial": {"S": 3, "R": 3}, "resolution_decades": 0.5, "budget": 20}})");
  // An adaptive sweep maps with one run a point (the first seed) and adds replicates, with the
  // next seeds, where the map asks for them (levels_plan.hpp).
  const SweepPlan twice = plan_sweep(adaptive);
  EXPECT_EQ(twice.replicates, 2u);
  ASSERT_EQ(twice.scenes.size(), 9u);
  for (const auto& scene : twice.scenes) EXPECT_EQ(scene.seed, 1u);
  const auto more = adaptive_scenes(twice, {{{0.01, 1e-3}, 0, 1, 0.0, 0.0, "replicate"}});
  ASSERT_EQ(more.size(), 1u);
  EXPECT_EQ(more[0].seed, 2u) << "replicate 1 runs with the second seed";
  adaptive["adaptive"]["budget"] = 8;
  EXPECT_EQ(error_of(adaptive), std::make_pair(422, std::string("adaptive.budget")));
  adaptive["adaptive"]["budget"] = 20;
  adaptive["numerics"]["seeds"] = json::parse("[7]");
  const SweepPlan p = plan_sweep(adaptive);
  ASSERT_FALSE(p.scenes.empty());
  EXPECT_EQ(p.scenes[0].seed, 7u);
  EXPECT_EQ(adaptive_scenes(p, {{{0.01, 1e-3}, 0, 0, 0.0, 0.0, "map"}})[0].seed, 7u);
}

TEST(Planner, ReplicatesRunEachPointWithSeedsOneToNAndTheirPerturbation) {
  json body = grid();  // 6 points
  body["replicates"] = {{"n", 4}, {"perturbation", 0.01}};
  const SweepPlan p = plan_sweep(body);
  EXPECT_EQ(p.replicates, 4u);
  ASSERT_EQ(p.scenes.size(), 24u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(p.scenes[i].seed, i + 1);
    EXPECT_EQ(p.scenes[i].perturbation, 0.01);
    EXPECT_EQ(p.scenes[i].S, p.scenes[0].S);
  }
  // The explicit seeds of the same runs are the same jobs: one concept, two spellings.
  json seeds = grid();
  seeds["numerics"]["seeds"] = json::parse("[1, 2, 3, 4]");
  seeds["numerics"]["perturbation"] = 0.01;
  const SweepPlan q = plan_sweep(seeds);
  ASSERT_EQ(q.scenes.size(), p.scenes.size());
  for (std::size_t i = 0; i < p.scenes.size(); ++i) {
    EXPECT_EQ(canonical_scene(p.scenes[i]), canonical_scene(q.scenes[i]));
  }
  // One replicate of a random structure needs no perturbation.
  json one = grid();
  one["numerics"] = {{"preset", "default"}, {"structure", "random"}};
  one["replicates"] = {{"n", 1}};
  EXPECT_EQ(plan_sweep(one).scenes.size(), 6u);
}

TEST(Planner, BadReplicatesAreRefusedWithTheirField) {
  const auto refused = [](json replicates, const char* field, json numerics = json::object()) {
    json b = grid();
    b["replicates"] = replicates;
    for (const auto& [k, v] : numerics.items()) b["numerics"][k] = v;
    EXPECT_EQ(error_of(b), std::make_pair(422, std::string(field))) << replicates.dump();
  };
  refused(4, "replicates");
  refused({{"n", 4}, {"perturbation", 0.01}, {"seeds", 3}}, "replicates.seeds");
  refused({{"perturbation", 0.01}}, "replicates.n");
  refused({{"n", 0}, {"perturbation", 0.01}}, "replicates.n");
  refused({{"n", 2.5}, {"perturbation", 0.01}}, "replicates.n");
  refused({{"n", kMaxSeeds + 1}, {"perturbation", 0.01}}, "replicates.n");
  refused({{"n", 4}, {"perturbation", 0.6}}, "replicates.perturbation");  // engine: [0, 0.5]
  refused({{"n", 4}, {"perturbation", -0.01}}, "replicates.perturbation");
  refused({{"n", 4}, {"perturbation", "1%"}}, "replicates.perturbation");
  refused({{"n", 4}}, "replicates.perturbation");  // a regular lattice: n copies of one run
  refused({{"n", 4}, {"perturbation", 0.01}}, "replicates.perturbation", {{"perturbation", 0.02}});
  refused({{"n", 4}, {"perturbation", 0.01}}, "numerics.seeds", {{"seeds", json::parse("[1, 2]")}});
  refused({{"n", 4}, {"perturbation", 0.01}}, "numerics.seed", {{"seed", 3}});
  // points x replicates above the sweep limit: 413 at replicates
  json b = grid();
  b["replicates"] = {{"n", 4}, {"perturbation", 0.01}};
  PlannerLimits limits;
  limits.max_points = 20;
  EXPECT_EQ(error_of(b, limits), std::make_pair(413, std::string("replicates")));
}

// Issue 47's body: replicates and two levels, the default preset and 8 cells across a strut.
json trusted() {
  return json::parse(R"({"name": "trusted", "phi": 0.4, "replicates": {"n": 4, "perturbation": 0.01},
      "adaptive": {"S": {"min": 3e-3, "max": 3e-2}, "R": {"min": 1e-5, "max": 1e-2},
                   "initial": {"S": 3, "R": 4}, "resolution_decades": 0.25, "budget": 400,
                   "budget_cpu_hours": 40,
                   "levels": [{"preset": "default"}, {"cells_per_strut": 8}]}})");
}

TEST(Planner, AnAdaptiveSweepWithLevelsStartsAtTheCoarsestWithOneRunAPoint) {
  const SweepPlan p = plan_sweep(trusted());
  ASSERT_EQ(p.levels.size(), 2u);
  EXPECT_EQ(p.replicates, 4u);
  EXPECT_EQ(p.budget_cpu_seconds, 40 * 3600.0);
  ASSERT_EQ(p.scenes.size(), 12u) << "the initial 3 x 4 grid";
  SweepPlan default_preset = plan_sweep(json::parse(R"({"name": "d", "phi": 0.4, "S": 0.01,
      "R": 1e-3, "numerics": {"preset": "default"}})"));
  for (const auto& scene : p.scenes) {
    EXPECT_EQ(scene.seed, 1u);
    EXPECT_EQ(scene.perturbation, 0.01);
    EXPECT_EQ(scene.grid_cells_per_unit(), default_preset.scenes[0].grid_cells_per_unit());
  }
  // The finer level: 8 cells across the strut (36 per unit cell at phi 0.4), the rest the same.
  const compaction::SceneParams fine = level_scene(p, 1, {0.01, 1e-3});
  EXPECT_NEAR(fine.cells_per_strut, 8.0, 1e-12);
  EXPECT_GT(fine.grid_cells_per_unit(), p.scenes[0].grid_cells_per_unit());
  EXPECT_GT(run_cpu_seconds(p, {0.01, 1e-3}, 1), 4 * run_cpu_seconds(p, {0.01, 1e-3}, 0));
  const auto scenes = adaptive_scenes(p, {{{0.01, 1e-3}, 1, 2, 0.0, 0.0, "replicate"}});
  EXPECT_EQ(scenes[0].seed, 3u);
  EXPECT_EQ(scenes[0].grid_cells_per_unit(), fine.grid_cells_per_unit());
  // Without levels: one level, the sweep's numerics.
  json one = trusted();
  one["adaptive"].erase("levels");
  EXPECT_EQ(plan_sweep(one).levels.size(), 1u);
}

TEST(Planner, BadLevelsAndCpuBudgetsAreRefusedWithTheirField) {
  const auto refused = [](const char* key, json value, const std::string& field) {
    json b = trusted();
    b["adaptive"][key] = value;
    EXPECT_EQ(error_of(b), std::make_pair(422, field)) << value.dump();
  };
  refused("levels", json::array(), "adaptive.levels");
  refused("levels", json::parse("[{}, {}, {}, {}, {}]"), "adaptive.levels");
  refused("levels", json::parse(R"([{"cells_per_strut": 8}, {"preset": "default"}])"), "adaptive.levels[1]");
  refused("levels", json::parse(R"([{"preset": "default"}, {"preset": "default"}])"), "adaptive.levels[1]");
  refused("levels", json::parse(R"([{"preset": "default"}, {"eps_end": 0.3}])"), "adaptive.levels[1].eps_end");
  refused("levels", json::parse(R"([{"preset": "coarse"}])"), "adaptive.levels[0].preset");
  refused("levels", json::parse(R"([{"preset": "default"}, {"cells_per_strut": "8"}])"),
          "adaptive.levels[1].cells_per_strut");
  refused("levels", json::parse(R"([{"preset": "default"}, {"cells_per_strut": 80}])"),
          "adaptive.levels[1].cells_per_strut");
  refused("levels", json::parse(R"([3])"), "adaptive.levels[0]");
  refused("budget_cpu_hours", 0, "adaptive.budget_cpu_hours");
  refused("budget_cpu_hours", "40", "adaptive.budget_cpu_hours");
  refused("budget_cpu_hours", 1e-3, "adaptive.budget_cpu_hours");  // below the initial grid's cost
}

TEST(Planner, AnAdaptiveSweepStartsWithItsInitialGridAtItsPhi) {
  const json body = json::parse(R"({"name": "map", "phi": 0.4, "numerics": {"preset": "default"},
      "adaptive": {"S": {"min": 1e-3, "max": 1e-1}, "R": {"min": 1e-5, "max": 1e-1},
                   "initial": {"S": 5, "R": 5}, "resolution_decades": 0.125, "budget": 200}})");
  const SweepPlan p = plan_sweep(body);
  ASSERT_TRUE(p.adaptive);
  EXPECT_EQ(p.adaptive->budget, 200u);
  ASSERT_EQ(p.scenes.size(), 25u);
  for (const auto& s : p.scenes) EXPECT_EQ(s.phi, 0.4);
  // Cheapest first (a run costs about 1/S), as the planner ranks every later point: the
  // queue runs a sweep's jobs in the order they were added.
  EXPECT_EQ(p.scenes.front().S, 1e-1);
  EXPECT_EQ(p.scenes.front().R, 1e-5);
  EXPECT_EQ(p.scenes.back().S, 1e-3);
  EXPECT_EQ(p.scenes.back().R, 1e-1);
  for (std::size_t i = 1; i < p.scenes.size(); ++i) {
    EXPECT_GE(p.scenes[i - 1].S, p.scenes[i].S) << "scene " << i;
  }
  // Further points get the sweep's numerics and phi.
  const auto more = adaptive_scenes(p, {{0.02, 3e-4}});
  ASSERT_EQ(more.size(), 1u);
  EXPECT_EQ(more[0].phi, 0.4);
  EXPECT_EQ(more[0].cells_per_strut, 4.5);
  EXPECT_EQ(more[0].S, 0.02);
}

TEST(Planner, AnAdaptiveSweepNamesWhatItCannotTake) {
  const json ok = json::parse(R"({"name": "map", "phi": 0.4, "adaptive": {"S": {"min": 1e-3,
      "max": 1e-1}, "R": {"min": 1e-5, "max": 1e-1}, "initial": {"S": 3, "R": 3},
      "resolution_decades": 0.25, "budget": 20}})");
  json b = ok;
  b["S"] = 0.01;
  EXPECT_EQ(error_of(b), std::make_pair(422, std::string("S")));
  b = ok;
  b["phi"] = json::array({0.3, 0.4});
  EXPECT_EQ(error_of(b), std::make_pair(422, std::string("phi")));
  b = ok;
  b.erase("phi");
  EXPECT_EQ(error_of(b), std::make_pair(422, std::string("phi")));
  b = ok;
  b["adaptive"]["budget"] = 5;
  EXPECT_EQ(error_of(b), std::make_pair(422, std::string("adaptive.budget")));
}
