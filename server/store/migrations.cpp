#include "store/migrations.hpp"

#include <cstdio>
#include <stdexcept>

#include <spdlog/spdlog.h>

namespace compaction::server {

namespace {
// FNV-1a: a stable checksum of a migration's text (std::hash is not stable across builds).
std::string checksum(const std::string& s) {
  std::uint64_t h = 1469598103934665603ULL;
  for (unsigned char c : s) {
    h ^= c;
    h *= 1099511628211ULL;
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}
}  // namespace

int apply_migrations(sqlite::Database& db, const std::vector<Migration>& migrations) {
  db.prepare(
        "CREATE TABLE IF NOT EXISTS schema_migrations ("
        " version INTEGER PRIMARY KEY, name TEXT NOT NULL, checksum TEXT NOT NULL,"
        " applied_at TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ', 'now')))")
      .run();
  int applied = 0;
  int expected = 1;
  for (const Migration& m : migrations) {
    if (m.version != expected) {
      throw std::runtime_error("migration " + m.name + " breaks the numbering (expected " +
                               std::to_string(expected) + ")");
    }
    ++expected;
    sqlite::Transaction tx(db);
    auto q = db.prepare("SELECT checksum FROM schema_migrations WHERE version = ?");
    q.bind(1, m.version);
    if (q.step()) {
      if (q.text(0) != checksum(m.sql)) {
        throw std::runtime_error("applied migration " + m.name +
                                 " was edited; add a new migration instead");
      }
      continue;
    }
    db.exec_script(m.sql);
    db.prepare("INSERT INTO schema_migrations (version, name, checksum) VALUES (?, ?, ?)")
        .bind(1, m.version)
        .bind(2, m.name)
        .bind(3, checksum(m.sql))
        .run();
    tx.commit();
    spdlog::info("applied migration {}", m.name);
    ++applied;
  }
  auto newest = db.prepare("SELECT max(version) FROM schema_migrations");
  if (newest.step() && !newest.is_null(0) && newest.int64(0) >= expected) {
    throw std::runtime_error("the database has migration " + std::to_string(newest.int64(0)) +
                             ", newer than this server knows; upgrade the server");
  }
  return applied;
}

}  // namespace compaction::server
