// The database behind the stores: one writer connection (its mutex: one writing thread at a
// time, each write one BEGIN IMMEDIATE transaction; wait_durable after the commits that must
// survive a power loss), a pool of read-only connections (each
// read its own read transaction, so reads never wait for a write or for each other), the
// artifact files, and the job event log every transition writes into.
// Only the stores (queue_store, sweep_store, store_reads) and migrations hold SQL.
#pragma once

#include <cstdint>
#include <mutex>
#include <optional>
#include <string>

#include "store/artifact_files.hpp"
#include "store/database_lock.hpp"
#include "store/group_commit.hpp"
#include "store/sqlite.hpp"

namespace compaction::server {

using Millis = std::int64_t;  // milliseconds since the Unix epoch

struct StoreConfig {
  Millis lease_ms = 60'000;          // a lease lasts this long after a lease or heartbeat
  Millis backoff_base_ms = 5'000;    // retry n waits base * 2^(n-1), capped at backoff_max_ms
  Millis backoff_max_ms = 600'000;
  std::string engine_version;        // the version the identity of new jobs carries
};

// The event log keeps this many of the newest events per job (older ones are counted in the
// job's events_dropped); a job that is leased and given back forever cannot grow it.
constexpr int max_events_per_job = 50;

struct StoreDb {
  // Takes the database's lock (DatabaseInUse when another server holds it), opens the
  // database, applies the pending migrations and removes artifact folders that no committed row
  // names.
  StoreDb(const std::string& path, StoreConfig config);

  DatabaseLock lock;  // first: held before anything below opens, migrates or cleans
  StoreConfig config;
  std::mutex write_mutex;
  sqlite::Database writer;
  // Writes that many workers make at once (completions) share transactions through it.
  GroupCommit group_commit{writer, write_mutex};
  sqlite::ReaderPool readers;
  ArtifactFiles files;
  sqlite::WalSync wal;
  // The WAL is on the artifacts' file system (the usual case: <db>.artifacts/ beside <db>): the
  // artifacts' shared syncfs makes commits durable too, so that a complete's two waits (its
  // files, then its commit) join the same rounds as the other uploads' instead of two kinds.
  bool wal_synced_with_files = false;

  // Called right after a commit on the writer, with its lock: lets go of the lock, then returns
  // once that commit is on disk. For what a client is told is stored and would not make again
  // by itself: a result, a sweep, a cancellation. The queue's other moves (lease, heartbeat, fail, release, rescue) commit
  // without waiting: a power loss that undoes one leaves a job running or queued, which the
  // rescuer and the leases' tokens already handle.
  void wait_durable(std::unique_lock<std::mutex>& lock);
  // The same after a commit made without the caller holding the lock (group_commit).
  void wait_durable();
};

// Appends an event to a job's log inside the caller's write transaction, counts it in the
// totals by kind, and drops the job's events beyond max_events_per_job.
void log_event(sqlite::Database& writer, std::int64_t job_id, Millis at, const char* kind,
               int attempt, const std::optional<std::string>& worker, const std::string& message);

}  // namespace compaction::server
