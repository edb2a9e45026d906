// Numbered schema migrations (schema/migrations/NNNN_name.sql, embedded in the binary at build
// time). Each is applied once, in order, inside a transaction, and recorded in the
// schema_migrations table; an applied migration is never edited (its checksum is kept and a
// change is refused at start).
#pragma once

#include <string>
#include <vector>

#include "store/sqlite.hpp"

namespace compaction::server {

struct Migration {
  int version;        // NNNN of the file name
  std::string name;   // the file name
  std::string sql;
};

// The migrations compiled into this binary, sorted by version.
const std::vector<Migration>& embedded_migrations();

// Applies the pending ones; returns how many were applied. Throws on a gap, on an applied
// migration whose text changed, or on a database newer than this binary.
int apply_migrations(sqlite::Database& db, const std::vector<Migration>& migrations);

}  // namespace compaction::server
