#include "store/store_reads.hpp"

#include <algorithm>
#include <tuple>

#include "store/sweep_store.hpp"

namespace compaction::server {

namespace {

// The columns of a job with its result, in the order read_job reads them.
constexpr const char* job_columns =
    "j.id, j.state, j.S, j.R, j.phi, j.cells_per_unit, j.eps_end, j.engine_version, j.scene,"
    " j.priority, j.attempts, j.max_attempts, j.worker, j.progress_eps, j.created_at,"
    " j.started_at, j.heartbeat_at, j.finished_at, j.run_after, j.lease_deadline, j.last_error,"
    " r.status, r.reason, r.class, r.confidence, r.runner_up, r.n_reflections,"
    " r.band_speed_ratio, r.features, r.engine_version, r.source_revision, r.eps_reached,"
    " r.wall_seconds, r.worker, r.created_at, r.origin_database, r.origin_job, r.imported_at,"
    " h.label, h.reason, h.set_by, h.set_at, h.token, h.imported_at, j.point_id";

// What job_columns reads beside the job j: its result and its human label.
constexpr const char* result_joins =
    " LEFT JOIN results r ON r.job_id = j.id LEFT JOIN human_labels h ON h.job_id = j.id";
const std::string job_tables = std::string(" jobs j") + result_joins;

JobRecord read_job(sqlite::Statement& s) {
  JobRecord j;
  j.id = s.int64(0);
  j.state = s.text(1);
  j.S = s.real(2);
  j.R = s.real(3);
  j.phi = s.real(4);
  j.cells_per_unit = s.int64(5);
  j.eps_end = s.real(6);
  j.engine_version = s.text(7);
  j.scene = s.text(8);
  j.priority = s.int64(9);
  j.attempts = s.int64(10);
  j.max_attempts = s.int64(11);
  j.worker = s.opt_text(12);
  j.progress_eps = s.opt_real(13);
  j.created_at = s.int64(14);
  j.started_at = s.opt_int64(15);
  j.heartbeat_at = s.opt_int64(16);
  j.finished_at = s.opt_int64(17);
  j.run_after = s.int64(18);
  j.lease_deadline = s.opt_int64(19);
  j.last_error = s.opt_text(20);
  if (!s.is_null(21)) {
    StoredResult r;
    r.status = s.text(21);
    r.reason = s.text(22);
    r.cls = s.opt_text(23);
    r.confidence = s.opt_real(24);
    r.runner_up = s.opt_text(25);
    r.n_reflections = s.opt_int64(26);
    r.band_speed_ratio = s.opt_real(27);
    r.features = s.opt_text(28);
    r.engine_version = s.text(29);
    r.source_revision = s.text(30);
    r.eps_reached = s.opt_real(31);
    r.wall_seconds = s.opt_real(32);
    r.worker = s.text(33);
    r.created_at = s.int64(34);
    r.origin_database = s.opt_text(35);
    r.origin_job = s.opt_int64(36);
    r.imported_at = s.opt_int64(37);
    j.result = std::move(r);
  }
  if (!s.is_null(38)) {
    j.human_label = HumanLabel{s.text(38), s.text(39), s.text(40), s.int64(41),
                               s.opt_text(42).value_or(""), s.opt_int64(43)};
  }
  j.point_id = s.opt_int64(44).value_or(0);
  return j;
}

StateCounts counts_of_sweep(sqlite::Database& db, std::int64_t id) {
  auto s = db.prepare(
      "SELECT j.state, count(*) FROM sweep_jobs sj JOIN jobs j ON j.id = sj.job_id"
      " WHERE sj.sweep_id = ? GROUP BY j.state");
  s.bind(1, id);
  StateCounts c;
  while (s.step()) {
    const auto state = parse_job_state(s.text(0));
    const std::int64_t n = s.int64(1);
    if (!state) continue;  // the schema's CHECK allows no other state
    switch (*state) {
      case JobState::queued: c.queued = n; break;
      case JobState::running: c.running = n; break;
      case JobState::succeeded: c.succeeded = n; break;
      case JobState::failed: c.failed = n; break;
      case JobState::cancelled: c.cancelled = n; break;
    }
  }
  return c;
}

constexpr const char* sweep_columns =
    "id, name, request, priority, created_at, cancelled_at, origin_database, origin_sweep, origin";

SweepRecord read_sweep(sqlite::Statement& s, sqlite::Database& db) {
  SweepRecord r;
  r.id = s.int64(0);
  r.name = s.text(1);
  r.request = s.text(2);
  r.priority = s.int64(3);
  r.created_at = s.int64(4);
  r.cancelled_at = s.opt_int64(5);
  r.origin_database = s.opt_text(6);
  r.origin_sweep = s.opt_int64(7);
  r.origin = s.opt_text(8);
  r.counts = counts_of_sweep(db, r.id);
  return r;
}

}  // namespace

std::optional<SweepRecord> StoreReads::sweep(std::int64_t id) {
  auto db = db_.readers.take();
  sqlite::ReadTransaction read(*db);
  auto s = db->prepare(std::string("SELECT ") + sweep_columns + " FROM sweeps WHERE id = ?");
  s.bind(1, id);
  if (!s.step()) return std::nullopt;
  return read_sweep(s, *db);
}

Page<SweepRecord> StoreReads::sweeps(int limit, int offset) {
  auto db = db_.readers.take();
  sqlite::ReadTransaction read(*db);
  auto s = db->prepare(std::string("SELECT ") + sweep_columns +
                       " FROM sweeps ORDER BY id DESC LIMIT ? OFFSET ?");
  s.bind(1, limit).bind(2, offset);
  Page<SweepRecord> page;
  while (s.step()) page.items.push_back(read_sweep(s, *db));
  auto n = db->prepare("SELECT count(*) FROM sweeps");
  n.step();
  page.total = n.int64(0);
  return page;
}

std::vector<std::int64_t> StoreReads::live_adaptive_sweeps() {
  auto db = db_.readers.take();
  sqlite::ReadTransaction read(*db);
  auto s = db->prepare(
      "SELECT id FROM sweeps WHERE cancelled_at IS NULL AND origin_database IS NULL"
      " AND json_extract(request, '$.adaptive') IS NOT NULL ORDER BY id");
  std::vector<std::int64_t> out;
  while (s.step()) out.push_back(s.int64(0));
  return out;
}

std::vector<std::int64_t> StoreReads::live_adaptive_sweeps_of_job(std::int64_t job_id) {
  auto db = db_.readers.take();
  sqlite::ReadTransaction read(*db);
  return compaction::server::live_adaptive_sweeps_of_job(*db, job_id);
}

std::optional<std::vector<JobRecord>> StoreReads::sweep_jobs(std::int64_t id) {
  auto db = db_.readers.take();
  sqlite::ReadTransaction read(*db);
  if (!db->has_row("SELECT 1 FROM sweeps WHERE id = ?", id)) return std::nullopt;
  auto s = db->prepare(std::string("SELECT ") + job_columns +
                       " FROM sweep_jobs sj JOIN jobs j ON j.id = sj.job_id" + result_joins +
                       " WHERE sj.sweep_id = ? ORDER BY sj.position");
  s.bind(1, id);
  std::vector<JobRecord> rows;
  while (s.step()) rows.push_back(read_job(s));
  return rows;
}

RunPage<JobRecord> StoreReads::jobs(const RunQuery& q) {
  auto db = db_.readers.take();
  sqlite::ReadTransaction read(*db);
  const RunPage<RunRow> rows = read_run_page(*db, q);
  RunPage<JobRecord> page{{}, rows.total, rows.next};
  auto s = db->prepare(std::string("SELECT ") + job_columns + " FROM" + job_tables + " WHERE j.id = ?");
  for (const RunRow& row : rows.items) {
    s.reset();
    s.bind(1, row.id());
    if (s.step()) page.items.push_back(read_job(s));
  }
  return page;
}

std::optional<JobDetail> StoreReads::job(std::int64_t id) {
  auto db = db_.readers.take();
  sqlite::ReadTransaction read(*db);
  auto s = db->prepare(std::string("SELECT ") + job_columns + " FROM" + job_tables +
                       " WHERE j.id = ?");
  s.bind(1, id);
  if (!s.step()) return std::nullopt;
  JobDetail d;
  d.job = read_job(s);
  auto sweeps = db->prepare("SELECT sweep_id FROM sweep_jobs WHERE job_id = ? ORDER BY sweep_id");
  sweeps.bind(1, id);
  while (sweeps.step()) d.sweeps.push_back(sweeps.int64(0));
  auto replicates = db->prepare(
      "SELECT id FROM jobs WHERE point_id = ?1 AND id <> ?2 ORDER BY id LIMIT ?3");
  replicates.bind(1, d.job.point_id).bind(2, id).bind(3, static_cast<std::int64_t>(kMaxListedReplicates));
  while (replicates.step()) d.replicates.push_back(replicates.int64(0));
  auto events = db->prepare(
      "SELECT at, kind, attempt, worker, message FROM job_events WHERE job_id = ? ORDER BY id");
  events.bind(1, id);
  while (events.step()) {
    d.events.push_back({events.int64(0), events.text(1), events.int64(2), events.opt_text(3),
                        events.text(4)});
  }
  auto dropped = db->prepare("SELECT events_dropped FROM jobs WHERE id = ?");
  dropped.bind(1, id);
  if (dropped.step()) d.events_dropped = dropped.int64(0);
  if (d.job.result) {
    auto summary = db->prepare("SELECT summary FROM results WHERE job_id = ?");
    summary.bind(1, id);
    if (summary.step()) d.summary = summary.text(0);
  }
  return d;
}

namespace {

// What the map reads of a job and its result, in the order read_map_point reads them.
constexpr const char* map_columns =
    "SELECT j.S, j.R, j.phi, j.state, r.class, r.confidence, r.runner_up, r.n_reflections,"
    " r.band_speed_ratio, j.id, r.status, j.cells_per_unit, j.eps_end, j.progress_eps,"
    " r.band_speed_error, r.band_speed_transit, r.band_speed_transit_error, h.label,"
    " j.structure, r.band_speed_early, r.band_speed_early_error, r.band_speed_lead,"
    " r.band_speed_lead_error, j.point_id, j.geometry";

PhaseMapPoint read_map_point(sqlite::Statement& s) {
  PhaseMapPoint p;
  p.S = s.real(0);
  p.R = s.real(1);
  p.phi = s.real(2);
  p.state = s.text(3);
  p.cls = s.opt_text(4);
  p.confidence = s.opt_real(5);
  p.runner_up = s.opt_text(6);
  p.n_reflections = s.opt_int64(7);
  p.band_speed_ratio = s.opt_real(8);
  p.job_id = s.int64(9);
  p.status = s.opt_text(10);
  p.cells_per_unit = s.int64(11);
  p.eps_end = s.real(12);
  p.progress_eps = s.opt_real(13);
  p.band_speed_error = s.opt_real(14);
  p.band_speed_transit = s.opt_real(15);
  p.band_speed_transit_error = s.opt_real(16);
  p.human_label = s.opt_text(17);
  if (auto structure = s.opt_text(18)) p.structure = *structure;
  p.band_speed_early = s.opt_real(19);
  p.band_speed_early_error = s.opt_real(20);
  p.band_speed_lead = s.opt_real(21);
  p.band_speed_lead_error = s.opt_real(22);
  p.point_id = s.opt_int64(23).value_or(0);
  if (auto geometry = s.opt_text(24)) p.geometry = *geometry;
  return p;
}

}  // namespace

std::vector<PhaseMapPoint> StoreReads::phase_map(double phi, std::optional<std::int64_t> sweep_id,
                                                 std::optional<std::int64_t> cells_per_unit,
                                                 const std::string& geometry) {
  auto db = db_.readers.take();
  sqlite::ReadTransaction read(*db);
  auto s = db->prepare(
      std::string(map_columns) +
      // The covering indexes of migrations 0008, 0009, 0011 and 0013; named, as SQLite would otherwise
      // read each result by its row (rowid) and so its whole summary.
      " FROM jobs j INDEXED BY jobs_map"
      " LEFT JOIN results r INDEXED BY results_map ON r.job_id = j.id"
      " LEFT JOIN human_labels h ON h.job_id = j.id"
      " WHERE j.phi BETWEEN ?1 - 1e-9 AND ?1 + 1e-9"
      " AND (?2 IS NULL OR j.id IN (SELECT job_id FROM sweep_jobs WHERE sweep_id = ?2))"
      " AND (?3 IS NULL OR j.cells_per_unit = ?3) AND j.geometry = ?4");
  s.bind(1, phi).bind(2, sweep_id).bind(3, cells_per_unit).bind(4, geometry);
  std::vector<PhaseMapPoint> points;
  while (s.step()) points.push_back(read_map_point(s));
  // jobs_map yields the rows by (phi, S, R, id), which is (S, R, id) whenever the jobs within the
  // tolerance share one phi; sorted here otherwise (an ORDER BY would sort every time).
  const auto by_S_R_id = [](const PhaseMapPoint& a, const PhaseMapPoint& b) {
    return std::tie(a.S, a.R, a.job_id) < std::tie(b.S, b.R, b.job_id);
  };
  if (!std::is_sorted(points.begin(), points.end(), by_S_R_id)) {
    std::sort(points.begin(), points.end(), by_S_R_id);
  }
  return points;
}

std::vector<PhaseMapPoint> StoreReads::sweep_map(std::int64_t sweep_id) {
  auto db = db_.readers.take();
  sqlite::ReadTransaction read(*db);
  auto s = db->prepare(std::string(map_columns) +
                       " FROM sweep_jobs sj JOIN jobs j ON j.id = sj.job_id"
                       " LEFT JOIN results r INDEXED BY results_map ON r.job_id = j.id"
                       " LEFT JOIN human_labels h ON h.job_id = j.id"
                       " WHERE sj.sweep_id = ? ORDER BY sj.position, j.id");
  s.bind(1, sweep_id);
  std::vector<PhaseMapPoint> points;
  while (s.step()) points.push_back(read_map_point(s));
  return points;
}

std::optional<std::vector<ArtifactInfo>> StoreReads::artifacts(std::int64_t job_id) {
  auto db = db_.readers.take();
  sqlite::ReadTransaction read(*db);
  if (!db->has_row("SELECT 1 FROM jobs WHERE id = ?", job_id)) return std::nullopt;
  auto s = db->prepare(
      "SELECT name, content_type, size FROM artifacts WHERE job_id = ? ORDER BY name");
  s.bind(1, job_id);
  std::vector<ArtifactInfo> out;
  while (s.step()) out.push_back({s.text(0), s.text(1), s.int64(2)});
  return out;
}

std::optional<Artifact> StoreReads::artifact(std::int64_t job_id, const std::string& name) {
  std::optional<std::string> path;
  Artifact a;
  {
    auto db = db_.readers.take();
    sqlite::ReadTransaction read(*db);
    auto s = db->prepare(
        "SELECT name, content_type, data, path FROM artifacts WHERE job_id = ? AND name = ?");
    s.bind(1, job_id).bind(2, name);
    if (!s.step()) return std::nullopt;
    a = {s.text(0), s.text(1), s.is_null(3) ? s.blob(2) : std::string(), std::nullopt};
    path = s.opt_text(3);
  }
  if (path) a.data = db_.files.read(*path);  // with no connection held
  return a;
}

namespace {

StoreMetrics read_metrics(sqlite::Database& db) {
  StoreMetrics m;
  auto by_state = db.prepare("SELECT state, count(*) FROM jobs GROUP BY state ORDER BY state");
  while (by_state.step()) m.jobs_by_state.emplace_back(by_state.text(0), by_state.int64(1));
  auto by_kind = db.prepare("SELECT kind, total FROM event_totals ORDER BY kind");
  while (by_kind.step()) m.events_by_kind.emplace_back(by_kind.text(0), by_kind.int64(1));
  auto by_status =
      db.prepare("SELECT status, count(*) FROM results GROUP BY status ORDER BY status");
  while (by_status.step()) m.results_by_status.emplace_back(by_status.text(0), by_status.int64(1));
  auto sweeps = db.prepare("SELECT count(*) FROM sweeps");
  sweeps.step();
  m.sweeps = sweeps.int64(0);
  return m;
}

}  // namespace

StoreMetrics StoreReads::metrics() {
  auto db = db_.readers.take();
  sqlite::ReadTransaction read(*db);
  return read_metrics(*db);
}

ScrapeMetrics StoreReads::scrape_metrics() {
  auto db = db_.readers.take();
  sqlite::ReadTransaction read(*db);
  ScrapeMetrics m;
  m.store = read_metrics(*db);
  // One pass over the succeeded jobs: a column per bucket, then the count and the sum.
  std::string sql = "SELECT ";
  for (double le : job_duration_buckets_seconds) {
    sql += "coalesce(sum(d <= " + std::to_string(static_cast<std::int64_t>(le * 1000)) + "), 0), ";
  }
  sql += "count(*), coalesce(sum(d), 0) FROM (SELECT finished_at - started_at AS d FROM jobs"
         " WHERE state = 'succeeded' AND finished_at IS NOT NULL AND started_at IS NOT NULL)";
  auto d = db->prepare(sql);
  d.step();
  const int n = static_cast<int>(std::size(job_duration_buckets_seconds));
  for (int i = 0; i < n; ++i) m.duration_buckets.push_back(d.int64(i));
  m.duration_count = d.int64(n);
  m.duration_sum_seconds = d.real(n + 1) / 1000.0;
  auto w = db->prepare(
      "SELECT worker, total FROM (SELECT worker, total FROM worker_lease_expiries"
      " ORDER BY last_at DESC, worker LIMIT ?) ORDER BY worker");
  w.bind(1, max_workers_with_expiries);
  while (w.step()) m.lease_expiries_by_worker.emplace_back(w.text(0), w.int64(1));
  return m;
}

std::string StoreReads::fingerprint() {
  auto db = db_.readers.take();
  sqlite::ReadTransaction read(*db);
  std::string out;
  for (const char* q :
       {"SELECT group_concat(id || state || attempts || coalesce(lease_token, '') ||"
        " coalesce(lease_deadline, '') || run_after || priority, ';') FROM jobs",
        "SELECT group_concat(id || name || coalesce(cancelled_at, ''), ';') FROM sweeps",
        "SELECT group_concat(sweep_id || ':' || job_id, ';') FROM sweep_jobs",
        "SELECT group_concat(job_id || status, ';') FROM results",
        "SELECT group_concat(job_id || name || size, ';') FROM artifacts",
        "SELECT count(*) FROM job_events"}) {
    auto s = db->prepare(q);
    s.step();
    out += s.text(0) + "|";
  }
  return out;
}

}  // namespace compaction::server
