// JSON form of the scene parameters (schema/scene.schema.json). Keys are the field names of
// SceneParams; enums are their lower-case names. Reading is strict: unknown keys, wrong types
// and non-finite numbers are errors that name the field.
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "compaction/params.hpp"

namespace compaction {

nlohmann::json to_json(const SceneParams& p);

// Reads the keys present in j over `p` (absent keys keep their value, but when j moves the scene
// to another geometry, the keys it leaves out that depend on the geometry take that geometry's
// defaults: scene_defaults). Returns every problem found, type errors and validate()'s range
// errors alike; p is meaningful only when empty.
std::vector<FieldError> from_json(const nlohmann::json& j, SceneParams& p);

// The same without validate(): unknown keys and wrong types only, for a caller that completes
// the scene (a sweep's numerics, each point's S, R and phi) before it validates it once.
std::vector<FieldError> read_json(const nlohmann::json& j, SceneParams& p);

}  // namespace compaction
