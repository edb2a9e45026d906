#include "store/sqlite.hpp"

#include <fcntl.h>
#include <sqlite3.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace compaction::server::sqlite {

namespace {
[[noreturn]] void fail(sqlite3* db, const std::string& what) {
  throw Error(what + ": " + (db ? sqlite3_errmsg(db) : "out of memory"));
}
}  // namespace

Database::Database(const std::string& path, int busy_timeout_ms, Access access) {
  // A read-only connection lives in a ReaderPool, which lends it to one thread at a time, so
  // SQLite's own per-call mutex is left out (NOMUTEX); the writer keeps it (FULLMUTEX).
  const int flags = access == Access::read_only
                        ? SQLITE_OPEN_READONLY | SQLITE_OPEN_NOMUTEX
                        : SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX;
  if (sqlite3_open_v2(path.c_str(), &db_, flags, nullptr) != SQLITE_OK) {
    std::string msg = "cannot open database " + path + ": " +
                      (db_ ? sqlite3_errmsg(db_) : "out of memory");
    sqlite3_close(db_);
    db_ = nullptr;
    throw Error(msg);
  }
  sqlite3_busy_timeout(db_, busy_timeout_ms);
  sqlite3_extended_result_codes(db_, 1);
  // WAL: readers never block the writer. NORMAL: a commit does not wait for the disk; the
  // writes that must survive a power loss wait for WalSync after their commit.
  {
    Statement s = prepare("PRAGMA journal_mode = WAL");
    if (!s.step() || s.text(0) != "wal") throw Error("cannot switch " + path + " to WAL mode");
  }
  prepare("PRAGMA synchronous = NORMAL").run();
  prepare("PRAGMA foreign_keys = ON").run();
}

namespace {
void call_text_function(sqlite3_context* ctx, int, sqlite3_value** args) {
  const auto fn = reinterpret_cast<Database::TextFunction>(sqlite3_user_data(ctx));
  if (sqlite3_value_type(args[0]) == SQLITE_NULL) {
    sqlite3_result_null(ctx);
    return;
  }
  try {
    const auto* text = reinterpret_cast<const char*>(sqlite3_value_text(args[0]));
    const auto out = fn(std::string_view(text, static_cast<std::size_t>(sqlite3_value_bytes(args[0]))));
    if (out) {
      sqlite3_result_text(ctx, out->data(), static_cast<int>(out->size()), SQLITE_TRANSIENT);
    } else {
      sqlite3_result_null(ctx);
    }
  } catch (const std::exception& e) {
    sqlite3_result_error(ctx, e.what(), -1);
  }
}
}  // namespace

void Database::define_function(const char* name, TextFunction fn) {
  const int flags = SQLITE_UTF8 | SQLITE_DETERMINISTIC | SQLITE_INNOCUOUS;
  if (sqlite3_create_function_v2(db_, name, 1, flags, reinterpret_cast<void*>(fn), call_text_function,
                                 nullptr, nullptr, nullptr) != SQLITE_OK) {
    throw Error(std::string("cannot define the SQL function ") + name + ": " + sqlite3_errmsg(db_));
  }
}

Database::~Database() {
  for (auto& [sql, stmt] : idle_statements_) sqlite3_finalize(stmt);
  sqlite3_close_v2(db_);
}

Statement Database::prepare(std::string_view sql) {
  {
    std::lock_guard lock(statements_mutex_);
    if (auto it = idle_statements_.find(std::string(sql)); it != idle_statements_.end()) {
      Statement s(*this, std::move(it->first), it->second);
      idle_statements_.erase(it);
      return s;
    }
  }
  return Statement(*this, sql);
}

void Database::give_back(std::string sql, sqlite3_stmt* stmt) {
  sqlite3_reset(stmt);
  sqlite3_clear_bindings(stmt);
  {
    std::lock_guard lock(statements_mutex_);
    if (idle_statements_.size() < max_idle_statements) {
      idle_statements_.emplace(std::move(sql), stmt);
      return;
    }
  }
  sqlite3_finalize(stmt);
}

void Database::exec_script(const std::string& sql) {
  char* err = nullptr;
  if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
    std::string msg = err ? err : "unknown error";
    sqlite3_free(err);
    throw Error("script failed: " + msg);
  }
}

std::int64_t Database::changes() const { return sqlite3_changes64(db_); }
std::int64_t Database::total_changes() const { return sqlite3_total_changes64(db_); }

bool Database::has_row(std::string_view sql, std::int64_t id) {
  Statement s = prepare(sql);
  s.bind(1, id);
  return s.step();
}
std::int64_t Database::last_insert_rowid() const { return sqlite3_last_insert_rowid(db_); }

Statement::Statement(Database& owner, std::string_view sql)
    : owner_(&owner), db_(owner.handle()), sql_(sql) {
  if (sqlite3_prepare_v2(db_, sql.data(), static_cast<int>(sql.size()), &stmt_, nullptr) !=
      SQLITE_OK) {
    sqlite3_finalize(stmt_);  // NULL after a failed prepare; finalize(NULL) is a no-op
    stmt_ = nullptr;
    fail(db_, "prepare failed for \"" + sql_ + "\"");
  }
}

Statement::Statement(Database& owner, std::string sql, sqlite3_stmt* stmt)
    : owner_(&owner), db_(owner.handle()), sql_(std::move(sql)), stmt_(stmt) {}

Statement::~Statement() {
  if (stmt_) owner_->give_back(std::move(sql_), stmt_);
}

Statement::Statement(Statement&& o) noexcept
    : owner_(o.owner_), db_(o.db_), sql_(std::move(o.sql_)), stmt_(o.stmt_) {
  o.stmt_ = nullptr;
}

Statement& Statement::bind(int i, std::int64_t v) {
  if (sqlite3_bind_int64(stmt_, i, v) != SQLITE_OK) fail(db_, "bind");
  return *this;
}
Statement& Statement::bind(int i, double v) {
  if (sqlite3_bind_double(stmt_, i, v) != SQLITE_OK) fail(db_, "bind");
  return *this;
}
Statement& Statement::bind(int i, std::string_view v) {
  if (sqlite3_bind_text64(stmt_, i, v.data(), v.size(), SQLITE_TRANSIENT, SQLITE_UTF8) !=
      SQLITE_OK) {
    fail(db_, "bind");
  }
  return *this;
}
Statement& Statement::bind_blob(int i, const void* data, std::size_t size) {
  if (sqlite3_bind_blob64(stmt_, i, data, size, SQLITE_TRANSIENT) != SQLITE_OK) fail(db_, "bind");
  return *this;
}
Statement& Statement::bind_null(int i) {
  if (sqlite3_bind_null(stmt_, i) != SQLITE_OK) fail(db_, "bind");
  return *this;
}

bool Statement::step() {
  const int rc = sqlite3_step(stmt_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  fail(db_, std::string("step failed for \"") + sqlite3_sql(stmt_) + "\"");
}

void Statement::run() {
  while (step()) {
  }
}

void Statement::reset() {
  sqlite3_reset(stmt_);
  sqlite3_clear_bindings(stmt_);
}

bool Statement::is_null(int col) const { return sqlite3_column_type(stmt_, col) == SQLITE_NULL; }
std::int64_t Statement::int64(int col) const { return sqlite3_column_int64(stmt_, col); }
double Statement::real(int col) const { return sqlite3_column_double(stmt_, col); }
std::string Statement::text(int col) const {
  const auto* p = sqlite3_column_text(stmt_, col);
  return p ? std::string(reinterpret_cast<const char*>(p),
                         static_cast<std::size_t>(sqlite3_column_bytes(stmt_, col)))
           : std::string();
}
std::optional<std::int64_t> Statement::opt_int64(int col) const {
  if (is_null(col)) return std::nullopt;
  return int64(col);
}
std::optional<double> Statement::opt_real(int col) const {
  if (is_null(col)) return std::nullopt;
  return real(col);
}
std::optional<std::string> Statement::opt_text(int col) const {
  if (is_null(col)) return std::nullopt;
  return text(col);
}
std::string Statement::blob(int col) const {
  const void* p = sqlite3_column_blob(stmt_, col);
  const int n = sqlite3_column_bytes(stmt_, col);
  return p ? std::string(static_cast<const char*>(p), static_cast<std::size_t>(n)) : std::string();
}

Transaction::Transaction(Database& db) : db_(db), changes_at_begin_(db.total_changes()) {
  db_.prepare("BEGIN IMMEDIATE").run();
}

Transaction::~Transaction() {
  if (!done_) {
    try {
      db_.prepare("ROLLBACK").run();
    } catch (...) {
      // Nothing sensible to do: the connection rolls back on close anyway.
    }
  }
}

void Transaction::commit() {
  db_.prepare("COMMIT").run();
  done_ = true;
  // A transaction that changed nothing (a rescue that found no expired lease) leaves the
  // version the readers' tags name as it was.
  if (db_.total_changes() != changes_at_begin_) ++db_.commits_;
}

WalSync::WalSync(std::string path)
    : wal_path_(std::move(path) + "-wal"), group_([this] { sync(); }) {}

WalSync::~WalSync() {
  if (fd_ >= 0) ::close(fd_);
}

void WalSync::sync() {
  if (fd_ < 0) {  // SQLite makes the WAL file with the first commit; it stays while db is open
    fd_ = ::open(wal_path_.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0) throw Error("cannot open " + wal_path_ + ": " + std::strerror(errno));
  }
  // Every commit made so far is in the WAL file's pages: one fdatasync covers them all. (A
  // checkpoint that moved them into the database file synced both files already.)
  if (::fdatasync(fd_) != 0) throw Error(std::string("cannot sync the WAL: ") + std::strerror(errno));
}

ReadTransaction::ReadTransaction(Database& db) : db_(db) { db_.prepare("BEGIN").run(); }

ReadTransaction::~ReadTransaction() {
  try {
    db_.prepare("COMMIT").run();
  } catch (...) {
    // A read transaction has nothing to lose; the next BEGIN fails loudly if the connection
    // is unusable.
  }
}

ReaderPool::Handle ReaderPool::take() {
  {
    std::lock_guard lock(mutex_);
    if (!idle_.empty()) {
      auto db = std::move(idle_.back());
      idle_.pop_back();
      return Handle(*this, std::move(db));
    }
  }
  return Handle(*this, std::make_unique<Database>(path_, 5000, Access::read_only));
}

void ReaderPool::give_back(std::unique_ptr<Database> db) {
  if (!db) return;
  std::lock_guard lock(mutex_);
  idle_.push_back(std::move(db));
}

}  // namespace compaction::server::sqlite
