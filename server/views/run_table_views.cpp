#include "views/run_table_views.hpp"

#include "views/csv_text.hpp"
#include "views/views.hpp"

namespace compaction::server::views {

using nlohmann::json;

namespace {

json with_page(json out, const PageInfo& p) {
  out["total"] = p.total;
  out["limit"] = p.limit;
  out["offset"] = p.offset;
  out["sort"] = p.sort;
  out["next"] = p.next ? json(*p.next) : json(nullptr);
  return out;
}

}  // namespace

json run_value(const RunValue& v) {
  if (const auto* n = std::get_if<std::int64_t>(&v)) return *n;
  if (const auto* x = std::get_if<double>(&v)) return *x;
  if (const auto* t = std::get_if<std::string>(&v)) return *t;
  return nullptr;
}

json jobs(const std::vector<JobRecord>& jobs, const PageInfo& page) {
  json out = json::array();
  for (const JobRecord& j : jobs) out.push_back(job(j));
  return with_page({{"jobs", out}}, page);
}

json run_table(const std::vector<RunRow>& rows, const PageInfo& page) {
  json columns = json::array();
  for (const RunColumn& c : run_columns()) columns.push_back(c.name);
  json out = json::array();
  for (const RunRow& r : rows) {
    json row = json::object();
    for (std::size_t i = 0; i < r.values.size(); ++i) row[run_columns()[i].name] = run_value(r.values[i]);
    out.push_back(std::move(row));
  }
  return with_page({{"columns", columns}, {"rows", out}}, page);
}

std::string run_csv_header() {
  std::string line;
  for (const RunColumn& c : run_columns()) {
    if (!line.empty()) line += ',';
    line += c.name;
  }
  return line + "\n";
}

std::string run_csv_line(const RunRow& row) {
  std::string line;
  for (std::size_t i = 0; i < row.values.size(); ++i) {
    if (i) line += ',';
    const RunValue& v = row.values[i];
    if (const auto* n = std::get_if<std::int64_t>(&v)) {
      line += std::to_string(*n);
    } else if (const auto* x = std::get_if<double>(&v)) {
      line += json(*x).dump();  // as the JSON answers write it
    } else if (const auto* t = std::get_if<std::string>(&v)) {
      line += csv_text(*t);
    }
  }
  return line + "\n";
}

}  // namespace compaction::server::views
