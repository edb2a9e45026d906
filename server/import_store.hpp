// Merges another server's export (export_format.hpp) into this database in one transaction:
// the sweep (one local sweep per source sweep, marked imported), each run as a job with its
// result and artifacts, and the runs' human labels. The rule (docs/service.md, "Merging maps"):
//  - a run is recognised by its identity, engine version + canonical scene, as the queue
//    recognises identical parameters;
//  - no job of that identity here: a new succeeded job with the imported result;
//  - a job without a result (queued, running, failed, cancelled): it takes the imported result
//    (a running job's lease is lost: its worker hears 409 and stops);
//  - a job with a result that says the same (status, reason, class, confidence, runner-up,
//    N_r, c_b/V, features, eps reached; worker, times and wall time may differ): identical,
//    nothing is added;
//  - a job with a result that differs: the stored result stays (a result is never
//    overwritten), the imported one is kept in result_conflicts with its provenance, once per
//    source run;
//  - a human label comes along when the job has none here (a label set here stays).
// An import that would change nothing (the same file again) writes nothing.
#pragma once

#include <cstdint>
#include <string>

#include "export_format.hpp"
#include "store_db.hpp"

namespace compaction::server {

struct ImportOutcome {
  std::int64_t sweep_id = 0;
  bool sweep_created = false;
  std::int64_t runs = 0;             // runs in the file
  std::int64_t added = 0;            // new jobs
  std::int64_t filled = 0;           // jobs here without a result that took the imported one
  std::int64_t identical = 0;        // the same result was here already
  std::int64_t conflicts = 0;        // a different result was here: kept beside it
  std::int64_t conflicts_known = 0;  // that conflict was recorded by an earlier import
  std::int64_t linked = 0;           // jobs newly linked to the sweep
  std::int64_t labels = 0;           // human labels brought along
  bool changed() const {
    return sweep_created || added + filled + conflicts + linked + labels > 0;
  }
};

class ImportStore {
 public:
  explicit ImportStore(StoreDb& db) : db_(db) {}

  // This database's id (migration 0005), named as the source of its exports.
  std::string database_id();

  // Writes the new results' artifact files (outside the write lock), then merges in one
  // transaction; on any error nothing is stored and the files are removed.
  ImportOutcome merge(const ExportFile& file, Millis now);

  // The results of other servers that differ from a job's stored one (JSON text per row).
  std::vector<std::string> conflicts(std::int64_t job_id);

 private:
  StoreDb& db_;
};

}  // namespace compaction::server
