// The artifacts of results as files: one folder per stored result below a root folder beside
// the database (<db>.artifacts/). A result's files are written and flushed to disk before the
// transaction that records them, with no lock held, so a large upload never blocks the store;
// a folder that no committed row names (a crash before the commit, a lost lease) is removed.
#pragma once

#include <filesystem>
#include <set>
#include <string>
#include <vector>

namespace compaction::server {

struct Artifact;

class ArtifactFiles {
 public:
  explicit ArtifactFiles(std::filesystem::path root);

  const std::filesystem::path& root() const { return root_; }

  // Writes the artifacts into root/folder/ (created; fsync'd with the folder); returns the
  // path of each file relative to the root, in order. Throws std::runtime_error on I/O errors
  // (and leaves nothing behind).
  std::vector<std::string> write(const std::string& folder, const std::vector<Artifact>& artifacts);

  // The bytes of a file by its relative path; throws std::runtime_error when it is missing.
  std::string read(const std::string& relative_path) const;

  // Removes root/folder/ and everything in it (no error if it is absent).
  void remove(const std::string& folder) noexcept;

  // Removes every folder below the root whose name is not in `keep`; returns how many.
  int remove_all_but(const std::set<std::string>& keep) noexcept;

 private:
  std::filesystem::path root_;
};

}  // namespace compaction::server
