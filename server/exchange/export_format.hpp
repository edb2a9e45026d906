// The export file of a sweep (schema/sweep-export.md): the results of one sweep with their
// scenes, provenance, human labels and the artifacts the map and the run page need, that
// another server imports (compaction-server --import FILE, or
// POST /api/v1/imports) into its own database. The writer makes the file from the store's
// records; the reader checks a whole file and turns it into the rows the import store merges.
#pragma once

#include <cstdint>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "store/label_store.hpp"
#include "store/queue_store.hpp"
#include "store/store_reads.hpp"
#include "store/sweep_store.hpp"

namespace compaction::server {

inline constexpr const char* kExportFormat = "compaction-sweep-export";
inline constexpr int kExportVersion = 1;

// Which artifacts an export carries (GET /sweeps/{id}/export?format=archive&artifacts=...).
enum class ExportArtifacts {
  // "run_page": all but the particle snapshots (snapshot_*.npy, 20 bytes a particle and frame,
  // the largest files of a bundle, which neither the map nor the run page reads; the run page
  // shows the snapshots' PNGs). About 2.5 MB a run at the default preset.
  run_page,
  // "none": no file, the results, summaries, labels and provenance only: all the phase map
  // needs, a few kB a run, small enough to commit a whole map.
  none,
};
bool exported_artifact(const std::string& name, ExportArtifacts which);

// --- writing ---

// The exporting server.
struct ExportSource {
  std::string database;  // this database's id (database_identity)
  std::string engine_version, source_revision;
  std::string server;    // the address the export was asked at (the Host header)
  Millis exported_at = 0;
};

// One succeeded job of the sweep, with what the file carries of it.
struct ExportRun {
  JobRecord job;           // with its result and human label
  std::int64_t position = 0;
  std::string summary;     // summary.json as stored
  std::vector<Artifact> artifacts;         // the exported ones, with their bytes
  std::vector<std::string> left_out;       // names of the artifacts not carried
};

struct Store;

// The export of a sweep of the store (its succeeded jobs, their summaries and the exported
// artifacts); nullopt for an unknown sweep. server: the address the export was asked at.
std::optional<std::string> export_sweep(Store& store, std::int64_t sweep_id,
                                        const std::string& server, Millis now,
                                        ExportArtifacts which = ExportArtifacts::run_page);

// The file's text. jobs_without_result counts the sweep's jobs not exported (queued, running,
// failed, cancelled: nothing to merge).
std::string write_export(const ExportSource& source, const SweepRecord& sweep,
                         const std::vector<ExportRun>& runs, std::int64_t jobs_without_result,
                         ExportArtifacts which = ExportArtifacts::run_page);

// --- reading ---

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

// Checks the whole file; throws ApiError(422, field, message) at the first problem, the field
// named as in the file ("runs[3].summary.params.S", "runs[0].artifacts[2].data"). Runs are read
// one at a time and handed to on_run as each is checked (the file's head is read first, in a
// pass of its own: `in` is read twice, from its start); a file costs about one run's document at
// a time, plus what on_run keeps.
using RunSink = std::function<void(ImportedRun&)>;
ExportFile read_export(std::FILE* in, const RunSink& on_run);

// The same for a file in memory, every run kept in ExportFile::runs.
ExportFile read_export(const std::string& text);

}  // namespace compaction::server
