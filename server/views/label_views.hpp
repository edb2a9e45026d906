// The JSON of human labels, their audit and the provenance of imported sweeps and results (the
// REST API's and the exports' documents; views.hpp places them in jobs, sweeps and the map).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "store/label_store.hpp"
#include "store/store_reads.hpp"

namespace compaction::server::views {

// {"label", "reason", "by", "at"} or null.
nlohmann::json human_label(const std::optional<HumanLabel>& l);
// {"job_id", "action", "label", "previous_label", "classifier_label", "reason", "by", "at"}.
nlohmann::json label_change(const LabelChange& c);
nlohmann::json label_audit(const std::vector<LabelChange>& changes, std::int64_t total, int limit,
                           int offset);
// An imported result: {"database", "job", "imported_at"}; null for a result computed here.
nlohmann::json result_origin(const StoredResult& r);
// An imported sweep: {"database", "sweep"} and the import's provenance; null for a local sweep.
nlohmann::json sweep_origin(const SweepRecord& s);

}  // namespace compaction::server::views
