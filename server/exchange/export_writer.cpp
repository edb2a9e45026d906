// The writing half of export_format.hpp: the file is written run by run as text (the artifacts'
// base64 make most of it), each run's object through nlohmann.
#include "compaction/result.hpp"
#include "exchange/base64.hpp"
#include "exchange/export_format.hpp"
#include "http/http_util.hpp"
#include "store/store.hpp"
#include "views/json_opt.hpp"
#include "views/label_views.hpp"

namespace compaction::server {

using nlohmann::json;

bool exported_artifact(const std::string& name, ExportArtifacts which) {
  if (which == ExportArtifacts::none) return false;
  const bool snapshot_npy = name.rfind("snapshot_", 0) == 0 && name.size() > 4 &&
                            name.compare(name.size() - 4, 4, ".npy") == 0;
  return !snapshot_npy;
}

namespace {

json run_json(const ExportSource& source, const ExportRun& e) {
  const JobRecord& j = e.job;
  const StoredResult& r = *j.result;
  // A run imported here keeps the database and job that computed it.
  const json origin = r.origin_database
                          ? json{{"database", *r.origin_database}, {"job", opt(r.origin_job)}}
                          : json{{"database", source.database}, {"job", j.id}};
  json artifacts = json::array();
  for (const Artifact& a : e.artifacts) {
    artifacts.push_back({{"name", a.name},
                         {"content_type", a.content_type},
                         {"size", a.data.size()},
                         {"data", base64_encode(a.data)}});
  }
  return {{"job_id", j.id},
          {"position", e.position},
          {"engine_version", j.engine_version},
          {"scene", json::parse(j.scene)},
          {"origin", origin},
          {"worker", r.worker},
          {"attempts", j.attempts},
          {"started_at", opt(j.started_at)},
          {"finished_at", opt(j.finished_at)},
          {"result",
           {{"status", r.status},
            {"reason", r.reason},
            {"class", opt(r.cls)},
            {"confidence", opt(r.confidence)},
            {"runner_up", opt(r.runner_up)},
            {"n_reflections", opt(r.n_reflections)},
            {"band_speed_ratio", opt(r.band_speed_ratio)},
            {"features", r.features ? json::parse(*r.features) : json(nullptr)},
            {"eps_reached", opt(r.eps_reached)},
            {"wall_seconds", opt(r.wall_seconds)},
            {"source_revision", r.source_revision},
            {"created_at", r.created_at}}},
          {"human_label", views::human_label(j.human_label)},
          {"summary", json::parse(e.summary)},
          {"artifacts", std::move(artifacts)},
          {"artifacts_left_out", e.left_out}};
}

}  // namespace

std::string write_export(const ExportSource& source, const SweepRecord& sweep,
                         const std::vector<ExportRun>& runs, std::int64_t jobs_without_result,
                         ExportArtifacts which) {
  // An imported sweep keeps the database and id it was first made as.
  const json origin = sweep.origin_database
                          ? json{{"database", *sweep.origin_database}, {"sweep", opt(sweep.origin_sweep)}}
                          : json{{"database", source.database}, {"sweep", sweep.id}};
  const json head = {
      {"format", kExportFormat},
      {"version", kExportVersion},
      {"exported_at", source.exported_at},
      {"source",
       {{"database", source.database},
        {"engine_version", source.engine_version},
        {"source_revision", source.source_revision},
        {"server", source.server}}},
      {"sweep",
       {{"id", sweep.id},
        {"name", sweep.name},
        {"request", json::parse(sweep.request)},
        {"priority", sweep.priority},
        {"created_at", sweep.created_at},
        {"origin", origin}}},
      {"jobs_without_result", jobs_without_result},
      {"artifacts_rule", which == ExportArtifacts::none
                             ? "no artifact: results, summaries, labels and provenance only"
                             : "every artifact of a run but its particle snapshots (snapshot_*.npy)"}};
  // The head's keys, then "runs" last (written as text: one run at a time).
  std::string out = json_text(head);
  out.pop_back();  // the closing brace
  out += ",\"runs\":[";
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (i > 0) out += ',';
    out += json_text(run_json(source, runs[i]));
  }
  out += "]}";
  return out;
}

std::optional<std::string> export_sweep(Store& store, std::int64_t sweep_id,
                                        const std::string& server, Millis now,
                                        ExportArtifacts which) {
  const auto sweep = store.reads.sweep(sweep_id);
  const auto jobs = store.reads.sweep_jobs(sweep_id);
  if (!sweep || !jobs) return std::nullopt;
  ExportSource source{store.imports.database_id(), compaction::engine_version(),
                      compaction::source_revision(), server, now};
  std::vector<ExportRun> runs;
  std::int64_t without_result = 0;
  std::int64_t position = 0;
  for (const JobRecord& j : *jobs) {
    const std::int64_t at = position++;
    if (!j.result) {
      ++without_result;
      continue;
    }
    ExportRun e;
    e.job = j;
    e.position = at;
    const auto detail = store.reads.job(j.id);
    if (!detail || !detail->summary) continue;  // results are never deleted: not reached
    e.summary = *detail->summary;
    for (const ArtifactInfo& a : store.reads.artifacts(j.id).value_or(std::vector<ArtifactInfo>{})) {
      if (!exported_artifact(a.name, which)) {
        e.left_out.push_back(a.name);
      } else if (auto bytes = store.reads.artifact(j.id, a.name)) {
        e.artifacts.push_back(std::move(*bytes));
      }
    }
    runs.push_back(std::move(e));
  }
  return write_export(source, *sweep, runs, without_result, which);
}

}  // namespace compaction::server
