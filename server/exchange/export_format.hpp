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

#include "store/import_rows.hpp"
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
// The file read: the rows of store/import_rows.hpp (ExportFile, ImportedRun, RunSink).

// Checks the whole file; throws ApiError(422, field, message) at the first problem, the field
// named as in the file ("runs[3].summary.params.S", "runs[0].artifacts[2].data"). Runs are read
// one at a time and handed to on_run as each is checked (the file's head is read first, in a
// pass of its own: `in` is read twice, from its start); a file costs about one run's document at
// a time, plus what on_run keeps.
ExportFile read_export(std::FILE* in, const RunSink& on_run);

// The same for a file in memory, every run kept in ExportFile::runs.
ExportFile read_export(const std::string& text);

}  // namespace compaction::server
