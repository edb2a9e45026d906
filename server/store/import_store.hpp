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
//  - a human label comes along when the job has none here (a label set here stays), marked
//    imported, with the importer's token and time beside what the source claims (who, when).
// Provenance that names this database is checked against it, never taken on trust: a sweep
// origin naming this database must be a sweep made here that holds every run of the file, and a
// run origin naming it must be that very job with its own result. A run of another database is
// here at most once: a second run claiming the same origin with another scene is refused.
// An import that would change nothing (the same file again) writes nothing; a refused one
// leaves no row and no file.
#pragma once

#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include "store/import_rows.hpp"
#include "store/store_db.hpp"

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
  std::vector<std::int64_t> filled_jobs;  // the jobs that were filled (their checkpoints go)
  bool changed() const {
    return sweep_created || added + filled + conflicts + linked + labels > 0;
  }
};

class ImportStore {
 public:
  explicit ImportStore(StoreDb& db) : db_(db) {}

  // This database's id (migration 0005), named as the source of its exports.
  std::string database_id();

  // A reader of one export file that checks it and hands each run to on_run as it is read (the
  // exchange's read_export(in, on_run), export_format.hpp).
  using FileReader = std::function<ExportFile(const RunSink& on_run)>;

  // Reads an export file with `read` and merges it: each run's files are written as the run is
  // read (unless its computation has a result here already) and its bytes released, then the
  // merge is one transaction; on any error nothing is stored and the files are removed. One
  // import at a time: a second waits, so imports sent in parallel cost one import's memory.
  // importer: the token that asked (tokens.hpp), for the labels.
  ImportOutcome import_file(const FileReader& read, const std::string& importer, Millis now);

  // Merges a file read in memory: writes the new results' artifact files (outside the write
  // lock), then merges in one transaction, as import_file does.
  ImportOutcome merge(ExportFile file, Millis now, const std::string& importer = "open");

  // The results of other servers that differ from a job's stored one (JSON text per row).
  std::vector<std::string> conflicts(std::int64_t job_id);

 private:
  struct Staging;
  ImportOutcome merge_staged(const ExportFile& f, Millis now, const std::string& importer,
                             Staging& staging);

  StoreDb& db_;
  std::mutex import_mutex_;
};

}  // namespace compaction::server
