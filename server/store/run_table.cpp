#include "store/run_table.hpp"

#include <algorithm>
#include <stdexcept>

#include "compaction/params.hpp"

namespace compaction::server {

namespace {

// A column of the table and where run_rows holds it (nullptr: derived from the others, below).
struct ColumnSource {
  RunColumn column;
  const char* sql;
};

const std::vector<ColumnSource>& sources() {
  using T = RunType;
  static const std::vector<ColumnSource> all = {
      {{"id", T::integer, true}, "job_id"},
      {{"sweep", T::integer, true}, "sweep"},
      {{"state", T::text, true}, "state"},
      {{"S", T::number, true, true}, "S"},
      {{"R", T::number, true, true}, "R"},
      {{"phi", T::number, true, true}, "phi"},
      {{"preset", T::text, true}, "preset"},
      {{"cells_per_unit", T::integer, true}, "cells_per_unit"},
      {{"cells_per_strut", T::number, false}, nullptr},
      {{"seed", T::integer, true}, "seed"},
      {{"point_id", T::integer, true}, "point_id"},
      {{"status", T::text, true}, "status"},
      {{"class", T::text, true}, "class"},
      {{"confidence", T::number, true, true}, "confidence"},
      {{"runner_up", T::text, true}, "runner_up"},
      {{"n_reflections", T::integer, true, true}, "n_reflections"},
      {{"band_speed_ratio", T::number, true, true}, "band_speed_ratio"},
      {{"human_label", T::text, true}, "human_label"},
      {{"label", T::text, true}, "label"},
      {{"source_database", T::text, true}, "source_database"},
      {{"source_job", T::integer, true}, "source_job"},
      {{"geometry", T::text, true}, "geometry"},
      // The result's eps_reached and wall_seconds and the classifier's numeric features
      // (migration 0015; engine/classify/include/compaction/classify/features.hpp says what
      // each one is).
      {{"eps_reached", T::number, true, true}, "eps_reached"},
      {{"wall_seconds", T::number, true, true}, "wall_seconds"},
      {{"first_reflection_eps", T::number, true, true}, "first_reflection_eps"},
      {{"speed_excess", T::number, true, true}, "speed_excess"},
      {{"arrival_eps", T::number, true, true}, "arrival_eps"},
      {{"coherence", T::number, true, true}, "coherence"},
      {{"peak_jump", T::number, true, true}, "peak_jump"},
      {{"stress_ratio", T::number, true, true}, "stress_ratio"},
      {{"undulation_share", T::number, true, true}, "undulation_share"},
      {{"deflection_growth", T::number, true, true}, "deflection_growth"},
      {{"deflection_before_yield", T::number, true, true}, "deflection_before_yield"},
      {{"n_fronts", T::integer, true, true}, "n_fronts"},
      {{"band_turns", T::integer, true, true}, "band_turns"},
      {{"band_speed_error", T::number, true, true}, "band_speed_error"},
      {{"band_speed_early", T::number, true, true}, "band_speed_early"},
      {{"band_speed_lead", T::number, true, true}, "band_speed_lead"},
      {{"bottom_speed_ratio", T::number, true, true}, "bottom_speed_ratio"},
      {{"top_stress_undulation", T::number, true, true}, "top_stress_undulation"},
      {{"stress_drop", T::number, true, true}, "stress_drop"},
      {{"eps_first_yield", T::number, true, true}, "eps_first_yield"},
  };
  return all;
}

}  // namespace

double cells_per_strut(std::int64_t cells_per_unit, double phi, const std::string& geometry) {
  Geometry g = Geometry::pseudo1d;
  parse(geometry, g);
  return static_cast<double>(cells_per_unit) * strut_fraction(phi, g);
}

namespace {

std::size_t index_of(std::string_view name) {
  const auto i = run_column(name);
  if (!i) throw std::logic_error("no run table column " + std::string(name));
  return *i;
}

// A statement's text and its parameters, in the order of their '?'.
struct Sql {
  std::string text;
  std::vector<RunValue> params;

  void bind(sqlite::Statement& s) const {
    int i = 1;
    for (const RunValue& v : params) {
      if (const auto* n = std::get_if<std::int64_t>(&v)) {
        s.bind(i, *n);
      } else if (const auto* x = std::get_if<double>(&v)) {
        s.bind(i, *x);
      } else if (const auto* t = std::get_if<std::string>(&v)) {
        s.bind(i, *t);
      } else {
        s.bind_null(i);
      }
      ++i;
    }
  }
};

// The WHERE clauses, joined with AND.
class Where {
 public:
  void add(std::string clause, std::vector<RunValue> params = {}) {
    sql_.text += (sql_.text.empty() ? " WHERE " : " AND ") + clause;
    for (RunValue& p : params) sql_.params.push_back(std::move(p));
  }
  const Sql& sql() const { return sql_; }

 private:
  Sql sql_;
};

std::string placeholders(std::size_t n) {
  std::string s;
  for (std::size_t i = 0; i < n; ++i) s += i ? ", ?" : "?";
  return s;
}

void add_range(Where& w, const char* column, const NumberRange& r) {
  if (r.lo) w.add(std::string(column) + " >= ?", {*r.lo});
  if (r.hi) w.add(std::string(column) + " <= ?", {*r.hi});
}

void add_choice(Where& w, const char* column, const TextChoice& c) {
  if (!c.given()) return;
  std::vector<std::string> any_of;
  if (!c.values.empty()) any_of.push_back(std::string(column) + " IN (" + placeholders(c.values.size()) + ")");
  if (c.none) any_of.push_back(std::string(column) + " IS NULL");
  if (c.any) any_of.push_back(std::string(column) + " IS NOT NULL");
  std::string clause;
  for (const std::string& a : any_of) clause += (clause.empty() ? "(" : " OR ") + a;
  w.add(clause + ")", std::vector<RunValue>(c.values.begin(), c.values.end()));
}

// LIKE's pattern of a text anywhere ('%text%') or at the start ('text%'), its own '%', '_' and
// '\' escaped.
std::string like_pattern(const std::string& text, bool anywhere) {
  std::string p = anywhere ? "%" : "";
  for (char c : text) {
    if (c == '%' || c == '_' || c == '\\') p += '\\';
    p += c;
  }
  return p + "%";
}

Where filter_sql(const RunFilter& f) {
  Where w;
  if (f.sweep) w.add("job_id IN (SELECT job_id FROM sweep_jobs WHERE sweep_id = ?)", {*f.sweep});
  if (f.point) w.add("point_id = ?", {*f.point});
  add_choice(w, "state", {f.states});
  if (f.phi) w.add("phi BETWEEN ? AND ?", {*f.phi - 1e-9, *f.phi + 1e-9});
  for (const auto& [column, range] : f.ranges) add_range(w, sources().at(column).sql, range);
  if (!f.cells_per_unit.empty()) {
    std::vector<RunValue> params(f.cells_per_unit.begin(), f.cells_per_unit.end());
    w.add("cells_per_unit IN (" + placeholders(f.cells_per_unit.size()) + ")", std::move(params));
  }
  add_choice(w, "preset", f.preset);
  add_choice(w, "geometry", {f.geometries});
  add_choice(w, "class", f.cls);
  add_choice(w, "label", f.label);
  add_choice(w, "human_label", f.human_label);
  if (f.imported) w.add(*f.imported ? "source_database IS NOT NULL" : "source_database IS NULL");
  if (f.source) w.add("source_database LIKE ? ESCAPE '\\'", {like_pattern(*f.source, false)});
  if (f.text) {
    const std::string p = like_pattern(*f.text, true);
    w.add("(source_database LIKE ? ESCAPE '\\'"
          " OR job_id IN (SELECT job_id FROM human_labels"
          "               WHERE reason LIKE ? ESCAPE '\\' OR set_by LIKE ? ESCAPE '\\')"
          " OR job_id IN (SELECT job_id FROM sweep_jobs WHERE sweep_id IN"
          "               (SELECT id FROM sweeps WHERE name LIKE ? ESCAPE '\\')))",
          {p, p, p, p});
  }
  return w;
}

const char* sort_sql(const RunSort& s) { return sources().at(s.column).sql; }

// ORDER BY the sort column, nulls last, then the id in the same direction.
std::string order_sql(const RunSort& s) {
  const char* dir = s.descending ? " DESC" : " ASC";
  if (s.column == kRunIdColumn) return std::string(" ORDER BY job_id") + dir;
  return std::string(" ORDER BY ") + sort_sql(s) + dir + " NULLS LAST, job_id" + dir;
}

// The rows after `a` in the order of `s`.
void add_after(Where& w, const RunSort& s, const RunAfter& a) {
  const char* beyond = s.descending ? "<" : ">";
  if (s.column == kRunIdColumn) {
    w.add(std::string("job_id ") + beyond + " ?", {a.id});
    return;
  }
  const std::string c = sort_sql(s);
  if (std::holds_alternative<std::monostate>(a.value)) {
    w.add("(" + c + " IS NULL AND job_id " + beyond + " ?)", {a.id});
  } else {
    w.add("((" + c + ", job_id) " + beyond + " (?, ?) OR " + c + " IS NULL)", {a.value, a.id});
  }
}

// Which of sources() a query reads: its columns, its id and sort column, and the columns the
// cells across a strut are made from when it is asked for.
std::vector<bool> read_columns(const RunQuery& q) {
  std::vector<bool> read(sources().size(), q.columns.empty());
  for (const std::size_t c : q.columns) read.at(c) = true;
  read[kRunIdColumn] = read[q.sort.column] = true;
  if (read[index_of("cells_per_strut")]) {
    for (const char* name : {"phi", "cells_per_unit", "geometry"}) read[index_of(name)] = true;
  }
  return read;
}

std::string select_sql(const std::vector<bool>& read) {
  std::string s = "SELECT ";
  for (std::size_t i = 0; i < sources().size(); ++i) {
    if (read[i] && sources()[i].sql) s += std::string(sources()[i].sql) + ", ";
  }
  s.erase(s.size() - 2);  // the last ", "
  return s + " FROM run_rows";
}

// Reads rows of select_sql(read), deriving the cells across a strut when it is read.
class RowReader {
 public:
  explicit RowReader(const std::vector<bool>& read) : derive_strut_(read[cells_per_strut_]) {
    for (std::size_t i = 0; i < sources().size(); ++i) {
      if (sources()[i].sql && read[i]) read_.push_back({i, sources()[i].column.type});
    }
  }

  RunRow read(sqlite::Statement& s) const {
    RunRow row;
    read(s, row);
    return row;
  }
  // Into `row`, whose cells of the columns not read stay as they are (a row read before by
  // this reader: empty).
  void read(sqlite::Statement& s, RunRow& row) const {
    row.values.resize(sources().size());
    for (std::size_t k = 0; k < read_.size(); ++k) {
      RunValue& v = row.values[read_[k].index];
      const int c = static_cast<int>(k);
      if (s.is_null(c)) {
        v = std::monostate{};
        continue;
      }
      switch (read_[k].type) {
        case RunType::integer: v = s.int64(c); break;
        case RunType::number: v = s.real(c); break;
        case RunType::text: v = s.text(c); break;
      }
    }
    if (derive_strut_) {
      const auto* geometry = std::get_if<std::string>(&row.values[geometry_]);
      row.values[cells_per_strut_] =
          cells_per_strut(std::get<std::int64_t>(row.values[cells_per_unit_]),
                          std::get<double>(row.values[phi_]), geometry ? *geometry : "pseudo1d");
    }
  }

 private:
  struct Column {
    std::size_t index;  // in sources()
    RunType type;
  };
  const std::size_t phi_ = index_of("phi"), cells_per_unit_ = index_of("cells_per_unit"),
                    cells_per_strut_ = index_of("cells_per_strut"), geometry_ = index_of("geometry");
  std::vector<Column> read_;  // the columns of the statement, in its order
  bool derive_strut_;
};

std::int64_t count_rows(sqlite::Database& db, const Sql& filter) {
  auto n = db.prepare("SELECT count(*) FROM run_rows" + filter.text);
  filter.bind(n);
  n.step();
  return n.int64(0);
}

// The statement of the query's rows: `extra` rows beyond its limit (1: whether there is a next
// page).
sqlite::Statement rows_statement(sqlite::Database& db, const RunQuery& q, std::int64_t extra) {
  Where w = filter_sql(q.filter);
  if (q.after) add_after(w, q.sort, *q.after);
  Sql sql = w.sql();
  sql.text = select_sql(read_columns(q)) + sql.text + order_sql(q.sort) + " LIMIT ? OFFSET ?";
  sql.params.emplace_back(q.limit + extra);
  sql.params.emplace_back(q.offset);
  auto s = db.prepare(sql.text);
  sql.bind(s);
  return s;
}

RunAfter after_row(const RunRow& r, const RunSort& s) { return {r.values.at(s.column), r.id()}; }

class StatementStream : public RunTable::Stream {
 public:
  StatementStream(sqlite::ReaderPool& pool, const RunQuery& q)
      : db_(pool.take()),
        read_(*db_),
        total_(count_rows(*db_, filter_sql(q.filter).sql())),
        rows_(rows_statement(*db_, q, 0)),
        reader_(read_columns(q)) {}

  std::int64_t total() const override { return total_; }
  bool next(RunRow& row) override {
    if (!rows_.step()) return false;
    reader_.read(rows_, row);
    return true;
  }

 private:
  sqlite::ReaderPool::Handle db_;  // first: held until the statement and the transaction end
  sqlite::ReadTransaction read_;
  std::int64_t total_;
  sqlite::Statement rows_;
  RowReader reader_;
};

}  // namespace

const std::vector<RunColumn>& run_columns() {
  static const std::vector<RunColumn> all = [] {
    std::vector<RunColumn> out;
    for (const ColumnSource& c : sources()) out.push_back(c.column);
    return out;
  }();
  return all;
}

std::optional<std::size_t> run_column(std::string_view name) {
  for (std::size_t i = 0; i < sources().size(); ++i) {
    if (sources()[i].column.name == name) return i;
  }
  return std::nullopt;
}

bool RunFilter::empty() const {
  const bool no_range = std::none_of(ranges.begin(), ranges.end(), [](const auto& r) { return r.second.any(); });
  return !sweep && !point && states.empty() && !phi && no_range && cells_per_unit.empty() && !preset.given() && geometries.empty() && !cls.given() &&
         !label.given() && !human_label.given() && !imported && !source && !text;
}

RunPage<RunRow> read_run_page(sqlite::Database& db, const RunQuery& q) {
  if (!sources().at(q.sort.column).column.sortable) {
    throw std::logic_error("the run table's column " + std::string(sources()[q.sort.column].column.name) +
                           " is not sortable");
  }
  RunPage<RunRow> page;
  page.total = count_rows(db, filter_sql(q.filter).sql());
  auto s = rows_statement(db, q, 1);
  RowReader reader(read_columns(q));
  while (s.step()) page.items.push_back(reader.read(s));
  if (static_cast<std::int64_t>(page.items.size()) > q.limit) {
    page.items.pop_back();
    if (!page.items.empty()) page.next = after_row(page.items.back(), q.sort);
  }
  return page;
}

RunPage<RunRow> RunTable::page(const RunQuery& q) {
  auto db = db_.readers.take();
  sqlite::ReadTransaction read(*db);
  return read_run_page(*db, q);
}

std::unique_ptr<RunTable::Stream> RunTable::stream(const RunQuery& q) {
  return std::make_unique<StatementStream>(db_.readers, q);
}

}  // namespace compaction::server
