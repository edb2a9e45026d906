// The reading half of export_format.hpp: every part of a file checked before anything is
// merged. A run's scene must be the canonical scene the server hashes (so the identity it is
// recognised by is the one its computing server had), its summary passes the checks of a
// worker's upload (result_intake.hpp) against that scene and engine version, the file's result
// must be what the summary says, and each artifact's base64 must decode to its size.
#include <set>

#include "api_error.hpp"
#include "base64.hpp"
#include "export_format.hpp"
#include "json_input.hpp"
#include "compaction/params_json.hpp"
#include "planner.hpp"
#include "result_intake.hpp"
#include "safe_text.hpp"

namespace compaction::server {

using nlohmann::json;

namespace {

[[noreturn]] void invalid(const std::string& field, const std::string& message) {
  throw ApiError(422, field, message);
}

const json& member(const json& obj, const std::string& path, const char* key) {
  if (!obj.is_object()) invalid(path, "must be an object");
  if (!obj.contains(key)) invalid(path + "." + key, "is required");
  return obj[key];
}

std::string field(const std::string& path, const char* key) {
  return path.empty() ? std::string(key) : path + "." + key;
}

std::int64_t integer(const json& obj, const std::string& path, const char* key, std::int64_t lo,
                     std::int64_t hi) {
  const json& v = member(obj, path, key);
  if (!v.is_number_integer() || v.get<std::int64_t>() < lo || v.get<std::int64_t>() > hi) {
    invalid(field(path, key), "must be an integer in [" + std::to_string(lo) + ", " +
                                  std::to_string(hi) + "], got " + describe(v));
  }
  return v.get<std::int64_t>();
}

std::optional<std::int64_t> optional_time(const json& obj, const std::string& path, const char* key) {
  if (!obj.contains(key) || obj[key].is_null()) return std::nullopt;
  return integer(obj, path, key, 0, std::int64_t(1) << 52);
}

Millis time_ms(const json& obj, const std::string& path, const char* key) {
  return integer(obj, path, key, 0, std::int64_t(1) << 52);
}

std::string text(const json& obj, const std::string& path, const char* key, std::size_t max_len,
                 bool name = true) {
  const json& v = member(obj, path, key);
  if (!v.is_string()) invalid(field(path, key), "must be a string, got " + describe(v));
  const std::string s = v.get<std::string>();
  if (s.empty() || s.size() > max_len) {
    invalid(field(path, key), "must be 1 to " + std::to_string(max_len) + " bytes");
  }
  if (name && has_control_characters(s)) invalid(field(path, key), "must not hold control characters");
  return s;
}

std::string database_id(const json& obj, const std::string& path, const char* key) {
  const std::string s = text(obj, path, key, 32);
  if (s.size() != 32 || s.find_first_not_of("0123456789abcdef") != std::string::npos) {
    invalid(field(path, key), "must be a database id: 32 lower-case hex digits");
  }
  return s;
}

std::optional<HumanLabel> read_human_label(const json& run, const std::string& path) {
  if (!run.contains("human_label") || run["human_label"].is_null()) return std::nullopt;
  const std::string p = path + ".human_label";
  const json& h = run["human_label"];
  if (!h.is_object()) invalid(p, "must be an object or null");
  HumanLabel l;
  l.label = text(h, p, "label", 1);
  if (std::string("abcdef").find(l.label) == std::string::npos) {
    invalid(p + ".label", "must be one of a, b, c, d, e, f");
  }
  l.reason = text(h, p, "reason", kLabelReasonMaxBytes, false);
  l.by = text(h, p, "by", kLabelByMaxBytes);
  l.at = time_ms(h, p, "at");
  return l;
}

std::vector<UploadedFile> read_artifacts(const json& run, const std::string& path) {
  const json& list = member(run, path, "artifacts");
  const std::string p = path + ".artifacts";
  if (!list.is_array()) invalid(p, "must be an array");
  if (list.size() > max_artifacts) {
    invalid(p, "at most " + std::to_string(max_artifacts) + " artifacts per run");
  }
  std::vector<UploadedFile> files;
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string a = p + "[" + std::to_string(k) + "]";
    const std::string name = text(list[k], a, "name", 100);
    const std::int64_t size = integer(list[k], a, "size", 0, std::int64_t(1) << 40);
    const json& data = member(list[k], a, "data");
    if (!data.is_string()) invalid(a + ".data", "must be a base64 string");
    auto bytes = base64_decode(data.get_ref<const std::string&>());
    if (!bytes) invalid(a + ".data", "is not canonical base64");
    if (static_cast<std::int64_t>(bytes->size()) != size) {
      invalid(a + ".data", "decodes to " + std::to_string(bytes->size()) + " bytes, size says " +
                               std::to_string(size));
    }
    files.push_back({name, std::move(*bytes)});
  }
  return files;
}

// The file's "result" must say what the summary says (a file edited by hand, or cut and
// mended, does not merge).
void check_result(const json& run, const std::string& path, const ResultRecord& r) {
  const json& given = member(run, path, "result");
  const std::string p = path + ".result";
  auto o = [](const auto& v) { return v ? json(*v) : json(nullptr); };
  const std::pair<const char*, json> derived[] = {
      {"status", r.status},
      {"class", o(r.cls)},
      {"confidence", o(r.confidence)},
      {"runner_up", o(r.runner_up)},
      {"n_reflections", o(r.n_reflections)},
      {"band_speed_ratio", o(r.band_speed_ratio)},
      {"source_revision", r.source_revision}};
  for (const auto& [key, value] : derived) {
    const json& g = member(given, p, key);
    if (g != value) invalid(p + "." + key, "does not match the run's summary (" + describe(g) + ")");
  }
}

ImportedRun read_run(const json& run, const std::string& path, const std::string& source_database) {
  if (!run.is_object()) invalid(path, "must be an object");
  ImportedRun out;
  out.source_job = integer(run, path, "job_id", 1, std::int64_t(1) << 62);
  out.position = integer(run, path, "position", 0, std::int64_t(1) << 40);
  out.engine_version = text(run, path, "engine_version", 100);

  const json& scene = member(run, path, "scene");
  SceneParams p;
  if (const auto errors = compaction::from_json(scene, p); !errors.empty()) {
    invalid(path + ".scene." + errors.front().field, errors.front().message);
  }
  const std::string canonical = canonical_scene(p);
  if (canonical != scene.dump()) {
    invalid(path + ".scene", "is not the canonical scene of its parameters (made by another "
                             "version of the scene format?)");
  }
  out.job = job_row(p, out.engine_version);

  const json& origin = member(run, path, "origin");
  out.origin_database = database_id(origin, path + ".origin", "database");
  out.origin_job = integer(origin, path + ".origin", "job", 1, std::int64_t(1) << 62);
  if (out.origin_database == source_database && out.origin_job != out.source_job) {
    invalid(path + ".origin.job", "a run computed by the exporting database is its own job");
  }
  out.worker = text(run, path, "worker", 200);
  out.attempts = integer(run, path, "attempts", 0, 100);
  out.started_at = optional_time(run, path, "started_at");
  out.finished_at = optional_time(run, path, "finished_at");

  const json& summary = member(run, path, "summary");
  if (!summary.is_object()) invalid(path + ".summary", "must be an object");
  std::vector<UploadedFile> files = read_artifacts(run, path);
  try {
    out.result = intake_result(summary.dump(), canonical, out.engine_version, std::move(files));
  } catch (const ApiError& e) {
    // The upload's checks name "summary.x" and "files[name]"; here they are the run's parts.
    const std::string f = e.field.rfind("files", 0) == 0 ? "artifacts" + e.field.substr(5) : e.field;
    invalid(path + "." + f, e.what());
  }
  check_result(run, path, out.result);
  out.result_created_at = time_ms(member(run, path, "result"), path + ".result", "created_at");
  out.human_label = read_human_label(run, path);
  return out;
}

}  // namespace

ExportFile read_export(const std::string& file_text) {
  const json doc = parse_client_json(file_text, "file", 422);
  if (!doc.is_object()) invalid("file", "must be a JSON object (an export of compaction-server)");
  if (!doc.contains("format") || doc["format"] != kExportFormat) {
    invalid("format", std::string("must be \"") + kExportFormat + "\"");
  }
  ExportFile f;
  f.version = static_cast<int>(integer(doc, "", "version", 1, 1000));
  if (f.version != kExportVersion) {
    invalid("version", "this server reads version " + std::to_string(kExportVersion) +
                           ", the file is version " + std::to_string(f.version));
  }
  f.exported_at = time_ms(doc, "", "exported_at");
  const json& source = member(doc, "", "source");
  f.source_database = database_id(source, "source", "database");
  text(source, "source", "engine_version", 100);
  text(source, "source", "source_revision", 200);
  f.source = source.dump();

  const json& sweep = member(doc, "", "sweep");
  f.sweep.source_id = integer(sweep, "sweep", "id", 1, std::int64_t(1) << 62);
  f.sweep.name = text(sweep, "sweep", "name", kMaxNameBytes);
  const json& request = member(sweep, "sweep", "request");
  if (!request.is_object()) invalid("sweep.request", "must be an object (the accepted request)");
  f.sweep.request = request.dump();
  f.sweep.priority = static_cast<int>(integer(sweep, "sweep", "priority", kPriorityMin, kPriorityMax));
  f.sweep.created_at = time_ms(sweep, "sweep", "created_at");
  const json& origin = member(sweep, "sweep", "origin");
  f.sweep.origin_database = database_id(origin, "sweep.origin", "database");
  f.sweep.origin_sweep = integer(origin, "sweep.origin", "sweep", 1, std::int64_t(1) << 62);

  const json& runs = member(doc, "", "runs");
  if (!runs.is_array()) invalid("runs", "must be an array");
  std::set<std::string> identities;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const std::string path = "runs[" + std::to_string(i) + "]";
    ImportedRun r = read_run(runs[i], path, f.source_database);
    if (!identities.insert(r.job.identity).second) {
      invalid(path + ".scene", "the same computation (scene and engine version) appears twice");
    }
    f.runs.push_back(std::move(r));
  }
  return f;
}

}  // namespace compaction::server
