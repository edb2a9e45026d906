#include "store/queue_store.hpp"

#include <algorithm>
#include <random>

#include "store/sweep_store.hpp"

namespace compaction::server {

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

// Distinguishes "no such job" from "lease lost" after a guarded update changed nothing.
LeaseCheck missing_or_lost(sqlite::Database& db, std::int64_t job_id) {
  return db.has_row("SELECT 1 FROM jobs WHERE id = ?", job_id) ? LeaseCheck::lost
                                                                : LeaseCheck::unknown_job;
}

}  // namespace

void insert_result(sqlite::Database& w, std::int64_t job_id, const ResultRecord& r,
                   const std::string& worker, Millis created_at,
                   const std::vector<std::string>& paths, const std::optional<ResultOrigin>& origin) {
  // The phase map's band-speed readings are columns of their own, read from the features (?12)
  // here: a number, or NULL when the key is absent, null or not a number (migrations 0008,
  // 0009).
  auto feature = [](const char* key) {
    return std::string("CASE WHEN json_type(?12, '$.") + key +
           "') IN ('real', 'integer') THEN json_extract(?12, '$." + key + "') END";
  };
  w.prepare(
       "INSERT INTO results (job_id, status, reason, scene, engine_version, source_revision,"
       " class, confidence, runner_up, n_reflections, band_speed_ratio, features, eps_reached,"
       " wall_seconds, summary, worker, created_at, origin_database, origin_job, imported_at,"
       " band_speed_error, band_speed_transit, band_speed_transit_error, band_speed_early,"
       " band_speed_early_error, band_speed_lead, band_speed_lead_error)"
       " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16, ?17, ?18,"
       " ?19, ?20, " + feature("band_speed_error") + ", " + feature("band_speed_transit") + ", " +
       feature("band_speed_transit_error") + ", " + feature("band_speed_early") + ", " +
       feature("band_speed_early_error") + ", " + feature("band_speed_lead") + ", " +
       feature("band_speed_lead_error") + ")")
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
      .bind(17, created_at)
      .bind(18, origin ? std::optional<std::string>(origin->database) : std::nullopt)
      .bind(19, origin ? std::optional<std::int64_t>(origin->job) : std::nullopt)
      .bind(20, origin ? std::optional<Millis>(origin->imported_at) : std::nullopt)
      .run();
  auto art = w.prepare(
      "INSERT INTO artifacts (job_id, name, content_type, size, data, path)"
      " VALUES (?, ?, ?, ?, X'', ?)");
  for (std::size_t i = 0; i < r.artifacts.size(); ++i) {
    const Artifact& a = r.artifacts[i];
    art.reset();
    art.bind(1, job_id)
        .bind(2, a.name)
        .bind(3, a.content_type)
        .bind(4, static_cast<std::int64_t>(a.file_size.value_or(a.data.size())))
        .bind(5, paths[i])
        .run();
  }
}

Millis QueueStore::backoff(int attempts) const {
  Millis d = db_.config.backoff_base_ms;
  for (int i = 1; i < attempts && d < db_.config.backoff_max_ms; ++i) d *= 2;
  return std::min(d, db_.config.backoff_max_ms);
}

std::optional<Lease> QueueStore::lease(const std::string& worker, const std::string& engine_version,
                                     Millis now) {
  std::lock_guard lock(db_.write_mutex);
  sqlite::Transaction tx(db_.writer);
  std::optional<Lease> l = claim(worker, engine_version, now);
  if (l) tx.commit();
  return l;
}

std::optional<Lease> QueueStore::claim(const std::string& worker, const std::string& engine_version,
                                     Millis now) {
  const std::string token = new_token();
  // One atomic claim of the best queued job.
  auto s = db_.writer.prepare(
      "UPDATE jobs SET state = 'running', lease_token = ?1, lease_deadline = ?2 + ?3,"
      " worker = ?4, attempts = attempts + 1, started_at = ?2, heartbeat_at = ?2,"
      " progress_eps = 0"
      " WHERE id = (SELECT id FROM jobs WHERE state = 'queued' AND run_after <= ?2"
      "             AND engine_version = ?5 ORDER BY priority DESC, id LIMIT 1)"
      " RETURNING id, lease_deadline, scene, attempts, max_attempts");
  s.bind(1, token).bind(2, now).bind(3, db_.config.lease_ms).bind(4, worker).bind(5, engine_version);
  if (!s.step()) return std::nullopt;
  Lease l{s.int64(0), token, s.int64(1), s.text(2), static_cast<int>(s.int64(3)),
          static_cast<int>(s.int64(4)), std::nullopt};
  s.run();
  l.checkpoint = find_checkpoint(db_.writer, l.job_id);
  log_event(db_.writer, l.job_id, now, "leased", l.attempt, worker, "");
  return l;
}

LeaseCheck QueueStore::check_lease(std::int64_t job_id, const std::string& token) {
  auto db = db_.readers.take();
  sqlite::ReadTransaction read(*db);
  auto s = db->prepare("SELECT 1 FROM jobs WHERE id = ? AND state = 'running' AND lease_token = ?");
  s.bind(1, job_id).bind(2, token);
  return s.step() ? LeaseCheck::ok : missing_or_lost(*db, job_id);
}

QueueStore::LeasedJob QueueStore::leased_job(std::int64_t job_id, const std::string& token) {
  auto db = db_.readers.take();
  sqlite::ReadTransaction read(*db);
  auto s = db->prepare(
      "SELECT scene, engine_version FROM jobs WHERE id = ? AND state = 'running' AND lease_token = ?");
  s.bind(1, job_id).bind(2, token);
  if (!s.step()) return {missing_or_lost(*db, job_id), {}, {}};
  return {LeaseCheck::ok, s.text(0), s.text(1)};
}

LeaseCheck QueueStore::heartbeat(std::int64_t job_id, const std::string& token, double eps,
                               Millis now, Millis& deadline, std::string* worker) {
  std::lock_guard lock(db_.write_mutex);
  sqlite::Transaction tx(db_.writer);
  auto s = db_.writer.prepare(
      "UPDATE jobs SET lease_deadline = ?3 + ?4, heartbeat_at = ?3, progress_eps = ?5"
      " WHERE id = ?1 AND state = 'running' AND lease_token = ?2 RETURNING lease_deadline, worker");
  s.bind(1, job_id).bind(2, token).bind(3, now).bind(4, db_.config.lease_ms).bind(5, eps);
  if (!s.step()) return missing_or_lost(db_.writer, job_id);
  deadline = s.int64(0);
  if (worker) *worker = s.text(1);
  s.run();
  tx.commit();
  return LeaseCheck::ok;
}

LeaseCheck QueueStore::complete(std::int64_t job_id, const std::string& token,
                              const ResultRecord& r, Millis now,
                              const std::optional<LeaseRequest>& next, FollowUps* follow_ups) {
  // The files first, without the lock: the folder is named after the lease, so a concurrent
  // upload with another token never writes into it. Removed again unless the commit names it.
  const std::string folder = "job-" + std::to_string(job_id) + "-" + token_folder_name(token);
  const std::vector<std::string> paths = db_.files.write(folder, r.artifacts);
  struct RemoveUnlessKept {
    ArtifactFiles& files;
    const std::string& folder;
    bool keep = false;
    ~RemoveUnlessKept() {
      if (!keep) files.remove(folder);
    }
  } files_guard{db_.files, folder};
  // The statements go into a transaction shared with the completions that arrive at the same
  // time (group commit): one commit, and its WAL pages written once, for all of them.
  LeaseCheck check = LeaseCheck::ok;
  db_.group_commit.run([&] {
    auto s = db_.writer.prepare(
        "UPDATE jobs SET state = 'succeeded', lease_token = NULL, lease_deadline = NULL,"
        " finished_at = ?3, progress_eps = ?4"
        " WHERE id = ?1 AND state = 'running' AND lease_token = ?2 RETURNING attempts, worker");
    s.bind(1, job_id).bind(2, token).bind(3, now).bind(4, r.eps_reached);
    if (!s.step()) {
      check = missing_or_lost(db_.writer, job_id);
      return;
    }
    const int attempt = static_cast<int>(s.int64(0));
    const std::string worker = s.text(1);
    s.run();
    insert_result(db_.writer, job_id, r, worker, now, paths);
    log_event(db_.writer, job_id, now, "succeeded", attempt, worker,
              r.status == "ok" ? "" : "unstable: " + r.reason);
    if (follow_ups) {
      follow_ups->checkpoint = find_checkpoint(db_.writer, job_id).has_value();
      follow_ups->adaptive_sweeps = live_adaptive_sweeps_of_job(db_.writer, job_id);
      if (next) follow_ups->next = claim(next->worker, next->engine_version, now);
    }
  });
  if (check != LeaseCheck::ok) return check;
  files_guard.keep = true;
  db_.wait_durable();
  return LeaseCheck::ok;
}

FailOutcome QueueStore::fail(std::int64_t job_id, const std::string& token,
                           const std::string& reason, bool retryable, Millis now) {
  std::lock_guard lock(db_.write_mutex);
  sqlite::Transaction tx(db_.writer);
  auto s = db_.writer.prepare(
      "SELECT attempts, max_attempts, worker FROM jobs"
      " WHERE id = ?1 AND state = 'running' AND lease_token = ?2");
  s.bind(1, job_id).bind(2, token);
  if (!s.step()) return {missing_or_lost(db_.writer, job_id)};
  const int attempts = static_cast<int>(s.int64(0));
  const int max_attempts = static_cast<int>(s.int64(1));
  const std::string worker = s.text(2);
  FailOutcome out;
  out.state = retryable && attempts < max_attempts ? JobState::queued : JobState::failed;
  out.run_after = out.state == JobState::queued ? now + backoff(attempts) : now;
  db_.writer.prepare(
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
  log_event(db_.writer, job_id, now, out.state == JobState::queued ? "retry" : "failed", attempts, worker,
            reason);
  tx.commit();
  return out;
}

LeaseCheck QueueStore::release(std::int64_t job_id, const std::string& token, Millis now) {
  std::lock_guard lock(db_.write_mutex);
  sqlite::Transaction tx(db_.writer);
  auto s = db_.writer.prepare(
      "UPDATE jobs SET state = 'queued', lease_token = NULL, lease_deadline = NULL,"
      " attempts = max(attempts - 1, 0), run_after = ?3, progress_eps = NULL"
      " WHERE id = ?1 AND state = 'running' AND lease_token = ?2 RETURNING attempts, worker");
  s.bind(1, job_id).bind(2, token).bind(3, now);
  if (!s.step()) return missing_or_lost(db_.writer, job_id);
  const int attempt = static_cast<int>(s.int64(0));
  const std::string worker = s.text(1);
  s.run();
  log_event(db_.writer, job_id, now, "released", attempt + 1, worker, "the worker stopped");
  tx.commit();
  return LeaseCheck::ok;
}

int QueueStore::requeue_expired(Millis now) {
  std::lock_guard lock(db_.write_mutex);
  sqlite::Transaction tx(db_.writer);
  auto s = db_.writer.prepare(
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
  auto move = db_.writer.prepare(
      "UPDATE jobs SET state = ?2, lease_token = NULL, lease_deadline = NULL, last_error = ?3,"
      " run_after = ?4, finished_at = CASE WHEN ?2 = 'failed' THEN ?4 ELSE NULL END"
      " WHERE id = ?1 AND state = 'running' AND lease_deadline = ?5");
  auto by_worker = db_.writer.prepare(
      "INSERT INTO worker_lease_expiries (worker, total, last_at) VALUES (?1, 1, ?2)"
      " ON CONFLICT (worker) DO UPDATE SET total = total + 1, last_at = max(last_at, ?2)");
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
    log_event(db_.writer, e.id, now, "lease_expired", e.attempts, e.worker,
              give_up ? why + "; attempts used up" : why);
    if (e.worker) {
      by_worker.reset();
      by_worker.bind(1, *e.worker).bind(2, now).run();
    }
  }
  tx.commit();
  return static_cast<int>(expired.size());
}

std::optional<std::pair<std::string, std::string>> QueueStore::job_scene(std::int64_t job_id) {
  auto db = db_.readers.take();
  sqlite::ReadTransaction read(*db);
  auto s = db->prepare("SELECT scene, engine_version FROM jobs WHERE id = ?");
  s.bind(1, job_id);
  if (!s.step()) return std::nullopt;
  return std::make_pair(s.text(0), s.text(1));
}

}  // namespace compaction::server
