// schema/summary.schema.json, compiled into the server: the types and ranges of every field of a
// run's summary.json, checked on each worker's upload and each imported run before the checks
// against the job (result_intake.hpp).
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace compaction::server {

struct SchemaProblem {
  std::string field;    // as in the document: "classification.confidence", "" for the root
  std::string message;  // what the schema asks there
};

// The first problem of `summary` against the schema (the most specific one: the deepest field),
// or nothing.
std::optional<SchemaProblem> check_summary_schema(const nlohmann::json& summary);

}  // namespace compaction::server
