#include "store/checkpoint_store.hpp"

#include <set>

#include <spdlog/spdlog.h>

namespace compaction::server {

namespace {

constexpr const char* kFileName = "checkpoint.bin";

std::string folder_of(const std::string& path) { return path.substr(0, path.find('/')); }

// The attempt and worker of the job's live lease `token`, inside the caller's transaction.
struct LiveLease {
  LeaseCheck check = LeaseCheck::ok;
  int attempt = 0;
  std::string worker;
};
LiveLease live_lease(sqlite::Database& db, std::int64_t job_id, const std::string& token) {
  auto s = db.prepare(
      "SELECT attempts, worker FROM jobs WHERE id = ? AND state = 'running' AND lease_token = ?");
  s.bind(1, job_id).bind(2, token);
  if (!s.step()) {
    LiveLease none;
    none.check = db.has_row("SELECT 1 FROM jobs WHERE id = ?", job_id) ? LeaseCheck::lost
                                                                       : LeaseCheck::unknown_job;
    return none;
  }
  return {LeaseCheck::ok, static_cast<int>(s.int64(0)), s.text(1)};
}

std::string where(std::int64_t step, double eps) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "step %lld, eps %.6g", static_cast<long long>(step), eps);
  return buf;
}

}  // namespace

CheckpointStore::CheckpointStore(StoreDb& db, std::filesystem::path root)
    : db_(db), files_(std::move(root)) {
  std::lock_guard lock(db_.write_mutex);
  sqlite::Transaction tx(db_.writer);
  // A job that ended while the server went down between its commit and the removal.
  db_.writer
      .prepare("DELETE FROM job_checkpoints WHERE job_id IN"
               " (SELECT id FROM jobs WHERE state IN ('succeeded', 'failed'))")
      .run();
  std::set<std::string> keep;
  auto s = db_.writer.prepare("SELECT path FROM job_checkpoints");
  while (s.step()) keep.insert(folder_of(s.text(0)));
  tx.commit();
  if (const int n = files_.remove_all_but(keep); n > 0) {
    spdlog::info("removed {} checkpoint folder(s) no job needs", n);
  }
}

LeaseCheck CheckpointStore::put(std::int64_t job_id, const std::string& token,
                                const std::string& bytes, std::int64_t step, double eps,
                                Millis now) {
  // The file first, without the lock, in a folder of its own; removed unless the commit names it.
  const std::string folder = "job-" + std::to_string(job_id) + "-" + std::to_string(now) + "-s" +
                             std::to_string(step);
  const std::string path = files_.write(folder, {{kFileName, "application/octet-stream", bytes, std::nullopt}})[0];
  struct RemoveUnlessKept {
    ArtifactFiles& files;
    const std::string& folder;
    bool keep = false;
    ~RemoveUnlessKept() {
      if (!keep) files.remove(folder);
    }
  } guard{files_, folder};

  std::optional<std::string> replaced;
  {
    std::lock_guard lock(db_.write_mutex);
    sqlite::Transaction tx(db_.writer);
    const LiveLease lease = live_lease(db_.writer, job_id, token);
    if (lease.check != LeaseCheck::ok) return lease.check;
    auto old = db_.writer.prepare("SELECT path FROM job_checkpoints WHERE job_id = ?");
    old.bind(1, job_id);
    if (old.step()) replaced = old.text(0);
    db_.writer
        .prepare(
            "INSERT INTO job_checkpoints (job_id, path, size, step, eps, worker, attempt, created_at)"
            " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8) ON CONFLICT (job_id) DO UPDATE SET"
            " path = ?2, size = ?3, step = ?4, eps = ?5, worker = ?6, attempt = ?7, created_at = ?8")
        .bind(1, job_id)
        .bind(2, path)
        .bind(3, static_cast<std::int64_t>(bytes.size()))
        .bind(4, step)
        .bind(5, eps)
        .bind(6, lease.worker)
        .bind(7, lease.attempt)
        .bind(8, now)
        .run();
    log_event(db_.writer, job_id, now, "checkpoint", lease.attempt, lease.worker,
              "checkpoint at " + where(step, eps) + ", " + std::to_string(bytes.size()) + " bytes");
    tx.commit();
    guard.keep = true;
  }
  if (replaced && folder_of(*replaced) != folder) files_.remove(folder_of(*replaced));
  return LeaseCheck::ok;
}

std::optional<StoredCheckpoint> find_checkpoint(sqlite::Database& db, std::int64_t job_id) {
  auto s = db.prepare(
      "SELECT path, size, step, eps, worker, attempt, created_at FROM job_checkpoints"
      " WHERE job_id = ?");
  s.bind(1, job_id);
  if (!s.step()) return std::nullopt;
  return StoredCheckpoint{job_id,       s.text(0),  s.int64(1), s.int64(2), s.real(3),
                          s.text(4),    static_cast<int>(s.int64(5)), s.int64(6)};
}

std::optional<StoredCheckpoint> CheckpointStore::find(std::int64_t job_id) {
  auto db = db_.readers.take();
  sqlite::ReadTransaction read(*db);
  return find_checkpoint(*db, job_id);
}

std::string CheckpointStore::read(const StoredCheckpoint& c) const { return files_.read(c.path); }

LeaseCheck CheckpointStore::record_resume(std::int64_t job_id, const std::string& token,
                                          std::int64_t step, double eps, Millis now) {
  std::lock_guard lock(db_.write_mutex);
  sqlite::Transaction tx(db_.writer);
  const LiveLease lease = live_lease(db_.writer, job_id, token);
  if (lease.check != LeaseCheck::ok) return lease.check;
  db_.writer
      .prepare("INSERT INTO job_resumes (job_id, at, worker, attempt, step, eps)"
               " VALUES (?, ?, ?, ?, ?, ?)")
      .bind(1, job_id)
      .bind(2, now)
      .bind(3, lease.worker)
      .bind(4, lease.attempt)
      .bind(5, step)
      .bind(6, eps)
      .run();
  log_event(db_.writer, job_id, now, "resumed", lease.attempt, lease.worker,
            "resumed from the checkpoint at " + where(step, eps));
  tx.commit();
  return LeaseCheck::ok;
}

std::vector<Resume> CheckpointStore::resumes(std::int64_t job_id) {
  auto db = db_.readers.take();
  sqlite::ReadTransaction read(*db);
  auto s = db->prepare(
      "SELECT at, worker, attempt, step, eps FROM job_resumes WHERE job_id = ? ORDER BY id");
  s.bind(1, job_id);
  std::vector<Resume> out;
  while (s.step()) {
    out.push_back({s.int64(0), s.text(1), static_cast<int>(s.int64(2)), s.int64(3), s.real(4)});
  }
  return out;
}

void CheckpointStore::remove_if_done(std::int64_t job_id) {
  {
    // Most jobs end without a checkpoint: a read says so without taking the write lock. A job
    // that ended takes no new checkpoint (put needs its live lease), so none appears after it.
    auto db = db_.readers.take();
    sqlite::ReadTransaction read(*db);
    if (!db->has_row("SELECT 1 FROM job_checkpoints WHERE job_id = ?", job_id)) return;
  }
  std::optional<std::string> path;
  {
    std::lock_guard lock(db_.write_mutex);
    sqlite::Transaction tx(db_.writer);
    auto s = db_.writer.prepare(
        "DELETE FROM job_checkpoints WHERE job_id = ?1 AND job_id IN"
        " (SELECT id FROM jobs WHERE id = ?1 AND state IN ('succeeded', 'failed')) RETURNING path");
    s.bind(1, job_id);
    if (s.step()) path = s.text(0);
    s.run();
    tx.commit();
  }
  if (path) files_.remove(folder_of(*path));
}

}  // namespace compaction::server
