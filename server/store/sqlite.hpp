// A thin RAII layer over the SQLite C API: a connection, prepared statements with bound
// parameters, and an IMMEDIATE transaction. No queries live here (they live in job_store.cpp);
// errors become SqliteError carrying SQLite's message.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "store/group_sync.hpp"

struct sqlite3;
struct sqlite3_stmt;

namespace compaction::server::sqlite {

struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Statement;

enum class Access { read_write, read_only };

class Database {
 public:
  // Opens (creating) the file, sets WAL, synchronous NORMAL, foreign keys and the busy timeout.
  // In WAL mode NORMAL keeps every commit atomic and the file consistent through any crash,
  // but a commit reaches the disk only with the next sync of the WAL (WalSync) or checkpoint:
  // a power loss may undo the last commits. A crash of the process alone loses nothing.
  // A read-only connection needs the file to exist in WAL mode already, and serves one thread
  // at a time (it is opened without SQLite's per-call mutex; ReaderPool lends it so).
  explicit Database(const std::string& path, int busy_timeout_ms = 5000,
                    Access access = Access::read_write);
  ~Database();
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;

  // A statement compiled once per connection and kept: a Statement hands its compiled form
  // back when it ends (reset, bindings cleared), and the next prepare of the same text takes it
  // instead of parsing the SQL again.
  Statement prepare(std::string_view sql);
  // Runs a script of several statements without parameters (migration files only).
  void exec_script(const std::string& sql);
  std::int64_t changes() const;
  // Whether the query (with one id parameter) returns a row: "SELECT 1 FROM jobs WHERE id = ?".
  bool has_row(std::string_view sql, std::int64_t id);
  std::int64_t last_insert_rowid() const;
  sqlite3* handle() { return db_; }
  // Write transactions that changed a row, committed on this connection so far
  // (Transaction::commit counts them after the commit is visible to readers).
  std::uint64_t commits() const { return commits_.load(); }
  // Rows changed by every statement on this connection so far.
  std::int64_t total_changes() const;
  // Defines a deterministic SQL function of one text argument on this connection, which the
  // schema's triggers may call: NULL in, NULL out; fn's nullopt is NULL.
  using TextFunction = std::optional<std::string> (*)(std::string_view);
  void define_function(const char* name, TextFunction fn);

 private:
  friend class Transaction;
  friend class Statement;
  // At most this many compiled statements wait for reuse on a connection (the queries built
  // from filters have many texts; the queue's statements a few dozen).
  static constexpr std::size_t max_idle_statements = 256;
  void give_back(std::string sql, sqlite3_stmt* stmt);

  sqlite3* db_ = nullptr;
  std::atomic<std::uint64_t> commits_{0};
  std::mutex statements_mutex_;
  std::unordered_multimap<std::string, sqlite3_stmt*> idle_statements_;
};

class Statement {
 public:
  // Compiles sql on the connection (Database::prepare takes a kept one when it can).
  Statement(Database& owner, std::string_view sql);
  ~Statement();
  Statement(Statement&& o) noexcept;
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  // Binders by 1-based index; chainable.
  Statement& bind(int i, std::int64_t v);
  Statement& bind(int i, int v) { return bind(i, static_cast<std::int64_t>(v)); }
  Statement& bind(int i, double v);
  Statement& bind(int i, std::string_view v);
  Statement& bind(int i, const char* v) { return bind(i, std::string_view(v)); }
  Statement& bind(int i, const std::string& v) { return bind(i, std::string_view(v)); }
  Statement& bind_blob(int i, const void* data, std::size_t size);
  Statement& bind_null(int i);
  template <typename T>
  Statement& bind(int i, const std::optional<T>& v) {
    return v ? bind(i, *v) : bind_null(i);
  }

  // Steps once: true when a row is available.
  bool step();
  // Steps to the end (statements without rows); returns sqlite3_changes().
  void run();
  void reset();

  bool is_null(int col) const;
  std::int64_t int64(int col) const;
  double real(int col) const;
  std::string text(int col) const;
  std::optional<std::int64_t> opt_int64(int col) const;
  std::optional<double> opt_real(int col) const;
  std::optional<std::string> opt_text(int col) const;
  std::string blob(int col) const;

 private:
  friend class Database;
  Statement(Database& owner, std::string sql, sqlite3_stmt* stmt);

  Database* owner_ = nullptr;
  sqlite3* db_ = nullptr;
  std::string sql_;  // the text it was prepared from: its key among the kept statements
  sqlite3_stmt* stmt_ = nullptr;
};

// BEGIN IMMEDIATE on construction (takes the write lock at once, so two writers never deadlock
// on a lock upgrade); ROLLBACK on destruction unless commit() was called.
class Transaction {
 public:
  explicit Transaction(Database& db);
  ~Transaction();
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;
  void commit();

 private:
  Database& db_;
  std::int64_t changes_at_begin_ = 0;
  bool done_ = false;
};

// Makes commits durable: an fdatasync of the database's WAL file, shared by every commit made
// before it starts (group commit, GroupSync), so that concurrent writers that need durability
// wait for one sync between them instead of one each. (StoreDb uses it only when the artifacts
// are on another file system; otherwise their syncfs covers the WAL.)
class WalSync {
 public:
  // path: the database file, already in WAL mode.
  explicit WalSync(std::string path);
  ~WalSync();
  WalSync(const WalSync&) = delete;
  WalSync& operator=(const WalSync&) = delete;

  // Returns once every commit made before the call (on any connection of the file) is on disk.
  void wait_durable() { group_.wait(); }

 private:
  void sync();

  const std::string wal_path_;
  int fd_ = -1;  // opened by the first sync (only the syncing thread touches it)
  GroupSync group_;
};

// A read transaction (BEGIN DEFERRED ... COMMIT): the statements inside it see one snapshot
// of the database (WAL), while a writer on another connection goes on.
class ReadTransaction {
 public:
  explicit ReadTransaction(Database& db);
  ~ReadTransaction();
  ReadTransaction(const ReadTransaction&) = delete;
  ReadTransaction& operator=(const ReadTransaction&) = delete;

 private:
  Database& db_;
};

// Read-only connections to one database file, opened on demand and reused: each reader
// thread takes its own, so reads never wait for each other or for the writer.
class ReaderPool {
 public:
  explicit ReaderPool(std::string path) : path_(std::move(path)) {}

  class Handle {
   public:
    Handle(ReaderPool& pool, std::unique_ptr<Database> db) : pool_(pool), db_(std::move(db)) {}
    ~Handle() { pool_.give_back(std::move(db_)); }
    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;
    Database& operator*() { return *db_; }
    Database* operator->() { return db_.get(); }

   private:
    ReaderPool& pool_;
    std::unique_ptr<Database> db_;
  };

  Handle take();

 private:
  void give_back(std::unique_ptr<Database> db);

  std::string path_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<Database>> idle_;
};

}  // namespace compaction::server::sqlite
