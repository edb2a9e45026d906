// The query string of GET /api/v1/jobs read into the run table's query (store/run_table.hpp),
// and the cursor of its pages. Every parameter is checked: an unknown one, one given twice, a
// number that is not one, a sort key the table has not, a cursor of another order: 422 naming
// the parameter. docs/service.md ("The run table") lists them.
#pragma once

#include <string>
#include <vector>

#include <httplib.h>

#include "store/run_table.hpp"

namespace compaction::server {

enum class JobsFormat { json, table, csv };

struct JobsRequest {
  RunQuery query;
  JobsFormat format = JobsFormat::json;
  // The columns of the answer (format=table or csv), by index, in the order asked; empty: all.
  // query.columns holds the same (what the rows read).
  std::vector<std::size_t> columns;
};

JobsRequest read_jobs_request(const httplib::Request& req);

// "confidence" or "-confidence" (descending).
std::string sort_text(const RunSort& sort);
// The cursor of the rows after `after` in `sort`'s order (an answer's "next"): URL-safe text
// that read_jobs_request takes back as ?cursor=.
std::string cursor_text(const RunSort& sort, const RunAfter& after);

// The query parameters GET /jobs takes, for GET /limits.
std::vector<std::string> jobs_parameters();

}  // namespace compaction::server
