// schema/summary.schema.json accepts what the engine writes and what the committed exports
// carry (summaries of earlier engine versions among them), and names the field it refuses.
#include "exchange/summary_schema.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "compaction/bundle.hpp"

using nlohmann::json;
using compaction::server::check_summary_schema;

TEST(SummarySchema, AcceptsTheEnginesSummary) {
  compaction::SceneParams p;
  compaction::RunResult r;
  r.eps_reached = 0.3;
  EXPECT_FALSE(check_summary_schema(compaction::summary_json(p, r)));
}

TEST(SummarySchema, AcceptsEverySummaryOfTheCommittedExports) {
  int files = 0, runs = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(COMPACTION_SOURCE_DIR "/studies")) {
    const std::string name = entry.path().filename().string();
    if (name.size() < 12 || name.substr(name.size() - 12) != ".export.json") continue;
    ++files;
    std::ifstream in(entry.path());
    const json file = json::parse(in);
    for (const json& run : file["runs"]) {
      ++runs;
      const auto problem = check_summary_schema(run["summary"]);
      EXPECT_FALSE(problem) << entry.path() << " job " << run["job_id"] << ": " << problem->field
                            << ": " << problem->message;
    }
  }
  EXPECT_GE(files, 3);
  EXPECT_GE(runs, 300) << "the committed maps";
}

TEST(SummarySchema, NamesTheDeepestFieldItRefuses) {
  json s = compaction::summary_json(compaction::SceneParams{}, compaction::RunResult{});
  s["classification"] = {{"class", "b"}, {"features", {{"scores", {{"a", -1}}}}}};
  const auto problem = check_summary_schema(s);
  ASSERT_TRUE(problem);
  EXPECT_EQ(problem->field, "classification.features.scores.a");
  s.erase("classification");
  s.erase("engine_version");
  EXPECT_EQ(check_summary_schema(s)->field, "engine_version");
}
