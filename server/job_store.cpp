#include "job_store.hpp"

#include <algorithm>
#include <random>
#include <set>

#include <spdlog/spdlog.h>

#include "migrations.hpp"

namespace compaction::server {

using nlohmann::json;

namespace {

std::string new_token() {
  static thread_local std::random_device rd;
  static const char* hex = "0123456789abcdef";
  std::string t;
  for (int i = 0; i < 4; ++i) {
    std::uint32_t v = rd();
    for (int k = 0; k < 8; ++k, v >>= 4) t.push_back(hex[v & 15u]);
  }
  return t;  // 128 random bits
}

// A lease token as a folder name: the API only ever hands out hex tokens, but a name is built
// from what the client sent, so anything else is kept to [0-9a-z].
std::string token_folder_name(const std::string& token) {
  std::string out;
  for (char c : token.substr(0, 64)) {
    out += (c >= '0' && c <= '9') || (c >= 'a' && c <= 'z') ? c : 'x';
  }
  return out;
}

template <typename T>
json opt(const std::optional<T>& v) {
  return v ? json(*v) : json(nullptr);
}

// The columns of a job with its result, in the order job_row_json reads them.
constexpr const char* job_columns =
    "j.id, j.state, j.S, j.R, j.phi, j.cells_per_unit, j.eps_end, j.engine_version, j.scene,"
    " j.priority, j.attempts, j.max_attempts, j.worker, j.progress_eps, j.created_at,"
    " j.started_at, j.heartbeat_at, j.finished_at, j.run_after, j.lease_deadline, j.last_error,"
    " r.status, r.reason, r.class, r.confidence, r.runner_up, r.n_reflections,"
    " r.band_speed_ratio, r.features, r.engine_version, r.source_revision, r.eps_reached,"
    " r.wall_seconds, r.worker, r.created_at";

}  // namespace

JobStore::JobStore(const std::string& path, StoreConfig config)
    : config_(std::move(config)), db_(path), readers_(path), files_(path + ".artifacts") {
  std::lock_guard lock(mutex_);
  apply_migrations(db_, embedded_migrations());
  // Folders of results that were never committed (a crash between writing the files and the
  // transaction): nothing names them.
  std::set<std::string> keep;
  auto s = db_.prepare(
      "SELECT DISTINCT substr(path, 1, instr(path, '/') - 1) FROM artifacts WHERE path IS NOT NULL");
  while (s.step()) keep.insert(s.text(0));
  if (const int n = files_.remove_all_but(keep); n > 0) {
    spdlog::warn("removed {} artifact folder(s) of uploads that were never committed", n);
  }
}

Millis JobStore::backoff(int attempts) const {
  Millis d = config_.backoff_base_ms;
  for (int i = 1; i < attempts && d < config_.backoff_max_ms; ++i) d *= 2;
  return std::min(d, config_.backoff_max_ms);
}

void JobStore::log_event(std::int64_t job_id, Millis at, const char* kind, int attempt,
                         const std::optional<std::string>& worker, const std::string& message) {
  db_.prepare(
        "INSERT INTO job_events (job_id, at, kind, attempt, worker, message)"
        " VALUES (?, ?, ?, ?, ?, ?)")
      .bind(1, job_id)
      .bind(2, at)
      .bind(3, kind)
      .bind(4, attempt)
      .bind(5, worker)
      .bind(6, message)
      .run();
  db_.prepare(
        "INSERT INTO event_totals (kind, total) VALUES (?, 1)"
        " ON CONFLICT (kind) DO UPDATE SET total = total + 1")
      .bind(1, kind)
      .run();
  // Only the newest events of a job stay; the older ones are counted in jobs.events_dropped.
  auto trim = db_.prepare(
      "DELETE FROM job_events WHERE job_id = ?1 AND id <= (SELECT id FROM job_events"
      " WHERE job_id = ?1 ORDER BY id DESC LIMIT 1 OFFSET ?2)");
  trim.bind(1, job_id).bind(2, static_cast<std::int64_t>(max_events_per_job)).run();
  if (const std::int64_t dropped = db_.changes(); dropped > 0) {
    db_.prepare("UPDATE jobs SET events_dropped = events_dropped + ?2 WHERE id = ?1")
        .bind(1, job_id)
        .bind(2, dropped)
        .run();
  }
}

// ---- sweeps ---------------------------------------------------------------------------------

CreatedSweep JobStore::create_sweep(const SweepPlan& plan, Millis now) {
  std::lock_guard lock(mutex_);
  sqlite::Transaction tx(db_);
  CreatedSweep out;
  db_.prepare("INSERT INTO sweeps (name, request, priority, created_at) VALUES (?, ?, ?, ?)")
      .bind(1, plan.name)
      .bind(2, plan.request.dump())
      .bind(3, plan.priority)
      .bind(4, now)
      .run();
  out.id = db_.last_insert_rowid();

  auto insert = db_.prepare(
      "INSERT INTO jobs (identity, scene, engine_version, S, R, phi, cells_per_unit, eps_end,"
      " priority, max_attempts, run_after, created_at)"
      " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?11)"
      " ON CONFLICT (identity) DO NOTHING");
  auto find = db_.prepare("SELECT id, state FROM jobs WHERE identity = ?");
  // A job another sweep already holds: raise its priority to the highest that wants it.
  auto raise = db_.prepare("UPDATE jobs SET priority = max(priority, ?2) WHERE id = ?1");
  // Failed or cancelled before: a new sweep asks again, with fresh attempts.
  auto requeue = db_.prepare(
      "UPDATE jobs SET state = 'queued', attempts = 0, max_attempts = ?2, run_after = ?3,"
      " priority = ?4, finished_at = NULL, progress_eps = NULL"
      " WHERE id = ?1 AND state IN ('failed', 'cancelled')");
  auto link = db_.prepare(
      "INSERT OR IGNORE INTO sweep_jobs (sweep_id, job_id, position) VALUES (?, ?, ?)");

  std::int64_t position = 0;
  for (const SceneParams& p : plan.scenes) {
    const std::string scene = canonical_scene(p);
    insert.reset();
    insert.bind(1, job_identity(p, config_.engine_version))
        .bind(2, scene)
        .bind(3, config_.engine_version)
        .bind(4, p.S)
        .bind(5, p.R)
        .bind(6, p.phi)
        .bind(7, p.cells_per_unit)
        .bind(8, p.eps_final())
        .bind(9, plan.priority)
        .bind(10, plan.max_attempts)
        .bind(11, now)
        .run();
    const bool created = db_.changes() > 0;
    find.reset();
    find.bind(1, job_identity(p, config_.engine_version));
    if (!find.step()) throw sqlite::Error("job vanished during sweep creation");
    const std::int64_t job_id = find.int64(0);
    const std::string state = find.text(1);
    find.reset();
    if (created) {
      ++out.n_new;
    } else if (state == "succeeded") {
      ++out.n_reused;
    } else if (state == "failed" || state == "cancelled") {
      requeue.reset();
      requeue.bind(1, job_id).bind(2, plan.max_attempts).bind(3, now).bind(4, plan.priority).run();
      log_event(job_id, now, "queued", 0, std::nullopt,
                "requeued by sweep " + std::to_string(out.id) + " (was " + state + ")");
      ++out.n_requeued;
    } else {
      raise.reset();
      raise.bind(1, job_id).bind(2, plan.priority).run();
      ++out.n_shared;
    }
    link.reset();
    link.bind(1, out.id).bind(2, job_id).bind(3, position++).run();
    ++out.n_jobs;
  }
  tx.commit();
  return out;
}

json JobStore::counts_for_sweep(sqlite::Database& db, std::int64_t id) {
  json counts = {{"queued", 0}, {"running", 0}, {"succeeded", 0}, {"failed", 0},
                 {"cancelled", 0}};
  auto s = db.prepare(
      "SELECT j.state, count(*) FROM sweep_jobs sj JOIN jobs j ON j.id = sj.job_id"
      " WHERE sj.sweep_id = ? GROUP BY j.state");
  s.bind(1, id);
  std::int64_t total = 0;
  while (s.step()) {
    counts[s.text(0)] = s.int64(1);
    total += s.int64(1);
  }
  counts["total"] = total;
  return counts;
}

namespace {
json sweep_json(sqlite::Statement& s, json counts) {
  // columns: id, name, request, priority, created_at, cancelled_at
  const bool cancelled = !s.is_null(5);
  const std::int64_t open = counts["queued"].get<std::int64_t>() +
                            counts["running"].get<std::int64_t>();
  const char* state = cancelled ? "cancelled" : open > 0 ? "active" : "done";
  const std::int64_t total = counts["total"].get<std::int64_t>();
  const std::int64_t finished = total - open;
  return {{"id", s.int64(0)},
          {"name", s.text(1)},
          {"request", json::parse(s.text(2))},
          {"priority", s.int64(3)},
          {"created_at", s.int64(4)},
          {"cancelled_at", opt(s.opt_int64(5))},
          {"state", state},
          {"counts", counts},
          {"progress", total > 0 ? static_cast<double>(finished) / total : 1.0}};
}
}  // namespace

std::optional<json> JobStore::sweep(std::int64_t id) {
  auto db = readers_.take();
  sqlite::ReadTransaction read(*db);
  auto s = db->prepare(
      "SELECT id, name, request, priority, created_at, cancelled_at FROM sweeps WHERE id = ?");
  s.bind(1, id);
  if (!s.step()) return std::nullopt;
  return sweep_json(s, counts_for_sweep(*db, id));
}

json JobStore::list_sweeps(int limit, int offset) {
  auto db = readers_.take();
  sqlite::ReadTransaction read(*db);
  auto s = db->prepare(
      "SELECT id, name, request, priority, created_at, cancelled_at FROM sweeps"
      " ORDER BY id DESC LIMIT ? OFFSET ?");
  s.bind(1, limit).bind(2, offset);
  json out = json::array();
  while (s.step()) out.push_back(sweep_json(s, counts_for_sweep(*db, s.int64(0))));
  auto n = db->prepare("SELECT count(*) FROM sweeps");
  n.step();
  return {{"sweeps", out}, {"total", n.int64(0)}, {"limit", limit}, {"offset", offset}};
}

std::optional<json> JobStore::cancel_sweep(std::int64_t id, Millis now) {
  std::lock_guard lock(mutex_);
  sqlite::Transaction tx(db_);
  auto exists = db_.prepare("SELECT cancelled_at FROM sweeps WHERE id = ?");
  exists.bind(1, id);
  if (!exists.step()) return std::nullopt;
  db_.prepare("UPDATE sweeps SET cancelled_at = ?2 WHERE id = ?1 AND cancelled_at IS NULL")
      .bind(1, id)
      .bind(2, now)
      .run();
  // Jobs of this sweep that no other live sweep wants; a running one loses its lease (the
  // worker hears 409 at its next heartbeat and stops the run).
  auto victims = db_.prepare(
      "SELECT j.id, j.attempts, j.worker FROM sweep_jobs sj JOIN jobs j ON j.id = sj.job_id"
      " WHERE sj.sweep_id = ?1 AND j.state IN ('queued', 'running')"
      " AND NOT EXISTS (SELECT 1 FROM sweep_jobs o JOIN sweeps w ON w.id = o.sweep_id"
      "                 WHERE o.job_id = j.id AND o.sweep_id <> ?1 AND w.cancelled_at IS NULL)");
  victims.bind(1, id);
  std::vector<std::tuple<std::int64_t, int, std::optional<std::string>>> jobs;
  while (victims.step()) {
    jobs.emplace_back(victims.int64(0), static_cast<int>(victims.int64(1)), victims.opt_text(2));
  }
  auto cancel = db_.prepare(
      "UPDATE jobs SET state = 'cancelled', lease_token = NULL, lease_deadline = NULL,"
      " finished_at = ?2 WHERE id = ?1 AND state IN ('queued', 'running')");
  for (const auto& [job_id, attempt, worker] : jobs) {
    cancel.reset();
    cancel.bind(1, job_id).bind(2, now).run();
    log_event(job_id, now, "cancelled", attempt, worker, "sweep " + std::to_string(id) + " cancelled");
  }
  tx.commit();
  return json{{"id", id}, {"cancelled_jobs", jobs.size()}};
}

std::optional<json> JobStore::sweep_results(std::int64_t id) {
  auto db = readers_.take();
  sqlite::ReadTransaction read(*db);
  auto exists = db->prepare("SELECT 1 FROM sweeps WHERE id = ?");
  exists.bind(1, id);
  if (!exists.step()) return std::nullopt;
  auto s = db->prepare(std::string("SELECT ") + job_columns +
                       " FROM sweep_jobs sj JOIN jobs j ON j.id = sj.job_id"
                       " LEFT JOIN results r ON r.job_id = j.id"
                       " WHERE sj.sweep_id = ? ORDER BY sj.position");
  s.bind(1, id);
  json rows = json::array();
  while (s.step()) rows.push_back(job_row_json(s));
  return rows;
}

// ---- jobs -----------------------------------------------------------------------------------

json JobStore::job_row_json(sqlite::Statement& s) {
  json j = {{"id", s.int64(0)},
            {"state", s.text(1)},
            {"S", s.real(2)},
            {"R", s.real(3)},
            {"phi", s.real(4)},
            {"cells_per_unit", s.int64(5)},
            {"eps_end", s.real(6)},
            {"engine_version", s.text(7)},
            {"scene", json::parse(s.text(8))},
            {"priority", s.int64(9)},
            {"attempts", s.int64(10)},
            {"max_attempts", s.int64(11)},
            {"worker", opt(s.opt_text(12))},
            {"progress_eps", opt(s.opt_real(13))},
            {"created_at", s.int64(14)},
            {"started_at", opt(s.opt_int64(15))},
            {"heartbeat_at", opt(s.opt_int64(16))},
            {"finished_at", opt(s.opt_int64(17))},
            {"run_after", s.int64(18)},
            {"lease_deadline", opt(s.opt_int64(19))},
            {"last_error", opt(s.opt_text(20))},
            {"result", nullptr}};
  if (!s.is_null(21)) {
    const auto features = s.opt_text(28);
    j["result"] = {{"status", s.text(21)},
                   {"reason", s.text(22)},
                   {"class", opt(s.opt_text(23))},
                   {"confidence", opt(s.opt_real(24))},
                   {"runner_up", opt(s.opt_text(25))},
                   {"n_reflections", opt(s.opt_int64(26))},
                   {"band_speed_ratio", opt(s.opt_real(27))},
                   {"features", features ? json::parse(*features) : json(nullptr)},
                   {"engine_version", s.text(29)},
                   {"source_revision", s.text(30)},
                   {"eps_reached", opt(s.opt_real(31))},
                   {"wall_seconds", opt(s.opt_real(32))},
                   {"worker", s.text(33)},
                   {"created_at", s.int64(34)}};
  }
  return j;
}

json JobStore::list_jobs(const JobFilter& f) {
  auto db = readers_.take();
  sqlite::ReadTransaction read(*db);
  // Absent filters bind NULL and match everything; phi matches within 1e-9.
  const std::string where =
      " WHERE (?1 IS NULL OR j.id IN (SELECT job_id FROM sweep_jobs WHERE sweep_id = ?1))"
      " AND (?2 IS NULL OR j.state = ?2) AND (?3 IS NULL OR abs(j.phi - ?3) < 1e-9)";
  auto bind_filters = [&](sqlite::Statement& s) {
    s.bind(1, f.sweep_id);
    if (f.state) {
      s.bind(2, to_string(*f.state));
    } else {
      s.bind_null(2);
    }
    s.bind(3, f.phi);
  };
  auto s = db->prepare(std::string("SELECT ") + job_columns +
                       " FROM jobs j LEFT JOIN results r ON r.job_id = j.id" + where +
                       " ORDER BY j.id LIMIT ?4 OFFSET ?5");
  bind_filters(s);
  s.bind(4, f.limit).bind(5, f.offset);
  json jobs = json::array();
  while (s.step()) jobs.push_back(job_row_json(s));
  auto n = db->prepare("SELECT count(*) FROM jobs j" + where);
  bind_filters(n);
  n.step();
  return {{"jobs", jobs}, {"total", n.int64(0)}, {"limit", f.limit}, {"offset", f.offset}};
}

std::optional<json> JobStore::job(std::int64_t id) {
  auto db = readers_.take();
  sqlite::ReadTransaction read(*db);
  auto s = db->prepare(std::string("SELECT ") + job_columns +
                       " FROM jobs j LEFT JOIN results r ON r.job_id = j.id WHERE j.id = ?");
  s.bind(1, id);
  if (!s.step()) return std::nullopt;
  json j = job_row_json(s);
  auto sweeps = db->prepare("SELECT sweep_id FROM sweep_jobs WHERE job_id = ? ORDER BY sweep_id");
  sweeps.bind(1, id);
  j["sweeps"] = json::array();
  while (sweeps.step()) j["sweeps"].push_back(sweeps.int64(0));
  auto events = db->prepare(
      "SELECT at, kind, attempt, worker, message FROM job_events WHERE job_id = ? ORDER BY id");
  events.bind(1, id);
  j["events"] = json::array();
  auto dropped = db->prepare("SELECT events_dropped FROM jobs WHERE id = ?");
  dropped.bind(1, id);
  j["events_dropped"] = dropped.step() ? dropped.int64(0) : 0;
  while (events.step()) {
    j["events"].push_back({{"at", events.int64(0)},
                           {"kind", events.text(1)},
                           {"attempt", events.int64(2)},
                           {"worker", opt(events.opt_text(3))},
                           {"message", events.text(4)}});
  }
  if (!j["result"].is_null()) {
    auto summary = db->prepare("SELECT summary FROM results WHERE job_id = ?");
    summary.bind(1, id);
    if (summary.step()) j["result"]["summary"] = json::parse(summary.text(0));
  }
  return j;
}

json JobStore::phase_map(double phi, std::optional<std::int64_t> sweep_id) {
  auto db = readers_.take();
  sqlite::ReadTransaction read(*db);
  auto s = db->prepare(
      "SELECT j.S, j.R, j.phi, j.state, r.class, r.confidence, r.runner_up, r.n_reflections,"
      " r.band_speed_ratio, j.id, r.status, j.cells_per_unit, j.eps_end, j.progress_eps"
      " FROM jobs j LEFT JOIN results r ON r.job_id = j.id"
      " WHERE abs(j.phi - ?1) < 1e-9"
      " AND (?2 IS NULL OR j.id IN (SELECT job_id FROM sweep_jobs WHERE sweep_id = ?2))"
      " ORDER BY j.S, j.R, j.id");
  s.bind(1, phi).bind(2, sweep_id);
  json points = json::array();
  while (s.step()) {
    points.push_back({{"S", s.real(0)},
                      {"R", s.real(1)},
                      {"phi", s.real(2)},
                      {"state", s.text(3)},
                      {"class", opt(s.opt_text(4))},
                      {"confidence", opt(s.opt_real(5))},
                      {"runner_up", opt(s.opt_text(6))},
                      {"n_reflections", opt(s.opt_int64(7))},
                      {"band_speed_ratio", opt(s.opt_real(8))},
                      {"job_id", s.int64(9)},
                      {"status", opt(s.opt_text(10))},
                      {"cells_per_unit", s.int64(11)},
                      {"eps_end", s.real(12)},
                      {"progress_eps", opt(s.opt_real(13))}});
  }
  return {{"phi", phi}, {"points", points}};
}

// ---- the queue ------------------------------------------------------------------------------

std::optional<Lease> JobStore::lease(const std::string& worker, const std::string& engine_version,
                                     Millis now) {
  std::lock_guard lock(mutex_);
  sqlite::Transaction tx(db_);
  const std::string token = new_token();
  // One atomic claim of the best queued job.
  auto s = db_.prepare(
      "UPDATE jobs SET state = 'running', lease_token = ?1, lease_deadline = ?2 + ?3,"
      " worker = ?4, attempts = attempts + 1, started_at = ?2, heartbeat_at = ?2,"
      " progress_eps = 0"
      " WHERE id = (SELECT id FROM jobs WHERE state = 'queued' AND run_after <= ?2"
      "             AND engine_version = ?5 ORDER BY priority DESC, id LIMIT 1)"
      " RETURNING id, lease_deadline, scene, attempts, max_attempts");
  s.bind(1, token).bind(2, now).bind(3, config_.lease_ms).bind(4, worker).bind(5, engine_version);
  if (!s.step()) return std::nullopt;
  Lease l{s.int64(0), token, s.int64(1), s.text(2), static_cast<int>(s.int64(3)),
          static_cast<int>(s.int64(4))};
  s.run();
  log_event(l.job_id, now, "leased", l.attempt, worker, "");
  tx.commit();
  return l;
}

namespace {
// Distinguishes "no such job" from "lease lost" after a guarded update changed nothing.
LeaseCheck missing_or_lost(sqlite::Database& db, std::int64_t job_id) {
  auto s = db.prepare("SELECT 1 FROM jobs WHERE id = ?");
  s.bind(1, job_id);
  return s.step() ? LeaseCheck::lost : LeaseCheck::unknown_job;
}
}  // namespace

LeaseCheck JobStore::check_lease(std::int64_t job_id, const std::string& token) {
  auto db = readers_.take();
  sqlite::ReadTransaction read(*db);
  auto s = db->prepare("SELECT 1 FROM jobs WHERE id = ? AND state = 'running' AND lease_token = ?");
  s.bind(1, job_id).bind(2, token);
  return s.step() ? LeaseCheck::ok : missing_or_lost(*db, job_id);
}

LeaseCheck JobStore::heartbeat(std::int64_t job_id, const std::string& token, double eps,
                               Millis now, Millis& deadline) {
  std::lock_guard lock(mutex_);
  sqlite::Transaction tx(db_);
  auto s = db_.prepare(
      "UPDATE jobs SET lease_deadline = ?3 + ?4, heartbeat_at = ?3, progress_eps = ?5"
      " WHERE id = ?1 AND state = 'running' AND lease_token = ?2 RETURNING lease_deadline");
  s.bind(1, job_id).bind(2, token).bind(3, now).bind(4, config_.lease_ms).bind(5, eps);
  if (!s.step()) return missing_or_lost(db_, job_id);
  deadline = s.int64(0);
  s.run();
  tx.commit();
  return LeaseCheck::ok;
}

LeaseCheck JobStore::complete(std::int64_t job_id, const std::string& token,
                              const ResultRecord& r, Millis now) {
  // The files first, without the lock: the folder is named after the lease, so a concurrent
  // upload with another token never writes into it. Removed again unless the commit names it.
  const std::string folder = "job-" + std::to_string(job_id) + "-" + token_folder_name(token);
  const std::vector<std::string> paths = files_.write(folder, r.artifacts);
  struct RemoveUnlessKept {
    ArtifactFiles& files;
    const std::string& folder;
    bool keep = false;
    ~RemoveUnlessKept() {
      if (!keep) files.remove(folder);
    }
  } files_guard{files_, folder};
  std::lock_guard lock(mutex_);
  sqlite::Transaction tx(db_);
  auto s = db_.prepare(
      "UPDATE jobs SET state = 'succeeded', lease_token = NULL, lease_deadline = NULL,"
      " finished_at = ?3, progress_eps = ?4"
      " WHERE id = ?1 AND state = 'running' AND lease_token = ?2 RETURNING attempts, worker");
  s.bind(1, job_id).bind(2, token).bind(3, now).bind(4, r.eps_reached);
  if (!s.step()) return missing_or_lost(db_, job_id);
  const int attempt = static_cast<int>(s.int64(0));
  const std::string worker = s.text(1);
  s.run();
  // The primary key on results.job_id refuses a second result: it can never be overwritten.
  db_.prepare(
        "INSERT INTO results (job_id, status, reason, scene, engine_version, source_revision,"
        " class, confidence, runner_up, n_reflections, band_speed_ratio, features, eps_reached,"
        " wall_seconds, summary, worker, created_at)"
        " VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)")
      .bind(1, job_id)
      .bind(2, r.status)
      .bind(3, r.reason)
      .bind(4, r.scene)
      .bind(5, r.engine_version)
      .bind(6, r.source_revision)
      .bind(7, r.cls)
      .bind(8, r.confidence)
      .bind(9, r.runner_up)
      .bind(10, r.n_reflections)
      .bind(11, r.band_speed_ratio)
      .bind(12, r.features)
      .bind(13, r.eps_reached)
      .bind(14, r.wall_seconds)
      .bind(15, r.summary)
      .bind(16, worker)
      .bind(17, now)
      .run();
  auto art = db_.prepare(
      "INSERT INTO artifacts (job_id, name, content_type, size, data, path)"
      " VALUES (?, ?, ?, ?, X'', ?)");
  for (std::size_t i = 0; i < r.artifacts.size(); ++i) {
    const Artifact& a = r.artifacts[i];
    art.reset();
    art.bind(1, job_id)
        .bind(2, a.name)
        .bind(3, a.content_type)
        .bind(4, static_cast<std::int64_t>(a.data.size()))
        .bind(5, paths[i])
        .run();
  }
  log_event(job_id, now, "succeeded", attempt, worker,
            r.status == "ok" ? "" : "unstable: " + r.reason);
  tx.commit();
  files_guard.keep = true;
  return LeaseCheck::ok;
}

FailOutcome JobStore::fail(std::int64_t job_id, const std::string& token,
                           const std::string& reason, bool retryable, Millis now) {
  std::lock_guard lock(mutex_);
  sqlite::Transaction tx(db_);
  auto s = db_.prepare(
      "SELECT attempts, max_attempts, worker FROM jobs"
      " WHERE id = ?1 AND state = 'running' AND lease_token = ?2");
  s.bind(1, job_id).bind(2, token);
  if (!s.step()) return {missing_or_lost(db_, job_id)};
  const int attempts = static_cast<int>(s.int64(0));
  const int max_attempts = static_cast<int>(s.int64(1));
  const std::string worker = s.text(2);
  FailOutcome out;
  out.state = retryable && attempts < max_attempts ? JobState::queued : JobState::failed;
  out.run_after = out.state == JobState::queued ? now + backoff(attempts) : now;
  db_.prepare(
        "UPDATE jobs SET state = ?3, lease_token = NULL, lease_deadline = NULL, last_error = ?4,"
        " run_after = ?5, finished_at = CASE WHEN ?3 = 'failed' THEN ?6 ELSE NULL END"
        " WHERE id = ?1 AND state = 'running' AND lease_token = ?2")
      .bind(1, job_id)
      .bind(2, token)
      .bind(3, to_string(out.state))
      .bind(4, reason)
      .bind(5, out.run_after)
      .bind(6, now)
      .run();
  log_event(job_id, now, out.state == JobState::queued ? "retry" : "failed", attempts, worker,
            reason);
  tx.commit();
  return out;
}

LeaseCheck JobStore::release(std::int64_t job_id, const std::string& token, Millis now) {
  std::lock_guard lock(mutex_);
  sqlite::Transaction tx(db_);
  auto s = db_.prepare(
      "UPDATE jobs SET state = 'queued', lease_token = NULL, lease_deadline = NULL,"
      " attempts = max(attempts - 1, 0), run_after = ?3, progress_eps = NULL"
      " WHERE id = ?1 AND state = 'running' AND lease_token = ?2 RETURNING attempts, worker");
  s.bind(1, job_id).bind(2, token).bind(3, now);
  if (!s.step()) return missing_or_lost(db_, job_id);
  const int attempt = static_cast<int>(s.int64(0));
  const std::string worker = s.text(1);
  s.run();
  log_event(job_id, now, "released", attempt + 1, worker, "the worker stopped");
  tx.commit();
  return LeaseCheck::ok;
}

int JobStore::requeue_expired(Millis now) {
  std::lock_guard lock(mutex_);
  sqlite::Transaction tx(db_);
  auto s = db_.prepare(
      "SELECT id, attempts, max_attempts, worker, lease_deadline FROM jobs"
      " WHERE state = 'running' AND lease_deadline < ?");
  s.bind(1, now);
  struct Expired {
    std::int64_t id;
    int attempts, max_attempts;
    std::optional<std::string> worker;
    Millis deadline;
  };
  std::vector<Expired> expired;
  while (s.step()) {
    expired.push_back({s.int64(0), static_cast<int>(s.int64(1)), static_cast<int>(s.int64(2)),
                       s.opt_text(3), s.int64(4)});
  }
  auto move = db_.prepare(
      "UPDATE jobs SET state = ?2, lease_token = NULL, lease_deadline = NULL, last_error = ?3,"
      " run_after = ?4, finished_at = CASE WHEN ?2 = 'failed' THEN ?4 ELSE NULL END"
      " WHERE id = ?1 AND state = 'running' AND lease_deadline = ?5");
  for (const Expired& e : expired) {
    const bool give_up = e.attempts >= e.max_attempts;
    const std::string why = "lease expired (no heartbeat from " + e.worker.value_or("?") +
                            " since the deadline)";
    move.reset();
    move.bind(1, e.id)
        .bind(2, give_up ? "failed" : "queued")
        .bind(3, why)
        .bind(4, now)
        .bind(5, e.deadline)
        .run();
    log_event(e.id, now, "lease_expired", e.attempts, e.worker,
              give_up ? why + "; attempts used up" : why);
  }
  tx.commit();
  return static_cast<int>(expired.size());
}

std::optional<std::pair<std::string, std::string>> JobStore::job_scene(std::int64_t job_id) {
  auto db = readers_.take();
  sqlite::ReadTransaction read(*db);
  auto s = db->prepare("SELECT scene, engine_version FROM jobs WHERE id = ?");
  s.bind(1, job_id);
  if (!s.step()) return std::nullopt;
  return std::make_pair(s.text(0), s.text(1));
}

// ---- artifacts ------------------------------------------------------------------------------

std::optional<json> JobStore::list_artifacts(std::int64_t job_id) {
  auto db = readers_.take();
  sqlite::ReadTransaction read(*db);
  auto exists = db->prepare("SELECT 1 FROM jobs WHERE id = ?");
  exists.bind(1, job_id);
  if (!exists.step()) return std::nullopt;
  auto s = db->prepare(
      "SELECT name, content_type, size FROM artifacts WHERE job_id = ? ORDER BY name");
  s.bind(1, job_id);
  json out = json::array();
  while (s.step()) {
    out.push_back({{"name", s.text(0)}, {"content_type", s.text(1)}, {"size", s.int64(2)}});
  }
  return out;
}

std::optional<Artifact> JobStore::artifact(std::int64_t job_id, const std::string& name) {
  auto db = readers_.take();
  sqlite::ReadTransaction read(*db);
  auto s = db->prepare(
      "SELECT name, content_type, data, path FROM artifacts WHERE job_id = ? AND name = ?");
  s.bind(1, job_id).bind(2, name);
  if (!s.step()) return std::nullopt;
  const auto path = s.opt_text(3);
  return Artifact{s.text(0), s.text(1), path ? files_.read(*path) : s.blob(2)};
}

// ---- metrics --------------------------------------------------------------------------------

StoreMetrics JobStore::metrics() {
  auto db = readers_.take();
  sqlite::ReadTransaction read(*db);
  StoreMetrics m;
  auto by_state = db->prepare("SELECT state, count(*) FROM jobs GROUP BY state ORDER BY state");
  while (by_state.step()) m.jobs_by_state.emplace_back(by_state.text(0), by_state.int64(1));
  auto by_kind = db->prepare("SELECT kind, total FROM event_totals ORDER BY kind");
  while (by_kind.step()) m.events_by_kind.emplace_back(by_kind.text(0), by_kind.int64(1));
  auto by_status =
      db->prepare("SELECT status, count(*) FROM results GROUP BY status ORDER BY status");
  while (by_status.step()) m.results_by_status.emplace_back(by_status.text(0), by_status.int64(1));
  auto sweeps = db->prepare("SELECT count(*) FROM sweeps");
  sweeps.step();
  m.sweeps = sweeps.int64(0);
  return m;
}

std::string JobStore::fingerprint() {
  auto db = readers_.take();
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
