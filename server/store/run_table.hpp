// The run table (GET /api/v1/jobs): a row per job with the columns a researcher filters and
// sorts the runs by, read from run_rows (migration 0012: one narrow row per job, kept by
// triggers). Every page is one read transaction: the filtered set's count and its rows in the
// order asked, after a row (keyset) or an offset; a stream reads the same rows one at a time
// (the CSV).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "store/sqlite.hpp"
#include "store/store_db.hpp"

namespace compaction::server {

// A cell of the table: null, an integer, a number or a text.
using RunValue = std::variant<std::monostate, std::int64_t, double, std::string>;

enum class RunType { integer, number, text };

struct RunColumn {
  const char* name;  // as the API spells it
  RunType type;
  bool sortable;     // a derived column (cells_per_strut) is not
  bool ranged = false;  // GET /jobs filters it by NAME_min and NAME_max
};

// The table's columns in the order of its rows: id (the job), sweep (the first sweep that holds
// it), state, S, R, phi, preset, cells_per_unit, cells_per_strut, seed, point_id, status,
// class, confidence, runner_up, n_reflections, band_speed_ratio, human_label, label (the one
// that counts), source_database, source_job, geometry, then the result's eps_reached and
// wall_seconds and the classifier's numeric features (run_table.cpp lists them).
const std::vector<RunColumn>& run_columns();
// Grid cells across the thinnest strut of a run: cells_per_unit times its geometry's strut
// fraction (compaction::strut_fraction; geometry as the scene spells it, unknown: the 2D rule).
double cells_per_strut(std::int64_t cells_per_unit, double phi, const std::string& geometry);
// The index of a column by its name, or nullopt.
std::optional<std::size_t> run_column(std::string_view name);
inline constexpr std::size_t kRunIdColumn = 0;

// A row: one value per column of run_columns(), in its order.
struct RunRow {
  std::vector<RunValue> values;
  std::int64_t id() const { return std::get<std::int64_t>(values[kRunIdColumn]); }
};

// An inclusive range; a bound leaves out the rows without a value.
struct NumberRange {
  std::optional<double> lo, hi;
  bool any() const { return lo || hi; }
};

// Values of a text column that match (class letters, preset names), and whether a row without
// one or with any one matches; nothing given: no filter.
struct TextChoice {
  std::vector<std::string> values;
  bool none = false;  // no value
  bool any = false;   // any value
  bool given() const { return !values.empty() || none || any; }
};

// The rows a query keeps: every filter given must hold.
struct RunFilter {
  std::optional<std::int64_t> sweep;  // held by this sweep (any of its sweeps)
  std::optional<std::int64_t> point;  // a replicate of this point
  std::vector<std::string> states;    // in any of these states
  std::optional<double> phi;          // within 1e-9
  std::map<std::size_t, NumberRange> ranges;  // by column (RunColumn::ranged), each inclusive
  std::vector<std::int64_t> cells_per_unit;  // any of these grids
  TextChoice preset, cls, label, human_label;
  std::vector<std::string> geometries;  // of any of these geometries (to_string(Geometry))
  std::optional<bool> imported;        // a result computed on another server
  std::optional<std::string> source;   // the source database id starts with this
  std::optional<std::string> text;     // in a sweep's name, the source id, a label's reason or by

  bool empty() const;
};

// The order of the rows: one column, ascending or descending, the job's id after it in the
// same direction; rows without a value come last either way.
struct RunSort {
  std::size_t column = kRunIdColumn;
  bool descending = false;
};

// The rows after this one in the sort order (keyset paging): its value in the sort column and
// its id.
struct RunAfter {
  RunValue value;
  std::int64_t id = 0;
};

struct RunQuery {
  RunFilter filter;
  RunSort sort;
  // The columns a row needs (indexes of run_columns()); the others stay empty. Empty: all. The
  // id, the sort column and what a derived column is made from are read whatever it says.
  std::vector<std::size_t> columns;
  std::int64_t limit = 100;
  std::int64_t offset = 0;
  std::optional<RunAfter> after;
};

template <typename T>
struct RunPage {
  std::vector<T> items;
  std::int64_t total = 0;             // rows of the filtered set
  std::optional<RunAfter> next;       // where the next page starts; none after the last
};

// The query's text and parameters on run_rows (for StoreReads::jobs, which reads the same page
// as full job records in the same transaction).
RunPage<RunRow> read_run_page(sqlite::Database& db, const RunQuery& q);

class RunTable {
 public:
  explicit RunTable(StoreDb& db) : db_(db) {}

  RunPage<RunRow> page(const RunQuery& q);

  // The query's rows one at a time, up to its limit, in one read transaction held until the
  // stream ends; total() is the filtered set's count.
  class Stream {
   public:
    virtual ~Stream() = default;
    virtual std::int64_t total() const = 0;
    virtual bool next(RunRow& row) = 0;
  };
  std::unique_ptr<Stream> stream(const RunQuery& q);

 private:
  StoreDb& db_;
};

}  // namespace compaction::server
