// The SQLite layer's kept statements: a statement prepared again is the kept one, with its
// bindings cleared and its cursor reset; nested uses of one text get a statement each.
#include "store/sqlite.hpp"

#include <gtest/gtest.h>

#include "temp_dir.hpp"

using namespace compaction::server;

TEST(SqliteStatements, AKeptStatementComesBackResetAndUnbound) {
  TempDir dir;
  sqlite::Database db(dir.file("t.db"));
  db.exec_script("CREATE TABLE t (x INTEGER); INSERT INTO t VALUES (1), (2), (3);");
  {
    auto s = db.prepare("SELECT ?1, x FROM t ORDER BY x");
    s.bind(1, std::int64_t{5});
    ASSERT_TRUE(s.step());  // left in the middle of its rows
    EXPECT_EQ(s.int64(0), 5);
    EXPECT_EQ(s.int64(1), 1);
  }
  auto again = db.prepare("SELECT ?1, x FROM t ORDER BY x");
  ASSERT_TRUE(again.step());
  EXPECT_TRUE(again.is_null(0));  // the binding of the first use is gone
  EXPECT_EQ(again.int64(1), 1);   // from the first row again
  {
    // The same text while the first is in use: a second statement, both usable.
    auto nested = db.prepare("SELECT ?1, x FROM t ORDER BY x");
    nested.bind(1, std::int64_t{7});
    ASSERT_TRUE(nested.step());
    EXPECT_EQ(nested.int64(0), 7);
  }
  ASSERT_TRUE(again.step());
  EXPECT_EQ(again.int64(1), 2);
}

TEST(SqliteStatements, AKeptStatementHoldsNoReadLock) {
  TempDir dir;
  sqlite::Database db(dir.file("t.db"));
  db.exec_script("CREATE TABLE t (x INTEGER); INSERT INTO t VALUES (1), (2);");
  {
    auto s = db.prepare("SELECT x FROM t");
    ASSERT_TRUE(s.step());  // an open read, ended by giving the statement back
  }
  // A checkpoint that must see no reader: a read left open would make it return busy.
  auto c = db.prepare("PRAGMA wal_checkpoint(TRUNCATE)");
  ASSERT_TRUE(c.step());
  EXPECT_EQ(c.int64(0), 0);
}

TEST(SqliteStatements, AFailedPrepareThrowsAndLeavesTheConnectionUsable) {
  TempDir dir;
  sqlite::Database db(dir.file("t.db"));
  EXPECT_THROW(db.prepare("SELEC 1"), sqlite::Error);
  auto s = db.prepare("SELECT 1");
  ASSERT_TRUE(s.step());
  EXPECT_EQ(s.int64(0), 1);
}
