// One server per database: an exclusive lock on the file <db>.lock beside the database, held
// for as long as the store is open. A second compaction-server (or compaction-server --import)
// on the same database fails at start with the first one's pid, before it migrates, cleans or
// serves anything: two servers would each cache answers the other's writes make stale, and the
// start-up clean-up of one would delete the files the other is writing. The lock is flock(2):
// the kernel drops it when its holder exits, kill -9 included, so a stale lock file never
// blocks a restart. The file stays (removing it would race with the next holder).
#pragma once

#include <stdexcept>
#include <string>

namespace compaction::server {

struct DatabaseInUse : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class DatabaseLock {
 public:
  // Throws DatabaseInUse when another process holds the database, std::runtime_error when the
  // lock file cannot be made.
  explicit DatabaseLock(const std::string& db_path);
  ~DatabaseLock();
  DatabaseLock(const DatabaseLock&) = delete;
  DatabaseLock& operator=(const DatabaseLock&) = delete;

  static std::string lock_path(const std::string& db_path) { return db_path + ".lock"; }

 private:
  int fd_ = -1;
};

}  // namespace compaction::server
