#include "routes/run_query.hpp"

#include <algorithm>
#include <map>

#include "compaction/params.hpp"
#include "compaction/presets.hpp"
#include "exchange/base64.hpp"
#include "http/http_util.hpp"
#include "http/page_limits.hpp"
#include "input/safe_text.hpp"
#include "store/job_states.hpp"
#include "views/run_table_views.hpp"

namespace compaction::server {

using nlohmann::json;

namespace {

std::string value_of(const httplib::Request& req, const char* name) {
  return req.get_param_value(name);
}

// A comma-separated list: every item non-empty.
std::vector<std::string> list_of(const httplib::Request& req, const char* name) {
  const std::string text = value_of(req, name);
  std::vector<std::string> items;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    items.push_back(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (items.back().empty()) throw ApiError(422, name, "must be a comma-separated list without empty items");
    if (comma == std::string::npos) return items;
    start = comma + 1;
  }
}

// Values (each one `valid` says is one), "none" (no value) and "any" (any value),
// comma-separated.
TextChoice choice_of(const httplib::Request& req, const char* name, bool (*valid)(const std::string&),
                     const std::string& values) {
  TextChoice c;
  for (const std::string& item : list_of(req, name)) {
    if (item == "none") {
      c.none = true;
    } else if (item == "any") {
      c.any = true;
    } else if (valid(item)) {
      c.values.push_back(item);
    } else {
      throw ApiError(422, name, "must be " + values + ", none or any, comma-separated");
    }
  }
  return c;
}

bool class_letter(const std::string& s) { return s.size() == 1 && s[0] >= 'a' && s[0] <= 'f'; }
TextChoice labels_of(const httplib::Request& req, const char* name) {
  return choice_of(req, name, class_letter, "class letters a-f");
}

using Reader = void (*)(const httplib::Request&, const char*, JobsRequest&);
struct Param {
  const char* name;
  Reader read;
};

// The filters and the page's parameters but the ranges (below) and sort, limit, offset,
// cursor and format, which depend on each other (read_jobs_request).
const std::vector<Param>& params() {
  static const std::vector<Param> all = {
      {"sweep", [](const httplib::Request& q, const char* n, JobsRequest& r) { r.query.filter.sweep = query_id(q, n); }},
      {"point", [](const httplib::Request& q, const char* n, JobsRequest& r) { r.query.filter.point = query_id(q, n); }},
      {"state",
       [](const httplib::Request& q, const char* n, JobsRequest& r) {
         for (const std::string& s : list_of(q, n)) {
           if (!parse_job_state(s)) {
             throw ApiError(422, n, "must be queued, running, succeeded, failed or cancelled (comma-separated)");
           }
           r.query.filter.states.push_back(s);
         }
       }},
      {"phi", [](const httplib::Request& q, const char* n, JobsRequest& r) { r.query.filter.phi = query_number(q, n); }},
      {"cells_per_unit",
       [](const httplib::Request& q, const char* n, JobsRequest& r) {
         const auto& range = compaction::limits::cells_per_unit;
         for (const std::string& item : list_of(q, n)) {
           const auto v = decimal_number(item);
           if (!v || *v != static_cast<double>(static_cast<std::int64_t>(*v)) || !range.contains(*v)) {
             throw ApiError(422, n, "must be integers in " + to_string(range) + ", comma-separated");
           }
           r.query.filter.cells_per_unit.push_back(static_cast<std::int64_t>(*v));
         }
       }},
      {"preset",
       [](const httplib::Request& q, const char* n, JobsRequest& r) {
         r.query.filter.preset = choice_of(q, n, [](const std::string& s) { return find_preset(s) != nullptr; },
                                           preset_names());
       }},
      {"geometry",
       [](const httplib::Request& q, const char* n, JobsRequest& r) {
         for (const std::string& s : list_of(q, n)) {
           compaction::Geometry g;
           if (!compaction::parse(s, g)) {
             throw ApiError(422, n, "must be pseudo1d, full2d or pseudo1d_3d (comma-separated)");
           }
           r.query.filter.geometries.push_back(s);
         }
       }},
      {"class", [](const httplib::Request& q, const char* n, JobsRequest& r) { r.query.filter.cls = labels_of(q, n); }},
      {"label", [](const httplib::Request& q, const char* n, JobsRequest& r) { r.query.filter.label = labels_of(q, n); }},
      {"human_label", [](const httplib::Request& q, const char* n, JobsRequest& r) { r.query.filter.human_label = labels_of(q, n); }},
      {"imported",
       [](const httplib::Request& q, const char* n, JobsRequest& r) {
         const std::string v = value_of(q, n);
         if (v != "true" && v != "false") throw ApiError(422, n, "must be true or false");
         r.query.filter.imported = v == "true";
       }},
      {"source",
       [](const httplib::Request& q, const char* n, JobsRequest& r) {
         const std::string v = value_of(q, n);
         const bool hex = v.find_first_not_of("0123456789abcdefABCDEF") == std::string::npos;
         if (v.empty() || v.size() > 32 || !hex) {
           throw ApiError(422, n, "must be 1 to 32 hexadecimal digits (the start of a database id)");
         }
         r.query.filter.source = v;
       }},
      {"q",
       [](const httplib::Request& q, const char* n, JobsRequest& r) {
         const std::string v = value_of(q, n);
         if (v.empty() || v.size() > kMaxSearchBytes || has_control_characters(v)) {
           throw ApiError(422, n, "must be 1 to " + std::to_string(kMaxSearchBytes) +
                                      " bytes of UTF-8 text without control characters");
         }
         r.query.filter.text = v;
       }},
  };
  return all;
}

// The ranges: NAME_min and NAME_max of each ranged column, each inclusive.
std::vector<std::size_t> ranged_columns() {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < run_columns().size(); ++i) {
    if (run_columns()[i].ranged) out.push_back(i);
  }
  return out;
}

// sort, limit, offset, cursor, format, columns.
const char* const page_params[] = {"sort", "limit", "offset", "cursor", "format", "columns"};

RunSort sort_of(const httplib::Request& req) {
  RunSort s;
  if (!req.has_param("sort")) return s;
  std::string key = value_of(req, "sort");
  s.descending = !key.empty() && key[0] == '-';
  if (s.descending) key.erase(0, 1);
  const auto column = run_column(key);
  if (!column || !run_columns()[*column].sortable) {
    std::string keys;
    for (const RunColumn& c : run_columns()) {
      if (!c.sortable) continue;
      if (!keys.empty()) keys += ", ";
      keys += c.name;
    }
    throw ApiError(422, "sort", "must be one of " + keys + ", with - before it for descending");
  }
  s.column = *column;
  return s;
}

// base64url without padding (RFC 4648, section 5): the cursor goes into a URL as it is.
std::string base64url(std::string_view bytes) {
  std::string s = base64_encode(bytes);
  while (!s.empty() && s.back() == '=') s.pop_back();
  for (char& c : s) c = c == '+' ? '-' : c == '/' ? '_' : c;
  return s;
}

std::optional<std::string> from_base64url(std::string s) {
  if (s.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_") !=
      std::string::npos) {
    return std::nullopt;
  }
  for (char& c : s) c = c == '-' ? '+' : c == '_' ? '/' : c;
  while (s.size() % 4 != 0) s += '=';
  return base64_decode(s);
}

RunAfter cursor_of(const httplib::Request& req, const RunSort& sort) {
  const std::string text = value_of(req, "cursor");
  const auto bad = [](const std::string& why) { return ApiError(422, "cursor", why); };
  const auto bytes = text.size() <= 1000 ? from_base64url(text) : std::nullopt;
  if (!bytes) throw bad("must be the \"next\" of an answer of GET /jobs");
  json c;
  try {
    c = json::parse(*bytes);
  } catch (const json::exception&) {
    throw bad("must be the \"next\" of an answer of GET /jobs");
  }
  if (!c.is_object() || c.size() != 2 || !c.contains("sort") || !c.contains("after") ||
      !c["sort"].is_string() || !c["after"].is_array() || c["after"].size() != 2 ||
      !c["after"][1].is_number_integer()) {
    throw bad("must be the \"next\" of an answer of GET /jobs");
  }
  if (c["sort"] != sort_text(sort)) {
    throw bad("is a cursor of sort=" + valid_utf8(c["sort"].get<std::string>().substr(0, 40)) +
              ", not of this request's sort=" + sort_text(sort));
  }
  RunAfter after;
  after.id = c["after"][1].get<std::int64_t>();
  const json& v = c["after"][0];
  const RunType type = run_columns()[sort.column].type;
  if (v.is_null()) {
    after.value = std::monostate{};
  } else if (type == RunType::integer && v.is_number_integer()) {
    after.value = v.get<std::int64_t>();
  } else if (type == RunType::number && v.is_number()) {
    after.value = v.get<double>();
  } else if (type == RunType::text && v.is_string()) {
    after.value = v.get<std::string>();
  } else {
    throw bad("must be the \"next\" of an answer of GET /jobs");
  }
  return after;
}

// Every parameter known and given once.
void check_names(const httplib::Request& req) {
  static const std::vector<std::string> names = jobs_parameters();
  std::map<std::string, int> seen;
  for (const auto& [name, value] : req.params) {
    const bool known = std::find(names.begin(), names.end(), name) != names.end();
    const std::string field = valid_utf8(name.substr(0, 100));
    if (!known) throw ApiError(422, field, "is not a parameter of GET /jobs (docs/service.md, \"The run table\")");
    if (++seen[name] > 1) throw ApiError(422, field, "is given more than once (a list is comma-separated)");
  }
}

}  // namespace

std::vector<std::string> jobs_parameters() {
  std::vector<std::string> names;
  for (const Param& p : params()) names.emplace_back(p.name);
  for (const std::size_t c : ranged_columns()) {
    names.push_back(std::string(run_columns()[c].name) + "_min");
    names.push_back(std::string(run_columns()[c].name) + "_max");
  }
  for (const char* p : page_params) names.emplace_back(p);
  return names;
}

std::string sort_text(const RunSort& sort) {
  std::string s = sort.descending ? "-" : "";
  return s += run_columns().at(sort.column).name;
}

std::string cursor_text(const RunSort& sort, const RunAfter& after) {
  return base64url(json{{"sort", sort_text(sort)}, {"after", {views::run_value(after.value), after.id}}}.dump());
}

JobsRequest read_jobs_request(const httplib::Request& req) {
  check_names(req);
  JobsRequest r;
  if (req.has_param("format")) {
    const std::string f = value_of(req, "format");
    if (f == "json") {
      r.format = JobsFormat::json;
    } else if (f == "table") {
      r.format = JobsFormat::table;
    } else if (f == "csv") {
      r.format = JobsFormat::csv;
    } else {
      throw ApiError(422, "format", "must be json, table or csv");
    }
  }
  r.query.sort = sort_of(req);
  if (r.format == JobsFormat::csv) {
    const int max = static_cast<int>(kMaxCsvRows);
    r.query.limit = query_int(req, "limit", max, 1, max);
  } else {
    r.query.limit = query_int(req, "limit", kDefaultPageRows, 1, kMaxPageRows);
  }
  r.query.offset = query_int(req, "offset", 0, 0, kMaxOffset);
  if (req.has_param("cursor")) {
    if (req.has_param("offset")) throw ApiError(422, "cursor", "is not taken with offset");
    r.query.after = cursor_of(req, r.query.sort);
  }
  for (const Param& p : params()) {
    if (req.has_param(p.name)) p.read(req, p.name, r);
  }
  for (const std::size_t c : ranged_columns()) {
    const std::string name = run_columns()[c].name, lo = name + "_min", hi = name + "_max";
    NumberRange range{query_number(req, lo.c_str()), query_number(req, hi.c_str())};
    if (range.lo && range.hi && *range.lo > *range.hi) throw ApiError(422, hi, "must be at least " + lo);
    if (range.any()) r.query.filter.ranges[c] = range;
  }
  if (req.has_param("columns")) {
    if (r.format == JobsFormat::json) {
      throw ApiError(422, "columns", "is taken with format=table or format=csv (the jobs of format=json are whole)");
    }
    for (const std::string& name : list_of(req, "columns")) {
      const auto c = run_column(name);
      if (!c) throw ApiError(422, "columns", "has " + valid_utf8(name.substr(0, 40)) + ", not a column of the run table (GET /limits: jobs.columns)");
      if (std::find(r.columns.begin(), r.columns.end(), *c) != r.columns.end()) {
        throw ApiError(422, "columns", "names " + name + " twice");
      }
      r.columns.push_back(*c);
    }
    r.query.columns = r.columns;
  }
  return r;
}

}  // namespace compaction::server
