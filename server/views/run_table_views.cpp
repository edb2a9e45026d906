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

std::vector<std::size_t> answer_columns(const std::vector<std::size_t>& asked) {
  if (!asked.empty()) return asked;
  std::vector<std::size_t> all(run_columns().size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  return all;
}

json run_table(const std::vector<RunRow>& rows, const PageInfo& page,
               const std::vector<std::size_t>& columns) {
  json names = json::array();
  for (const std::size_t c : columns) names.push_back(run_columns().at(c).name);
  json out = json::array();
  for (const RunRow& r : rows) {
    json row = json::object();
    for (const std::size_t c : columns) row[run_columns()[c].name] = run_value(r.values.at(c));
    out.push_back(std::move(row));
  }
  return with_page({{"columns", names}, {"rows", out}}, page);
}

std::string run_csv_header(const std::vector<std::size_t>& columns) {
  std::string line;
  for (const std::size_t c : columns) {
    if (!line.empty()) line += ',';
    line += run_columns().at(c).name;
  }
  return line + "\n";
}

void append_run_csv_line(std::string& out, const RunRow& row, const std::vector<std::size_t>& columns) {
  for (std::size_t k = 0; k < columns.size(); ++k) {
    if (k) out += ',';
    const RunValue& v = row.values.at(columns[k]);
    if (const auto* n = std::get_if<std::int64_t>(&v)) {
      append_csv_integer(out, *n);
    } else if (const auto* x = std::get_if<double>(&v)) {
      append_csv_number(out, *x);  // as the JSON answers write it
    } else if (const auto* t = std::get_if<std::string>(&v)) {
      append_csv_text(out, *t);
    }
  }
  out += '\n';
}

}  // namespace compaction::server::views
