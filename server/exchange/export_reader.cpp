// The reading half of export_format.hpp: every part of a file checked before anything is
// merged. A run's scene must be the canonical scene the server hashes (so the identity it is
// recognised by is the one its computing server had), its summary passes the checks of a
// worker's upload (result_intake.hpp) against that scene and engine version, the file's result
// must be what the summary says, and each artifact's base64 must decode to its size.
//
// The file is read as a stream of JSON events (nlohmann's SAX interface) in two passes: the
// first builds the small members (format, version, source, sweep) and skips the runs, the second
// builds one run at a time, checks it and hands it on. So a file costs about one run's document
// at a time (plus what the caller keeps of each run), never a document of the whole file, and
// every document built has a budget of values: a file of millions of empty objects is refused at
// its first run instead of filling memory.
#include <cstdio>
#include <limits>
#include <set>
#include <utility>

#include "compaction/params_json.hpp"
#include "exchange/base64.hpp"
#include "exchange/export_format.hpp"
#include "exchange/result_intake.hpp"
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
  const auto i = as_int64(v);
  if (!i || *i < lo || *i > hi) {
    invalid(field(path, key), "must be an integer in [" + std::to_string(lo) + ", " +
                                  std::to_string(hi) + "], got " + describe(v));
  }
  return *i;
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
  if (has_control_characters(l.reason, true)) {
    invalid(p + ".reason", "must be UTF-8 text without control characters but newlines and tabs");
  }
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

namespace {

// Values a document of the file may hold: a sweep's request (2 000 points of 4 values), a run
// (its summary's features, a few hundred values, and its artifacts); and the bytes of the text
// in a member of the head (a run's text is its artifacts': the body's limit bounds it).
constexpr std::size_t kMaxMemberValues = 100'000;
constexpr std::size_t kMaxRunValues = 100'000;
constexpr std::size_t kMaxMemberTextBytes = 2 << 20;
constexpr std::size_t kNoTextLimit = std::numeric_limits<std::size_t>::max();
// A sweep's request as accepted here: the body limit of POST /api/v1/sweeps.
constexpr std::size_t kMaxRequestBytes = 1 << 20;

// One JSON document built from SAX events, refused beyond a number of values or a depth.
class Builder {
 public:
  Builder(std::string field, std::size_t max_values, std::size_t max_text, int outer_depth)
      : field_(std::move(field)), max_values_(max_values), max_text_(max_text), outer_depth_(outer_depth) {}

  bool done() const { return done_; }
  json take() { return std::move(root_); }

  void value(json v) {
    count();
    if (v.is_string() && (text_ += v.get_ref<const std::string&>().size()) > max_text_) {
      invalid(here(), "holds more than " + std::to_string(max_text_) + " bytes of text");
    }
    if (stack_.empty()) {
      root_ = std::move(v);
      done_ = true;
    } else if (stack_.back()->is_object()) {
      (*stack_.back())[key_] = std::move(v);
    } else {
      stack_.back()->push_back(std::move(v));
    }
  }
  void open(json container) {
    if (outer_depth_ + static_cast<int>(stack_.size()) + 1 > max_json_depth) {
      invalid(field_, "malformed JSON: nested deeper than " + std::to_string(max_json_depth) + " levels");
    }
    count();
    path_.push_back(stack_.empty() ? "" : step());
    json* at;
    if (stack_.empty()) {
      root_ = std::move(container);
      at = &root_;
    } else if (stack_.back()->is_object()) {
      at = &((*stack_.back())[key_] = std::move(container));
    } else {
      stack_.back()->push_back(std::move(container));
      at = &stack_.back()->back();
    }
    stack_.push_back(at);
  }
  void key(std::string k) {
    key_ = std::move(k);
    if ((text_ += key_.size()) > max_text_) {
      invalid(here(), "holds more than " + std::to_string(max_text_) + " bytes of text");
    }
  }
  void close() {
    stack_.pop_back();
    path_.pop_back();
    if (stack_.empty()) done_ = true;
  }

 private:
  void count() {
    if (++values_ > max_values_) {
      invalid(field_, "holds more than " + std::to_string(max_values_) + " JSON values");
    }
  }

  // The next value's place in its container: ".key" or "[index]".
  std::string step() const {
    std::string s(1, stack_.back()->is_object() ? '.' : '[');
    if (stack_.back()->is_object()) return s.append(key_);
    return s.append(std::to_string(stack_.back()->size())).append(1, ']');
  }
  // The field of the next value, as the file names it ("sweep.request.padding").
  std::string here() const {
    std::string f = field_;
    for (const std::string& p : path_) f += p;
    return stack_.empty() ? f : f + step();
  }

  std::string field_;
  std::size_t max_values_;
  std::size_t max_text_;
  std::size_t text_ = 0;
  int outer_depth_;
  json root_;
  std::vector<json*> stack_;
  std::vector<std::string> path_;  // how each open container is reached from its parent
  std::string key_;
  std::size_t values_ = 0;
  bool done_ = false;
};

// The two passes over a file's events: Pass::head builds the top-level members but "runs",
// Pass::runs builds each element of "runs" and hands it to on_run.
class ExportSax {
 public:
  enum class Pass { head, runs };
  using OnRun = std::function<void(json&& run, std::size_t index)>;

  ExportSax(Pass pass, OnRun on_run) : pass_(pass), on_run_(std::move(on_run)) {}

  json head = json::object();  // Pass::head: the members read
  bool runs_seen = false;

  bool null() { return scalar(nullptr); }
  bool boolean(bool v) { return scalar(v); }
  bool number_integer(json::number_integer_t v) { return scalar(v); }
  bool number_unsigned(json::number_unsigned_t v) { return scalar(v); }
  bool number_float(json::number_float_t v, const std::string&) { return scalar(v); }
  bool string(std::string& v) { return scalar(std::move(v)); }
  bool binary(json::binary_t&) { invalid("file", "malformed JSON"); }

  bool start_object(std::size_t) { return open(json::object()); }
  bool start_array(std::size_t) { return open(json::array()); }
  bool key(std::string& k) {
    if (builder_) {
      builder_->key(std::move(k));
    } else if (skipping_ == 0 && depth_ == 1) {
      member_ = std::move(k);
    }
    return true;
  }
  bool end_object() { return close(); }
  bool end_array() { return close(); }

  bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception&) {
    invalid("file", "malformed JSON at byte " + std::to_string(position));
  }

 private:
  bool scalar(json v) {
    if (builder_) {
      builder_->value(std::move(v));
      if (builder_->done()) finish();
      return true;
    }
    if (skipping_ > 0) return true;
    if (depth_ == 0) invalid("file", "must be a JSON object (an export of compaction-server)");
    if (in_runs_) {
      start_run();
      builder_->value(std::move(v));
      finish();
      return true;
    }
    if (member_ == "runs") invalid("runs", "must be an array");
    if (pass_ == Pass::head && head_member(member_)) head[member_] = std::move(v);
    return true;
  }

  // The members of the head that the reader reads; others are skipped unread.
  static bool head_member(const std::string& key) {
    return key == "format" || key == "version" || key == "exported_at" || key == "source" ||
           key == "sweep";
  }

  bool open(json container) {
    const bool array = container.is_array();
    ++depth_;
    if (builder_) {
      builder_->open(std::move(container));
      return true;
    }
    if (skipping_ > 0) {
      ++skipping_;
      return true;
    }
    if (depth_ == 1) {
      if (array) invalid("file", "must be a JSON object (an export of compaction-server)");
      return true;
    }
    if (in_runs_) {
      start_run();
      builder_->open(std::move(container));
      return true;
    }
    // A member of the file's object.
    if (member_ == "runs") {
      if (!array) invalid("runs", "must be an array");
      runs_seen = true;
      if (pass_ == Pass::runs) {
        in_runs_ = true;
      } else {
        skipping_ = 1;
      }
      return true;
    }
    if (pass_ == Pass::runs || !head_member(member_)) {
      skipping_ = 1;
      return true;
    }
    builder_.emplace(member_, kMaxMemberValues, kMaxMemberTextBytes, 1);
    builder_->open(std::move(container));
    return true;
  }

  bool close() {
    --depth_;
    if (builder_) {
      builder_->close();
      if (builder_->done()) finish();
      return true;
    }
    if (skipping_ > 0) {
      --skipping_;
      return true;
    }
    if (in_runs_ && depth_ == 1) in_runs_ = false;  // the end of "runs"
    return true;
  }

  void start_run() {
    builder_.emplace("runs[" + std::to_string(run_index_) + "]", kMaxRunValues, kNoTextLimit, 2);
  }

  void finish() {
    json v = builder_->take();
    builder_.reset();
    if (in_runs_) {
      on_run_(std::move(v), run_index_++);
    } else {
      head[member_] = std::move(v);
    }
  }

  Pass pass_;
  OnRun on_run_;
  int depth_ = 0;       // open containers
  int skipping_ = 0;    // open containers of a skipped member
  bool in_runs_ = false;
  std::string member_;  // the top-level key whose value comes next
  std::optional<Builder> builder_;
  std::size_t run_index_ = 0;
};

// The head of the file (everything but its runs), checked.
ExportFile read_head(const json& doc) {
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
  if (f.sweep.request.size() > kMaxRequestBytes) {
    invalid("sweep.request", "must be at most " + std::to_string(kMaxRequestBytes) +
                                 " bytes, as a sweep's request is");
  }
  f.sweep.priority = static_cast<int>(integer(sweep, "sweep", "priority", kPriorityMin, kPriorityMax));
  f.sweep.created_at = time_ms(sweep, "sweep", "created_at");
  const json& origin = member(sweep, "sweep", "origin");
  f.sweep.origin_database = database_id(origin, "sweep.origin", "database");
  f.sweep.origin_sweep = integer(origin, "sweep.origin", "sweep", 1, std::int64_t(1) << 62);
  return f;
}

// Runs both passes, `parse` reading the whole file's events into a handler each time.
ExportFile read_export_passes(const std::function<void(ExportSax&)>& parse, const RunSink& on_run) {
  ExportSax head(ExportSax::Pass::head, nullptr);
  parse(head);
  ExportFile f = read_head(head.head);
  if (!head.runs_seen) invalid("runs", "is required");

  std::set<std::string> identities;
  std::set<std::pair<std::string, std::int64_t>> origins;
  ExportSax runs(ExportSax::Pass::runs, [&](json&& run, std::size_t i) {
    const std::string path = "runs[" + std::to_string(i) + "]";
    ImportedRun r = read_run(run, path, f.source_database);
    run = json();  // the document is done with: only what the run keeps stays
    if (!identities.insert(r.job.identity).second) {
      invalid(path + ".scene", "the same computation (scene and engine version) appears twice");
    }
    if (!origins.emplace(r.origin_database, r.origin_job).second) {
      invalid(path + ".origin", "another run of the file claims the same origin (database " +
                                    r.origin_database + ", job " + std::to_string(r.origin_job) + ")");
    }
    ++f.run_count;
    on_run(r);
  });
  parse(runs);
  return f;
}

}  // namespace

ExportFile read_export(std::FILE* in, const RunSink& on_run) {
  auto pass = [in](ExportSax& sax) {
    std::rewind(in);
    json::sax_parse(in, &sax);
    if (std::ferror(in)) throw std::runtime_error("cannot read the export file");
  };
  return read_export_passes(pass, on_run);
}

ExportFile read_export(const std::string& file_text) {
  auto pass = [&file_text](ExportSax& sax) { json::sax_parse(file_text, &sax); };
  ExportFile f;
  ExportFile head = read_export_passes(pass, [&f](ImportedRun& r) { f.runs.push_back(std::move(r)); });
  f.version = head.version;
  f.exported_at = head.exported_at;
  f.source_database = std::move(head.source_database);
  f.source = std::move(head.source);
  f.sweep = std::move(head.sweep);
  f.run_count = head.run_count;
  return f;
}

}  // namespace compaction::server
