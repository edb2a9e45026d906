// An export file as the import store merges it (import_store.hpp): the sweep and its runs, each
// with its scene, result, artifacts, human label and provenance. The exchange's reader
// (exchange/export_format.hpp: read_export) checks a file and turns it into these rows.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "store/label_store.hpp"
#include "store/queue_store.hpp"
#include "store/sweep_store.hpp"

namespace compaction::server {

struct ImportedRun {
  std::int64_t source_job = 0;        // the job's id in the exporting database
  std::int64_t position = 0;          // its place in the sweep
  NewJob job;                         // identity (engine version + canonical scene), scene, S, R...
  std::string engine_version;
  std::string origin_database;        // the database that computed it
  std::int64_t origin_job = 0;        // and the job's id there
  std::string worker;
  std::int64_t attempts = 0;
  std::optional<Millis> started_at, finished_at;
  Millis result_created_at = 0;       // when the computing server stored the result
  ResultRecord result;                // from the summary, with the artifacts' bytes
  std::optional<HumanLabel> human_label;
  // Set by the importer when it has written the artifacts (result.artifacts then keep their
  // names and types, their bytes released): the folder below the artifact root and each file's
  // path, in the order of result.artifacts.
  std::string staged_folder;
  std::vector<std::string> staged_paths;
};

struct ImportedSweep {
  std::int64_t source_id = 0;         // its id in the exporting database
  std::string name, request;          // request: JSON text
  int priority = 0;
  Millis created_at = 0;
  std::string origin_database;        // the database it was first made in
  std::int64_t origin_sweep = 0;      // and its id there
};

struct ExportFile {
  int version = 0;
  Millis exported_at = 0;
  std::string source_database;
  std::string source;                 // the "source" object (JSON text), kept as provenance
  ImportedSweep sweep;
  std::vector<ImportedRun> runs;  // read_export(text) keeps them here; the streaming reader hands
                                  // each to its sink instead
  std::size_t run_count = 0;      // runs in the file
};

// Where a streaming reader hands each run as it has checked it.
using RunSink = std::function<void(ImportedRun&)>;

}  // namespace compaction::server
