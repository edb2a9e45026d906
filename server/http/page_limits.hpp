// How much one answer of a list holds (GET /sweeps, /jobs, /labels/audit), defined here and
// served by GET /api/v1/limits ("lists"), so the dashboard and the Python client page by the
// server's numbers.
#pragma once

#include <cstddef>
#include <cstdint>

namespace compaction::server {

inline constexpr int kDefaultPageRows = 100;
// A page of 1 000 full jobs (scene, result and features each) is about 1.5 MB of JSON.
inline constexpr int kMaxPageRows = 1000;
inline constexpr int kMaxOffset = 1'000'000'000;
// The CSV of the run table (GET /jobs?format=csv) is streamed, its rows read in one read
// transaction: at most this many (the first in the order asked; X-Total-Count says how many the
// filters keep). Twice the 100 000 runs the table is sized for (issue 49): about 40 MB.
inline constexpr std::int64_t kMaxCsvRows = 200'000;
// The run table's text search (q): a name, an id, a few words.
inline constexpr std::size_t kMaxSearchBytes = 200;

}  // namespace compaction::server
