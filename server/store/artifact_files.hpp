// The artifacts of results as files: one folder per stored result below a root folder beside
// the database (<db>.artifacts/). A result's files are written and flushed to disk before the
// transaction that records them, with no lock held, so a large upload never blocks the store;
// the flush (one syncfs of the file system) is shared by the uploads written at the same time
// (GroupSync); a folder that no committed row names (a crash before the commit, a lost lease)
// is removed.
#pragma once

#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "store/group_sync.hpp"

namespace compaction::server {

struct Artifact;

class ArtifactFiles {
 public:
  explicit ArtifactFiles(std::filesystem::path root);
  ~ArtifactFiles();
  ArtifactFiles(const ArtifactFiles&) = delete;
  ArtifactFiles& operator=(const ArtifactFiles&) = delete;

  const std::filesystem::path& root() const { return root_; }

  // Writes the artifacts into root/folder/ (created) and returns once the files, the folder
  // and its entry in the root are on disk (synced = false: without waiting; wait_synced() before
  // the commit that names them); returns the path of each file relative to the root, in order.
  // Throws std::runtime_error on I/O errors (and leaves nothing behind).
  std::vector<std::string> write(const std::string& folder, const std::vector<Artifact>& artifacts,
                                 bool synced = true);

  // Returns once everything written on the root's file system before the call (any file of
  // it, not only artifacts) is on disk: a round of the same shared syncfs as write's.
  void wait_synced() { group_.wait(); }

  // Whether path is on the root's file system (its writes are in wait_synced's flush).
  bool same_file_system(const std::filesystem::path& path) const;

  // The bytes of a file by its relative path; throws std::runtime_error when it is missing.
  std::string read(const std::string& relative_path) const;

  // Removes root/folder/ and everything in it (no error if it is absent).
  void remove(const std::string& folder) noexcept;

  // Removes every folder below the root whose name is not in `keep`; returns how many.
  int remove_all_but(const std::set<std::string>& keep) noexcept;

 private:
  // Flushes everything written below the root so far (one round of group_).
  void sync();

  std::filesystem::path root_;
  int root_fd_ = -1;  // names the file system to sync
  GroupSync group_;
};

}  // namespace compaction::server
