// The answers of GET /api/v1/jobs (the run table, store/run_table.hpp): the page as full jobs
// (format=json, the answer before the table), as the table's rows (format=table) or as CSV.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "store/run_table.hpp"
#include "store/store_reads.hpp"

namespace compaction::server::views {

// What an answer says beside its rows: the filtered set's size, the page, its order ("-phi")
// and the cursor of the next page (none after the last).
struct PageInfo {
  std::int64_t total = 0, limit = 0, offset = 0;
  std::string sort;
  std::optional<std::string> next;
};

// A cell as JSON: null, an integer, a number or a string.
nlohmann::json run_value(const RunValue& v);

// {"jobs": [job, ...], "total", "limit", "offset", "sort", "next"}
nlohmann::json jobs(const std::vector<JobRecord>& jobs, const PageInfo& page);
// The columns of an answer: those asked for (indexes of run_columns(), in their order), or
// every column when none were.
std::vector<std::size_t> answer_columns(const std::vector<std::size_t>& asked);

// {"columns": [name, ...], "rows": [{name: value, ...}, ...], "total", "limit", "offset",
//  "sort", "next"}, with these columns (answer_columns).
nlohmann::json run_table(const std::vector<RunRow>& rows, const PageInfo& page,
                         const std::vector<std::size_t>& columns);
// The CSV's first line (the column names), and one line per row appended to `out`, each
// ending in "\n".
std::string run_csv_header(const std::vector<std::size_t>& columns);
void append_run_csv_line(std::string& out, const RunRow& row, const std::vector<std::size_t>& columns);

}  // namespace compaction::server::views
