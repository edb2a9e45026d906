// The worker's scratch folder: held with an exclusive lock (flock on <work_dir>/.lock) while
// the worker lives, so that what a worker killed with -9 left behind can be told from what a
// live one is using. At start the worker clears its own folder's leftovers and removes the
// default-named folders of dead workers beside it.
#pragma once

#include <filesystem>
#include <string>

namespace compaction::worker {

// The default folder name's prefix: $TMPDIR/compaction-worker-<pid>.
inline constexpr const char* default_scratch_prefix = "compaction-worker-";

class ScratchFolder {
 public:
  // Creates the folder and takes its lock; throws std::runtime_error when it cannot be created
  // or another live worker holds it.
  explicit ScratchFolder(std::filesystem::path dir);
  ~ScratchFolder();
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;

  // Removes the job folders in it (left by an earlier worker of the same folder); returns how many.
  int remove_leftovers();

  // Removes the default-named folders beside this one whose worker is gone: no lock is held on
  // them. Returns how many.
  int remove_dead_siblings();

  // Removes the lock and the folder if nothing else is left in it.
  void remove_if_empty();

 private:
  std::filesystem::path dir_;
  int lock_fd_ = -1;
};

}  // namespace compaction::worker
