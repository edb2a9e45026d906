#include "exchange/result_intake.hpp"

#include <cmath>

#include "compaction/bundle_check.hpp"
#include "compaction/params_json.hpp"
#include "exchange/summary_schema.hpp"
#include "input/api_error.hpp"
#include "input/json_input.hpp"
#include "input/safe_text.hpp"
#include "plan/planner.hpp"

namespace compaction::server {

using nlohmann::json;

namespace {

[[noreturn]] void invalid(const std::string& field, const std::string& message) {
  throw ApiError(422, field, message);
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::optional<double> optional_number(const json& obj, const char* key, const std::string& field) {
  if (!obj.contains(key) || obj[key].is_null()) return std::nullopt;
  const json& v = obj[key];
  if (!v.is_number() || !std::isfinite(v.get<double>())) {
    invalid(field + "." + key, "must be a finite number or null, got " + describe(v));
  }
  return v.get<double>();
}

std::string required_string(const json& obj, const char* key, const std::string& field) {
  if (!obj.contains(key) || !obj[key].is_string()) {
    invalid(field + "." + key, "must be a string");
  }
  return obj[key].get<std::string>();
}

// The classifier's verdict (issue 3): stored when present, null columns otherwise.
void read_classification(const json& summary, ResultRecord& r) {
  if (!summary.contains("classification") || summary["classification"].is_null()) return;
  const json& c = summary["classification"];
  const std::string f = "summary.classification";
  if (!c.is_object()) invalid(f, "must be an object or null");
  if (c.contains("class") && !c["class"].is_null()) {
    const json& k = c["class"];
    if (!k.is_string() || k.get<std::string>().size() != 1 ||
        std::string("abcdef").find(k.get<std::string>()) == std::string::npos) {
      invalid(f + ".class", "must be one of a, b, c, d, e, f, got " + describe(k));
    }
    r.cls = k.get<std::string>();
  }
  r.confidence = optional_number(c, "confidence", f);
  if (r.confidence && (*r.confidence < 0.0 || *r.confidence > 1.0)) {
    invalid(f + ".confidence", "must be in [0, 1]");
  }
  if (c.contains("runner_up") && !c["runner_up"].is_null()) {
    if (!c["runner_up"].is_string()) invalid(f + ".runner_up", "must be a string or null");
    r.runner_up = c["runner_up"].get<std::string>();
  }
  if (c.contains("n_reflections") && !c["n_reflections"].is_null()) {
    if (!c["n_reflections"].is_number_integer() || c["n_reflections"].get<long long>() < 0) {
      invalid(f + ".n_reflections", "must be a non-negative integer or null");
    }
    r.n_reflections = c["n_reflections"].get<std::int64_t>();
  }
  r.band_speed_ratio = optional_number(c, "band_speed_ratio", f);
  if (c.contains("features") && !c["features"].is_null()) {
    if (!c["features"].is_object()) invalid(f + ".features", "must be an object or null");
    r.features = c["features"].dump();
  }
}

}  // namespace

bool valid_artifact_name(const std::string& name) {
  if (name.empty() || name.size() > 100 || name.front() == '.') return false;
  for (char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '-' || c == '.';
    if (!ok) return false;
  }
  return ends_with(name, ".npy") || ends_with(name, ".png") || ends_with(name, ".csv") ||
         ends_with(name, ".json") || ends_with(name, ".bin");
}

std::string artifact_content_type(const std::string& name) {
  if (ends_with(name, ".png")) return "image/png";
  if (ends_with(name, ".csv")) return "text/csv";
  if (ends_with(name, ".json")) return "application/json";
  return "application/octet-stream";  // .npy, .bin (movie.bin)
}

ResultRecord intake_result(const std::string& summary_text, const std::string& job_scene,
                           const std::string& job_engine_version, std::vector<UploadedFile> files) {
  json summary = parse_client_json(summary_text, "summary", 422);
  if (!summary.is_object()) {
    invalid("summary", "must be a JSON object (the bundle's summary.json)");
  }
  if (const auto problem = check_summary_schema(summary)) {
    invalid(problem->field.empty() ? "summary" : "summary." + problem->field, problem->message);
  }
  ResultRecord r;
  r.summary = summary.dump();

  const std::string status = summary["status"].get<std::string>();
  if (status == "cancelled") {
    invalid("summary.status", "a cancelled run is not a result; release or fail the job instead");
  }
  if (status != "ok" && status != "unstable") {
    invalid("summary.status", "must be \"ok\" or \"unstable\"");
  }
  r.status = status;
  if (summary.contains("reason") && !summary["reason"].is_null()) {
    if (!summary["reason"].is_string()) invalid("summary.reason", "must be a string");
    r.reason = summary["reason"].get<std::string>();
  }
  if (status == "unstable" && r.reason.empty()) {
    invalid("summary.reason", "an unstable run must say why");
  }

  if (!summary.contains("params")) invalid("summary.params", "is required");
  SceneParams p;
  const auto errors = compaction::from_json(summary["params"], p);
  if (!errors.empty()) {
    invalid("summary.params." + errors.front().field, errors.front().message);
  }
  // The job's scene as this engine reads it: a scene queued before a key existed (movie_d_eps)
  // stands for the same run with that key's default.
  SceneParams queued;
  const json job_json = json::parse(job_scene, nullptr, false);
  const bool readable = !job_json.is_discarded() && compaction::from_json(job_json, queued).empty();
  if (canonical_scene(p) != (readable ? canonical_scene(queued) : job_scene)) {
    invalid("summary.params", "do not match the parameters of the leased job");
  }
  r.scene = job_scene;
  r.engine_version = required_string(summary, "engine_version", "summary");
  if (r.engine_version != job_engine_version) {
    invalid("summary.engine_version", "the job was queued for engine " + job_engine_version +
                                          ", the run used " + r.engine_version);
  }
  r.source_revision = required_string(summary, "source_revision", "summary");
  r.eps_reached = optional_number(summary, "eps_reached", "summary");
  r.wall_seconds = optional_number(summary, "wall_seconds", "summary");
  read_classification(summary, r);

  if (files.size() > max_artifacts) {
    invalid("files", "at most " + std::to_string(max_artifacts) + " files per result");
  }
  for (auto& f : files) {
    if (!valid_artifact_name(f.name)) {
      invalid("files[" + valid_utf8(f.name.substr(0, 100)) + "]",
              "artifact names are letters, digits, '_', '-', '.' ending in .npy, .png, .csv, "
              ".json or .bin");
    }
    for (const auto& a : r.artifacts) {
      if (a.name == f.name) invalid("files[" + f.name + "]", "appears twice");
    }
    if (const auto problem = compaction::bundle_file_problem(f.name, f.data)) {
      invalid("files[" + f.name + "]", *problem);
    }
    // The bundle's summary.json, when it comes as a file too, is the summary above.
    if (f.name == "summary.json" && json::parse(f.data) != summary) {
      invalid("files[summary.json]", "differs from the summary field");
    }
    r.artifacts.push_back({f.name, artifact_content_type(f.name), std::move(f.data), std::nullopt});
  }
  return r;
}

}  // namespace compaction::server
