// schema/scene.schema.json mirrors SceneParams: the same keys as compaction::to_json, the same
// defaults, and its ranges agree with compaction::validate() at their ends.
#include <gtest/gtest.h>

#include <fstream>
#include <vector>

#include "compaction/params_json.hpp"

using nlohmann::json;

namespace {
json schema() {
  std::ifstream f(COMPACTION_SOURCE_DIR "/schema/scene.schema.json");
  return json::parse(f);
}
}  // namespace

TEST(SceneSchema, HasExactlyTheKeysOfSceneParams) {
  const json props = schema()["properties"];
  const json params = compaction::to_json(compaction::SceneParams{});
  for (const auto& [key, value] : params.items()) EXPECT_TRUE(props.contains(key)) << key;
  for (const auto& [key, value] : props.items()) EXPECT_TRUE(params.contains(key)) << key;
}

TEST(SceneSchema, DefaultsAreTheEnginesDefaults) {
  const json props = schema()["properties"];
  compaction::SceneParams d;
  json params = compaction::to_json(d);
  params["eps_end"] = d.eps_end;  // to_json writes eps_final(); the default is "fully dense"
  for (const auto& [key, value] : params.items()) {
    ASSERT_TRUE(props[key].contains("default")) << key;
    EXPECT_EQ(props[key]["default"], value) << key;
  }
}

TEST(SceneSchema, NumericBoundsAgreeWithValidate) {
  const json props = schema()["properties"];
  for (const auto& [key, p] : props.items()) {
    // A key's bounds, or those of each branch of its oneOf (cells_per_unit: 0, or a range).
    std::vector<json> ranges = {p};
    for (const json& branch : p.value("oneOf", json::array())) ranges.push_back(branch);
    for (const json& r : ranges) {
      for (const char* bound : {"minimum", "maximum"}) {
        if (!r.contains(bound) || key == "snapshot_eps") continue;
        compaction::SceneParams s;
        json j = {{key, r[bound]}};
        // Two cells per unit (one across the strut) resolve hole and strut only where both are
        // half the cell, phi = 0.75; there, too, the finest strut stays within 200 cells per unit.
        if (key == "cells_per_unit" || key == "cells_per_strut") j["phi"] = 0.75;
        // A movie frame falls on an output frame (movie_d_eps >= d_eps): each bound of one with
        // the other at a value that leaves it free.
        if (key == "movie_d_eps") j["d_eps"] = 0.001;
        if (key == "d_eps") j["movie_d_eps"] = 0.1;
        EXPECT_TRUE(compaction::from_json(j, s).empty()) << key << " at its " << bound;
      }
      if (r.contains("const")) {
        compaction::SceneParams s;
        EXPECT_TRUE(compaction::from_json({{key, r["const"]}}, s).empty()) << key << " = const";
      }
    }
    for (const char* bound : {"exclusiveMinimum", "exclusiveMaximum"}) {
      if (!p.contains(bound)) continue;
      compaction::SceneParams s;
      json j = {{key, p[bound]}};
      EXPECT_FALSE(compaction::from_json(j, s).empty()) << key << " at its " << bound;
    }
  }
}
