// The service's store in SQLite: the queue (queue_store.hpp), the sweeps (sweep_store.hpp), the
// reads (store_reads.hpp) and the run table (run_table.hpp) over one database (store_db.hpp).
// Only these files hold SQL, with sqlite.cpp (the connection) and migrations.cpp (the schema
// files); the REST documents are built from the records in views.hpp.
#pragma once

#include <string>

#include "store/checkpoint_store.hpp"
#include "store/import_store.hpp"
#include "store/label_store.hpp"
#include "store/queue_store.hpp"
#include "store/run_table.hpp"
#include "store/store_db.hpp"
#include "store/store_reads.hpp"
#include "store/sweep_store.hpp"

namespace compaction::server {

struct Store {
  // Opens the database and applies the pending migrations.
  Store(const std::string& path, StoreConfig config)
      : db(path, std::move(config)), queue(db), sweeps(db), reads(db), runs(db), labels(db),
        imports(db), checkpoints(db, path + ".checkpoints") {}
  Store(const Store&) = delete;
  Store& operator=(const Store&) = delete;

  const StoreConfig& config() const { return db.config; }

  StoreDb db;
  QueueStore queue;
  SweepStore sweeps;
  StoreReads reads;
  RunTable runs;        // the run table of GET /jobs (migration 0012)
  LabelStore labels;    // human labels and their audit
  ImportStore imports;  // merges another server's export
  CheckpointStore checkpoints;  // checkpoints of runs and their resumes
};

}  // namespace compaction::server
