// GET /api/v1/jobs, the run table, over HTTP on a loopback port with a real SQLite file
// (run_table_fill.hpp: runs of every kind): each filter keeps the rows its predicate keeps,
// checked against the unfiltered table; every column sorts both ways with nulls last and ties
// by id; pages walked by their cursor (and by offset) give the whole set once, without
// duplicates or gaps; the CSV holds the filtered rows in their order; every bad parameter is a
// 422 naming it; the list's answer before the table is kept; /limits serves the table's rules.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <map>
#include <set>
#include <sstream>

#include "http/page_limits.hpp"
#include "loopback_api.hpp"
#include "run_table_fill.hpp"

using namespace compaction::server;
using nlohmann::json;

namespace {

using Row = json;
using Keep = std::function<bool(const Row&)>;

struct RunsApi : LoopbackApi {
  run_table_fill::Filled filled;
  std::vector<Row> all;                         // the unfiltered table, by id
  std::map<std::int64_t, std::set<std::int64_t>> sweeps_of;  // job -> the sweeps holding it

  void SetUp() override {
    LoopbackApi::SetUp();
    filled = run_table_fill::fill(*store, dir);
    const json t = get("/api/v1/jobs?format=table&limit=1000");
    all = t["rows"].get<std::vector<Row>>();
    for (const Row& r : all) {
      const json d = get("/api/v1/jobs/" + std::to_string(r["id"].get<std::int64_t>()));
      sweeps_of[r["id"]] = d["sweeps"].get<std::set<std::int64_t>>();
    }
  }

  json get(const std::string& path) {
    auto r = client->Get(path.c_str());
    EXPECT_TRUE(r) << path;
    if (!r) return json();
    EXPECT_EQ(r->status, 200) << path << " " << r->body;
    return json::parse(r->body);
  }
  std::vector<std::int64_t> ids_of(const json& rows) {
    std::vector<std::int64_t> ids;
    for (const json& r : rows) ids.push_back(r["id"]);
    return ids;
  }
  std::vector<std::int64_t> kept(const Keep& keep) {
    std::vector<std::int64_t> ids;
    for (const Row& r : all) {
      if (keep(r)) ids.push_back(r["id"]);
    }
    return ids;
  }
};

bool in(const json& v, std::initializer_list<const char*> letters) {
  if (v.is_null()) return false;
  for (const char* l : letters) {
    if (v == l) return true;
  }
  return false;
}
bool at_least(const json& v, double lo) { return v.is_number() && v.get<double>() >= lo; }
bool at_most(const json& v, double hi) { return v.is_number() && v.get<double>() <= hi; }

}  // namespace

TEST_F(RunsApi, TheTableHoldsEveryRunWithItsColumns) {
  ASSERT_EQ(all.size(), 16u);
  const json t = get("/api/v1/jobs?format=table&limit=1000");
  EXPECT_EQ(t["total"], 16);
  EXPECT_EQ(t["sort"], "id");
  EXPECT_TRUE(t["next"].is_null());
  std::vector<std::string> columns;
  for (const RunColumn& c : run_columns()) columns.push_back(c.name);
  EXPECT_EQ(t["columns"], columns);
  for (const Row& r : all) EXPECT_EQ(r.size(), columns.size());
  // The queued run's result columns are null, the labelled run shows both labels.
  EXPECT_EQ(all[12]["state"], "queued");
  EXPECT_TRUE(all[12]["class"].is_null());
  EXPECT_EQ(all[1]["class"], "b");
  EXPECT_EQ(all[1]["human_label"], "d");
  EXPECT_EQ(all[1]["label"], "d");
  EXPECT_EQ(all[0]["preset"], "fast");
  EXPECT_EQ(all[6]["preset"], "default");
  EXPECT_TRUE(all[12]["preset"].is_null());
  EXPECT_EQ(all[14]["source_database"], filled.source);
}

TEST_F(RunsApi, EachFilterKeepsTheRowsItsPredicateKeeps) {
  const std::string src = filled.source;
  const std::string prefix = src.substr(0, 6);
  const std::vector<std::pair<std::string, Keep>> cases = {
      {"sweep=" + std::to_string(filled.overlap), [&](const Row& r) { return sweeps_of[r["id"]].count(filled.overlap) > 0; }},
      {"sweep=" + std::to_string(filled.fast), [&](const Row& r) { return sweeps_of[r["id"]].count(filled.fast) > 0; }},
      {"point=" + all[7]["point_id"].dump(), [&](const Row& r) { return r["point_id"] == all[7]["point_id"]; }},
      {"state=queued", [](const Row& r) { return r["state"] == "queued"; }},
      {"state=failed,running", [](const Row& r) { return in(r["state"], {"failed", "running"}); }},
      {"phi=0.4", [](const Row& r) { return r["phi"] == 0.4; }},
      {"phi_min=0.35&phi_max=0.45", [](const Row& r) { return at_least(r["phi"], 0.35) && at_most(r["phi"], 0.45); }},
      {"S_min=0.01", [](const Row& r) { return at_least(r["S"], 0.01); }},
      {"S_max=0.01&R_min=0.001", [](const Row& r) { return at_most(r["S"], 0.01) && at_least(r["R"], 0.001); }},
      {"R_max=1e-3", [](const Row& r) { return at_most(r["R"], 1e-3); }},
      {"confidence_min=0.3&confidence_max=0.6", [](const Row& r) { return at_least(r["confidence"], 0.3) && at_most(r["confidence"], 0.6); }},
      {"n_reflections_min=2", [](const Row& r) { return at_least(r["n_reflections"], 2); }},
      {"n_reflections_max=0", [](const Row& r) { return at_most(r["n_reflections"], 0); }},
      {"band_speed_ratio_min=1.5&band_speed_ratio_max=3", [](const Row& r) { return at_least(r["band_speed_ratio"], 1.5) && at_most(r["band_speed_ratio"], 3); }},
      {"deflection_before_yield_min=0.03", [](const Row& r) { return at_least(r["deflection_before_yield"], 0.03); }},
      {"coherence_max=0.5&n_fronts_min=2", [](const Row& r) { return at_most(r["coherence"], 0.5) && at_least(r["n_fronts"], 2); }},
      {"stress_ratio_min=0", [](const Row& r) { return at_least(r["stress_ratio"], 0); }},
      {"wall_seconds_min=0&eps_reached_max=1", [](const Row& r) { return at_least(r["wall_seconds"], 0) && at_most(r["eps_reached"], 1); }},
      {"cells_per_unit=10", [](const Row& r) { return r["cells_per_unit"] == 10; }},
      {"cells_per_unit=8,10", [](const Row& r) { return r["cells_per_unit"] == 8 || r["cells_per_unit"] == 10; }},
      {"preset=fast", [](const Row& r) { return r["preset"] == "fast"; }},
      {"preset=default,none", [](const Row& r) { return r["preset"] == "default" || r["preset"].is_null(); }},
      {"class=b,e", [](const Row& r) { return in(r["class"], {"b", "e"}); }},
      {"class=none", [](const Row& r) { return r["class"].is_null(); }},
      {"class=any", [](const Row& r) { return !r["class"].is_null(); }},
      {"label=d", [](const Row& r) { return r["label"] == "d"; }},
      {"label=a,none", [](const Row& r) { return r["label"] == "a" || r["label"].is_null(); }},
      {"human_label=any", [](const Row& r) { return !r["human_label"].is_null(); }},
      {"human_label=none", [](const Row& r) { return r["human_label"].is_null(); }},
      {"human_label=a", [](const Row& r) { return r["human_label"] == "a"; }},
      {"imported=true", [](const Row& r) { return !r["source_database"].is_null(); }},
      {"imported=false", [](const Row& r) { return r["source_database"].is_null(); }},
      {"source=" + prefix, [&](const Row& r) { return r["source_database"] == src; }},
      {"source=" + std::string(32, '0'), [](const Row&) { return false; }},
      {"q=trusted", [&](const Row& r) { return sweeps_of[r["id"]].count(filled.overlap) > 0; }},
      {"q=BUCKLES", [](const Row& r) { return r["id"] == 2; }},   // a label's reason, any case
      {"q=ana", [](const Row& r) { return r["id"] == 2; }},       // who set it
      {"q=" + src.substr(8, 10), [&](const Row& r) { return r["source_database"] == src; }},
      {"q=100%25", [](const Row&) { return false; }},             // '%' is a character
      {"q=part%20B", [&](const Row& r) { return sweeps_of[r["id"]].count(filled.imported) > 0; }},
      {"phi=0.4&class=a,b,c&human_label=none", [](const Row& r) {
         return r["phi"] == 0.4 && in(r["class"], {"a", "b", "c"}) && r["human_label"].is_null(); }},
  };
  for (const auto& [query, keep] : cases) {
    const std::vector<std::int64_t> expected = kept(keep);
    const json page = get("/api/v1/jobs?format=table&limit=1000&" + query);
    EXPECT_EQ(ids_of(page["rows"]), expected) << query;
    EXPECT_EQ(page["total"], expected.size()) << query;
    // The jobs of the answer before the table are the same.
    const json jobs = get("/api/v1/jobs?limit=1000&" + query);
    EXPECT_EQ(ids_of(jobs["jobs"]), expected) << query;
  }
}

TEST_F(RunsApi, EveryColumnSortsBothWaysWithNullsLastAndTiesById) {
  const json limits = get("/api/v1/limits");
  ASSERT_GE(limits["jobs"]["sort"].size(), 15u);
  for (const json& key : limits["jobs"]["sort"]) {
    const std::string k = key;
    for (const bool descending : {false, true}) {
      std::vector<Row> expected = all;
      std::stable_sort(expected.begin(), expected.end(), [&](const Row& a, const Row& b) {
        const json &x = a[k], &y = b[k];
        if (x.is_null() != y.is_null()) return y.is_null();  // nulls last, either way
        const bool tie = x == y;
        if (tie) return descending ? a["id"] > b["id"] : a["id"] < b["id"];
        return descending ? x > y : x < y;
      });
      const std::string sort = descending ? "-" + k : k;
      const json page = get("/api/v1/jobs?format=table&limit=1000&sort=" + sort);
      EXPECT_EQ(ids_of(page["rows"]), ids_of(expected)) << sort;
      EXPECT_EQ(page["sort"], sort);
    }
  }
}

TEST_F(RunsApi, PagesWalkedByTheirCursorGiveTheWholeSetOnce) {
  for (const std::string query :
       {"sort=id", "sort=-id", "sort=confidence", "sort=-confidence", "sort=class", "sort=-label",
        "sort=S&phi_min=0.3", "sort=-band_speed_ratio&state=succeeded", "sort=human_label",
        "sort=-source_database", "sort=point_id&preset=default,fast"}) {
    const json whole = get("/api/v1/jobs?format=table&limit=1000&" + query);
    for (const int limit : {1, 3, 5}) {
      std::vector<std::int64_t> walked;
      std::string cursor;
      int pages = 0;
      while (true) {
        const std::string path = "/api/v1/jobs?format=table&limit=" + std::to_string(limit) + "&" +
                                 query + (cursor.empty() ? "" : "&cursor=" + cursor);
        const json page = get(path);
        EXPECT_EQ(page["total"], whole["total"]) << path;
        for (const auto id : ids_of(page["rows"])) walked.push_back(id);
        ++pages;
        if (page["next"].is_null() || pages > 100) break;
        cursor = page["next"];
      }
      EXPECT_EQ(walked, ids_of(whole["rows"])) << query << " in pages of " << limit;
      // By offset, the same; and the full jobs' pages take the same cursor.
      std::vector<std::int64_t> by_offset;
      for (int offset = 0; offset < whole["total"].get<int>(); offset += limit) {
        const json page = get("/api/v1/jobs?limit=" + std::to_string(limit) + "&offset=" +
                              std::to_string(offset) + "&" + query);
        for (const auto id : ids_of(page["jobs"])) by_offset.push_back(id);
      }
      EXPECT_EQ(by_offset, ids_of(whole["rows"])) << query << " by offset, " << limit;
    }
    const json first = get("/api/v1/jobs?limit=2&" + query);
    if (!first["next"].is_null()) {
      const json second = get("/api/v1/jobs?limit=2&" + query + "&cursor=" + first["next"].get<std::string>());
      const auto ids = ids_of(whole["rows"]);
      EXPECT_EQ(ids_of(second["jobs"]), std::vector<std::int64_t>(ids.begin() + 2, ids.begin() + std::min<std::size_t>(4, ids.size())))
          << query;
    }
  }
}

TEST_F(RunsApi, ACursorKeepsItsPlaceWhileRunsAreAddedAndFinished) {
  const json first = get("/api/v1/jobs?format=table&limit=8&sort=-confidence");
  // A new run, and a queued one that finishes with the highest confidence (before the cursor).
  run_table_fill::create(*store, {{"name", "later"}, {"phi", 0.6}, {"S", 0.07}, {"R", 1e-2},
                                  {"numerics", run_table_fill::numerics({{"preset", "fast"}})}});
  const std::int64_t finished = run_table_fill::complete_next(*store, "a", 0.99, 1, 2.0);
  ASSERT_GT(finished, 0);
  std::vector<std::int64_t> seen = ids_of(first["rows"]);
  std::string cursor = first["next"];
  while (!cursor.empty()) {
    const json page = get("/api/v1/jobs?format=table&limit=8&sort=-confidence&cursor=" + cursor);
    for (const auto id : ids_of(page["rows"])) seen.push_back(id);
    cursor = page["next"].is_null() ? "" : page["next"].get<std::string>();
  }
  EXPECT_EQ(std::set<std::int64_t>(seen.begin(), seen.end()).size(), seen.size()) << "no run twice";
  EXPECT_EQ(seen.size(), 16u) << "the 17 runs but the one that moved before the cursor";
  EXPECT_EQ(std::count(seen.begin(), seen.end(), finished), 0);
}

TEST_F(RunsApi, TheCsvHoldsTheFilteredRowsInTheirOrder) {
  const std::string query = "sort=-band_speed_ratio&state=succeeded,queued";
  const json table = get("/api/v1/jobs?format=table&limit=1000&" + query);
  auto r = client->Get(("/api/v1/jobs?format=csv&" + query).c_str());
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(r->get_header_value("Content-Type"), "text/csv; charset=utf-8");
  EXPECT_EQ(r->get_header_value("X-Total-Count"), table["total"].dump());
  EXPECT_EQ(r->get_header_value("X-Row-Limit"), std::to_string(kMaxCsvRows));
  std::istringstream lines(r->body);
  std::string line;
  std::getline(lines, line);
  std::string header;
  for (const json& c : table["columns"]) {
    if (!header.empty()) header += ',';
    header += c.get<std::string>();
  }
  EXPECT_EQ(line, header);
  std::size_t n = 0;
  while (std::getline(lines, line)) {
    ASSERT_LT(n, table["rows"].size());
    const json& row = table["rows"][n++];
    std::string expected;
    for (const json& c : table["columns"]) {
      const json& v = row[c.get<std::string>()];
      if (&c != &table["columns"][0]) expected += ',';
      if (!v.is_null()) expected += v.is_string() ? v.get<std::string>() : v.dump();
    }
    EXPECT_EQ(line, expected);
  }
  EXPECT_EQ(n, table["rows"].size());
  // A limit keeps the first rows; the count still says how many the filters keep.
  auto three = client->Get(("/api/v1/jobs?format=csv&limit=3&" + query).c_str());
  ASSERT_TRUE(three);
  EXPECT_EQ(std::count(three->body.begin(), three->body.end(), '\n'), 4);
  EXPECT_EQ(three->get_header_value("X-Row-Limit"), "3");
  EXPECT_EQ(three->get_header_value("X-Total-Count"), table["total"].dump());
  auto none = client->Get("/api/v1/jobs?format=csv&class=a&state=queued");
  ASSERT_TRUE(none);
  EXPECT_EQ(none->body, header + "\n");
}

TEST_F(RunsApi, ColumnsNamesTheColumnsOfTheTableAndTheCsvInItsOrder) {
  const std::string query = "sort=-deflection_before_yield&class=any";
  const json whole = get("/api/v1/jobs?format=table&limit=1000&" + query);
  const json some = get("/api/v1/jobs?format=table&limit=1000&columns=deflection_before_yield,id,class&" + query);
  EXPECT_EQ(some["columns"], json({"deflection_before_yield", "id", "class"}));
  EXPECT_EQ(some["total"], whole["total"]);
  ASSERT_EQ(some["rows"].size(), whole["rows"].size());
  for (std::size_t i = 0; i < some["rows"].size(); ++i) {
    const json& w = whole["rows"][i];
    EXPECT_EQ(some["rows"][i], json({{"deflection_before_yield", w["deflection_before_yield"]},
                                     {"id", w["id"]}, {"class", w["class"]}}));
  }
  auto r = client->Get(("/api/v1/jobs?format=csv&columns=id,cells_per_strut,deflection_before_yield&" + query).c_str());
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  std::istringstream lines(r->body);
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, "id,cells_per_strut,deflection_before_yield");
  for (const json& w : whole["rows"]) {
    ASSERT_TRUE(std::getline(lines, line));
    const json& d = w["deflection_before_yield"];
    EXPECT_EQ(line, w["id"].dump() + "," + w["cells_per_strut"].dump() + "," + (d.is_null() ? "" : d.dump()));
  }
  EXPECT_FALSE(std::getline(lines, line));
  // Pages of a column subset walk by their cursor as the whole rows do (the sort column is read
  // for the cursor though it is not answered).
  const json sorted = get("/api/v1/jobs?format=table&limit=1000&sort=-confidence");
  std::vector<std::int64_t> walked;
  std::string cursor;
  for (int pages = 0; pages < 20; ++pages) {
    const json page = get("/api/v1/jobs?format=table&limit=4&sort=-confidence&columns=id,class" +
                          (cursor.empty() ? "" : "&cursor=" + cursor));
    EXPECT_EQ(page["columns"], json({"id", "class"}));
    for (const auto id : ids_of(page["rows"])) walked.push_back(id);
    if (page["next"].is_null()) break;
    cursor = page["next"];
  }
  EXPECT_EQ(walked, ids_of(sorted["rows"]));
}

TEST_F(RunsApi, EveryBadParameterIsRefusedNamingIt) {
  const std::string other_sort = get("/api/v1/jobs?limit=1&sort=S")["next"];
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"colour=red", "colour"},
      {"class=a&class=b", "class"},
      {"sweep=0", "sweep"},
      {"sweep=x", "sweep"},
      {"point=-3", "point"},
      {"state=done", "state"},
      {"state=queued,", "state"},
      {"phi=abc", "phi"},
      {"phi=0x10", "phi"},
      {"S_min=1e-400", "S_min"},
      {"S_min=nan", "S_min"},
      {"R_max=", "R_max"},
      {"S_min=0.1&S_max=0.01", "S_max"},
      {"confidence_min=high", "confidence_min"},
      {"n_reflections_max=two", "n_reflections_max"},
      {"band_speed_ratio_min=1,2", "band_speed_ratio_min"},
      {"cells_per_unit=1", "cells_per_unit"},
      {"cells_per_unit=8.5", "cells_per_unit"},
      {"preset=slow", "preset"},
      {"geometry=cube", "geometry"},
      {"geometry=pseudo1d,", "geometry"},
      {"class=g", "class"},
      {"label=ab", "label"},
      {"human_label=yes", "human_label"},
      {"imported=1", "imported"},
      {"source=xyz", "source"},
      {"source=" + std::string(33, 'a'), "source"},
      {"q=", "q"},
      {"q=" + std::string(kMaxSearchBytes + 1, 'x'), "q"},
      {"q=a%0Ab", "q"},
      {"q=%FF", "q"},
      {"sort=cells_per_strut", "sort"},
      {"sort=colour", "sort"},
      {"sort=--id", "sort"},
      {"deflection_before_yield_min=x", "deflection_before_yield_min"},
      {"coherence_min=0.6&coherence_max=0.5", "coherence_max"},
      {"seed_min=1", "seed_min"},
      {"columns=S,colour", "columns"},
      {"columns=S,,R", "columns"},
      {"columns=S,S", "columns"},
      {"columns=S", "columns"},  // format=json: whole jobs
      {"format=json&columns=id", "columns"},
      {"limit=0", "limit"},
      {"limit=" + std::to_string(kMaxPageRows + 1), "limit"},
      {"format=csv&limit=" + std::to_string(kMaxCsvRows + 1), "limit"},
      {"offset=-1", "offset"},
      {"format=xml", "format"},
      {"cursor=abc", "cursor"},
      {"cursor=!!", "cursor"},
      {"cursor=" + other_sort, "cursor"},
      {"sort=S&cursor=" + other_sort + "&offset=2", "cursor"},
  };
  for (const auto& [query, field] : cases) {
    auto r = client->Get(("/api/v1/jobs?" + query).c_str());
    ASSERT_TRUE(r) << query;
    EXPECT_EQ(r->status, 422) << query << " " << r->body.substr(0, 300);
    EXPECT_EQ(json::parse(r->body)["error"]["field"], field) << query;
  }
  EXPECT_EQ(client->Get(("/api/v1/jobs?sort=S&cursor=" + other_sort).c_str())->status, 200);
}

TEST_F(RunsApi, TheListBeforeTheTableAnswersAsItDid) {
  const json page = get("/api/v1/jobs?sweep=" + std::to_string(filled.fast) + "&state=succeeded&phi=0.4&limit=2&offset=1");
  EXPECT_EQ(page["total"], 6);
  EXPECT_EQ(page["limit"], 2);
  EXPECT_EQ(page["offset"], 1);
  EXPECT_EQ(ids_of(page["jobs"]), (std::vector<std::int64_t>{2, 3}));
  const json& job = page["jobs"][0];
  // Each job as GET /jobs/{id} shows it, without what only that answer holds.
  json detail = get("/api/v1/jobs/2");
  detail["result"].erase("summary");
  for (const auto& [key, value] : job.items()) EXPECT_EQ(value, detail[key]) << key;
  for (const char* key : {"scene", "result", "human_label", "point_id", "cells_per_strut", "attempts"}) {
    EXPECT_TRUE(job.contains(key)) << key;
  }
  EXPECT_EQ(job["result"]["class"], "b");
  EXPECT_EQ(job["human_label"]["label"], "d");
  EXPECT_EQ(get("/api/v1/jobs")["limit"], kDefaultPageRows);
}

TEST_F(RunsApi, LimitsServeTheTablesRules) {
  const json l = get("/api/v1/limits");
  EXPECT_EQ(l["lists"]["max_limit"], kMaxPageRows);
  EXPECT_EQ(l["lists"]["default_limit"], kDefaultPageRows);
  EXPECT_EQ(l["jobs"]["max_csv_rows"], kMaxCsvRows);
  EXPECT_EQ(l["jobs"]["q_max_bytes"], kMaxSearchBytes);
  std::vector<std::string> columns, sortable;
  std::size_t ranged = 0;
  for (const RunColumn& c : run_columns()) {
    columns.push_back(c.name);
    if (c.sortable) sortable.push_back(c.name);
    ranged += c.ranged;
  }
  EXPECT_EQ(l["jobs"]["columns"], columns);
  EXPECT_EQ(l["jobs"]["sort"], sortable);
  // Every parameter it lists is read: an empty value is refused as a bad value of it.
  // 13 filters, NAME_min and NAME_max of the S, R, phi, confidence, N_r, c_b/V and feature
  // columns, and sort, limit, offset, cursor, format and columns.
  EXPECT_EQ(ranged, 26u);
  EXPECT_EQ(l["jobs"]["parameters"].size(), 13u + 2 * ranged + 6u);
  for (const json& p : l["jobs"]["parameters"]) {
    auto r = client->Get(("/api/v1/jobs?" + p.get<std::string>() + "=").c_str());
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 422) << p;
    EXPECT_EQ(json::parse(r->body)["error"]["field"], p);
  }
}
