#include "store/store_db.hpp"

#include <set>

#include <spdlog/spdlog.h>

#include "store/migrations.hpp"
#include "store/scene_preset.hpp"

namespace compaction::server {

StoreDb::StoreDb(const std::string& path, StoreConfig config_in)
    : lock(path),
      config(std::move(config_in)),
      writer(path),
      readers(path),
      files(path + ".artifacts"),
      wal(path) {
  std::lock_guard lock(write_mutex);
  // The run table's preset column (migration 0012) is the store's rule, called by its triggers.
  writer.define_function("compaction_preset", &scene_preset_name);
  apply_migrations(writer, embedded_migrations());
  wal_synced_with_files = files.same_file_system(path);
  // Folders of results that were never committed (a crash between writing the files and the
  // transaction): nothing names them.
  std::set<std::string> keep;
  auto s = writer.prepare(
      "SELECT DISTINCT substr(path, 1, instr(path, '/') - 1) FROM artifacts WHERE path IS NOT NULL");
  while (s.step()) keep.insert(s.text(0));
  if (const int n = files.remove_all_but(keep); n > 0) {
    spdlog::warn("removed {} artifact folder(s) of uploads that were never committed", n);
  }
}

void StoreDb::wait_durable(std::unique_lock<std::mutex>& lock) {
  lock.unlock();
  wait_durable();
}

void StoreDb::wait_durable() {
  if (wal_synced_with_files) {
    files.wait_synced();
  } else {
    wal.wait_durable();
  }
}

void log_event(sqlite::Database& writer, std::int64_t job_id, Millis at, const char* kind,
               int attempt, const std::optional<std::string>& worker, const std::string& message) {
  writer.prepare(
        "INSERT INTO job_events (job_id, at, kind, attempt, worker, message)"
        " VALUES (?, ?, ?, ?, ?, ?)")
      .bind(1, job_id)
      .bind(2, at)
      .bind(3, kind)
      .bind(4, attempt)
      .bind(5, worker)
      .bind(6, message)
      .run();
  writer.prepare(
        "INSERT INTO event_totals (kind, total) VALUES (?, 1)"
        " ON CONFLICT (kind) DO UPDATE SET total = total + 1")
      .bind(1, kind)
      .run();
  // Only the newest events of a job stay; the older ones are counted in jobs.events_dropped.
  auto trim = writer.prepare(
      "DELETE FROM job_events WHERE job_id = ?1 AND id <= (SELECT id FROM job_events"
      " WHERE job_id = ?1 ORDER BY id DESC LIMIT 1 OFFSET ?2)");
  trim.bind(1, job_id).bind(2, static_cast<std::int64_t>(max_events_per_job)).run();
  if (const std::int64_t dropped = writer.changes(); dropped > 0) {
    writer.prepare("UPDATE jobs SET events_dropped = events_dropped + ?2 WHERE id = ?1")
        .bind(1, job_id)
        .bind(2, dropped)
        .run();
  }
}

}  // namespace compaction::server
