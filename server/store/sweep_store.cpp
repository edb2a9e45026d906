#include "store/sweep_store.hpp"

#include <tuple>

namespace compaction::server {

CreatedSweep SweepStore::create(const NewSweep& plan, Millis now) {
  std::unique_lock lock(db_.write_mutex);
  sqlite::Transaction tx(db_.writer);
  CreatedSweep out;
  db_.writer.prepare("INSERT INTO sweeps (name, request, priority, created_at) VALUES (?, ?, ?, ?)")
      .bind(1, plan.name)
      .bind(2, plan.request)
      .bind(3, plan.priority)
      .bind(4, now)
      .run();
  out.id = db_.writer.last_insert_rowid();

  link_jobs(out.id, 0, plan.jobs, plan.priority, plan.max_attempts, now, out);
  tx.commit();
  db_.wait_durable(lock);
  return out;
}

void SweepStore::link_jobs(std::int64_t sweep_id, std::int64_t position,
                           const std::vector<NewJob>& jobs, int priority, int max_attempts,
                           Millis now, CreatedSweep& out) {
  auto insert = db_.writer.prepare(
      "INSERT INTO jobs (identity, scene, engine_version, S, R, phi, cells_per_unit, eps_end,"
      " priority, max_attempts, run_after, created_at, structure)"
      " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?11, ?12)"
      " ON CONFLICT (identity) DO NOTHING");
  auto find = db_.writer.prepare("SELECT id, state FROM jobs WHERE identity = ?");
  // A job another sweep already holds: raise its priority to the highest that wants it.
  auto raise = db_.writer.prepare("UPDATE jobs SET priority = max(priority, ?2) WHERE id = ?1");
  // Failed or cancelled before: a new sweep asks again, with fresh attempts.
  auto requeue = db_.writer.prepare(
      "UPDATE jobs SET state = 'queued', attempts = 0, max_attempts = ?2, run_after = ?3,"
      " priority = ?4, finished_at = NULL, progress_eps = NULL"
      " WHERE id = ?1 AND state IN ('failed', 'cancelled')");
  auto link = db_.writer.prepare(
      "INSERT OR IGNORE INTO sweep_jobs (sweep_id, job_id, position) VALUES (?, ?, ?)");

  for (const NewJob& p : jobs) {
    insert.reset();
    insert.bind(1, p.identity)
        .bind(2, p.scene)
        .bind(3, db_.config.engine_version)
        .bind(4, p.S)
        .bind(5, p.R)
        .bind(6, p.phi)
        .bind(7, p.cells_per_unit)
        .bind(8, p.eps_end)
        .bind(9, priority)
        .bind(10, max_attempts)
        .bind(11, now)
        .bind(12, p.structure)
        .run();
    const bool created = db_.writer.changes() > 0;
    find.reset();
    find.bind(1, p.identity);
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
      requeue.bind(1, job_id).bind(2, max_attempts).bind(3, now).bind(4, priority).run();
      log_event(db_.writer, job_id, now, "queued", 0, std::nullopt,
                "requeued by sweep " + std::to_string(sweep_id) + " (was " + state + ")");
      ++out.n_requeued;
    } else {
      raise.reset();
      raise.bind(1, job_id).bind(2, priority).run();
      ++out.n_shared;
    }
    link.reset();
    link.bind(1, sweep_id).bind(2, job_id).bind(3, position++).run();
    ++out.n_jobs;
  }
}

std::optional<CreatedSweep> SweepStore::add_jobs(std::int64_t sweep_id,
                                                 const std::vector<NewJob>& jobs, int priority,
                                                 int max_attempts, Millis now) {
  std::unique_lock lock(db_.write_mutex);
  sqlite::Transaction tx(db_.writer);
  if (!db_.writer.has_row("SELECT 1 FROM sweeps WHERE id = ?", sweep_id)) return std::nullopt;
  auto next = db_.writer.prepare(
      "SELECT coalesce(max(position) + 1, 0) FROM sweep_jobs WHERE sweep_id = ?");
  next.bind(1, sweep_id);
  next.step();
  const std::int64_t position = next.int64(0);
  next.reset();
  CreatedSweep out;
  out.id = sweep_id;
  link_jobs(sweep_id, position, jobs, priority, max_attempts, now, out);
  tx.commit();
  db_.wait_durable(lock);
  return out;
}

std::optional<std::int64_t> SweepStore::cancel(std::int64_t id, Millis now) {
  std::unique_lock lock(db_.write_mutex);
  sqlite::Transaction tx(db_.writer);
  if (!db_.writer.has_row("SELECT 1 FROM sweeps WHERE id = ?", id)) return std::nullopt;
  db_.writer.prepare("UPDATE sweeps SET cancelled_at = ?2 WHERE id = ?1 AND cancelled_at IS NULL")
      .bind(1, id)
      .bind(2, now)
      .run();
  // Jobs of this sweep that no other live sweep wants; a running one loses its lease (the
  // worker hears 409 at its next heartbeat and stops the run).
  auto victims = db_.writer.prepare(
      "SELECT j.id, j.attempts, j.worker FROM sweep_jobs sj JOIN jobs j ON j.id = sj.job_id"
      " WHERE sj.sweep_id = ?1 AND j.state IN ('queued', 'running')"
      " AND NOT EXISTS (SELECT 1 FROM sweep_jobs o JOIN sweeps w ON w.id = o.sweep_id"
      "                 WHERE o.job_id = j.id AND o.sweep_id <> ?1 AND w.cancelled_at IS NULL)");
  victims.bind(1, id);
  std::vector<std::tuple<std::int64_t, int, std::optional<std::string>>> jobs;
  while (victims.step()) {
    jobs.emplace_back(victims.int64(0), static_cast<int>(victims.int64(1)), victims.opt_text(2));
  }
  auto cancel = db_.writer.prepare(
      "UPDATE jobs SET state = 'cancelled', lease_token = NULL, lease_deadline = NULL,"
      " finished_at = ?2 WHERE id = ?1 AND state IN ('queued', 'running')");
  for (const auto& [job_id, attempt, worker] : jobs) {
    cancel.reset();
    cancel.bind(1, job_id).bind(2, now).run();
    log_event(db_.writer, job_id, now, "cancelled", attempt, worker, "sweep " + std::to_string(id) + " cancelled");
  }
  tx.commit();
  db_.wait_durable(lock);
  return static_cast<std::int64_t>(jobs.size());
}

std::vector<std::int64_t> live_adaptive_sweeps_of_job(sqlite::Database& db, std::int64_t job_id) {
  auto s = db.prepare(
      "SELECT s.id FROM sweep_jobs sj JOIN sweeps s ON s.id = sj.sweep_id"
      " WHERE sj.job_id = ? AND s.cancelled_at IS NULL AND s.origin_database IS NULL"
      " AND json_extract(s.request, '$.adaptive') IS NOT NULL ORDER BY s.id");
  s.bind(1, job_id);
  std::vector<std::int64_t> out;
  while (s.step()) out.push_back(s.int64(0));
  return out;
}

}  // namespace compaction::server
