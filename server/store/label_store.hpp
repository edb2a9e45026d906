// Labels set by a person beside the classifier's: the current human label of a job (table
// human_labels) and the audit of every change (label_audit, never deleted), migration 0006.
// The classifier's label stays in results.class; where both exist, the human's is the one the
// map colours and the adaptive planner reads (docs/service.md, "Human labels").
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "store/store_db.hpp"

namespace compaction::server {

// The rules of a human label, served by GET /api/v1/limits (the dashboard's form checks them).
inline constexpr std::size_t kLabelReasonMaxBytes = 2000;
inline constexpr std::size_t kLabelByMaxBytes = 200;

struct HumanLabel {
  std::string label;   // "a".."f"
  std::string reason;  // why, 1 to kLabelReasonMaxBytes
  std::string by;      // who, 1 to kLabelByMaxBytes (an imported label: who the source says)
  Millis at = 0;       // when (an imported label: when the source says)
  // The token of the request that set it here (tokens.hpp: "open", "submit", "submit:NAME");
  // empty for a label read from an export file, and for labels set before migration 0010.
  std::string token;
  std::optional<Millis> imported_at;  // when an import brought it here
};

struct LabelChange {
  std::int64_t id = 0, job_id = 0;
  std::string action;  // "set", "cleared" or "imported"
  std::optional<std::string> label, previous_label, classifier_label;
  std::string reason;
  std::string by;      // who: a person's name; for "imported", the importer's token
  Millis at = 0;
  std::optional<std::string> token;       // the request's token (NULL before migration 0010)
  std::optional<std::string> claimed_by;  // "imported": the source's person and time
  std::optional<Millis> claimed_at;
};

enum class LabelOutcome {
  ok,
  unknown_job,  // no such job
  no_result,    // the job has no result yet: there is nothing to disagree with
  not_labelled, // a clear of a job without a human label
};

class LabelStore {
 public:
  explicit LabelStore(StoreDb& db) : db_(db) {}

  // Sets (or replaces) the job's human label and logs the change.
  LabelOutcome set(std::int64_t job_id, const HumanLabel& label);
  // Removes the job's human label (the classifier's is the job's label again) and logs who did.
  LabelOutcome clear(std::int64_t job_id, const std::string& reason, const std::string& by,
                     const std::string& token, Millis now);
  // The changes, newest first: of one job, or of every job.
  std::vector<LabelChange> audit(std::optional<std::int64_t> job_id, int limit, int offset,
                                 std::int64_t& total);

  // Inside the caller's write transaction (an import): sets the label when the job has none and
  // logs it as 'imported' by the importer's token at `now`, with the source's by and at as its
  // claim; returns whether it did.
  static bool import_label(sqlite::Database& writer, std::int64_t job_id, const HumanLabel& label,
                           const std::string& note, const std::string& importer, Millis now);

 private:
  StoreDb& db_;
};

}  // namespace compaction::server
