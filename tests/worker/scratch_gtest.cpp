// The worker's scratch folder: locked while a worker holds it, its job leftovers cleared, and
// the default-named folders of workers that are gone removed (but not live or foreign ones).
#include "scratch.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "temp_dir.hpp"

namespace fs = std::filesystem;
using compaction::worker::ScratchFolder;

TEST(ScratchFolderGtest, ASecondWorkerCannotTakeAFolderInUse) {
  TempDir dir;
  const fs::path work = dir.path / "w";
  ScratchFolder first(work);
  EXPECT_TRUE(fs::is_directory(work));
  EXPECT_THROW(ScratchFolder second(work), std::runtime_error);
}

TEST(ScratchFolderGtest, TheFolderIsFreeOnceItsWorkerIsGone) {
  TempDir dir;
  const fs::path work = dir.path / "w";
  { ScratchFolder first(work); }
  EXPECT_NO_THROW(ScratchFolder again(work));
}

TEST(ScratchFolderGtest, LeftoverJobFoldersAreRemovedAndOtherFilesKept) {
  TempDir dir;
  const fs::path work = dir.path / "w";
  fs::create_directories(work / "job-1-a1" / "out");
  fs::create_directories(work / "job-2-a3");
  std::ofstream(work / "notes.txt") << "mine";
  ScratchFolder s(work);
  EXPECT_EQ(s.remove_leftovers(), 2);
  EXPECT_FALSE(fs::exists(work / "job-1-a1"));
  EXPECT_TRUE(fs::exists(work / "notes.txt"));
}

TEST(ScratchFolderGtest, DeadSiblingsWithDefaultNamesAreRemoved) {
  TempDir dir;
  const fs::path dead = dir.path / "compaction-worker-12345";
  const fs::path live = dir.path / "compaction-worker-23456";
  const fs::path foreign = dir.path / "compaction-worker-mine";
  fs::create_directories(dead / "job-1-a1");
  fs::create_directories(foreign);
  ScratchFolder other(live);  // a live worker's folder: locked
  ScratchFolder self(dir.path / "compaction-worker-34567");
  EXPECT_EQ(self.remove_dead_siblings(), 1);
  EXPECT_FALSE(fs::exists(dead));
  EXPECT_TRUE(fs::exists(live));
  EXPECT_TRUE(fs::exists(foreign));
}

TEST(ScratchFolderGtest, AnEmptyFolderIsRemovedAtTheEnd) {
  TempDir dir;
  const fs::path work = dir.path / "w";
  ScratchFolder s(work);
  s.remove_if_empty();
  EXPECT_FALSE(fs::exists(work));
}
