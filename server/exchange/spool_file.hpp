// A file without a name, for a request body too large to hold in memory (an import): written
// once as the body arrives, read back from its start, and gone when closed, whatever ends the
// process (O_TMPFILE; on a file system without it, a named file unlinked at once).
#pragma once

#include <cstddef>
#include <cstdio>
#include <filesystem>

namespace compaction::server {

class SpoolFile {
 public:
  // Makes the file in `folder` (on the disk, not in /tmp, which may be memory). Throws
  // std::runtime_error.
  explicit SpoolFile(const std::filesystem::path& folder);
  ~SpoolFile();
  SpoolFile(const SpoolFile&) = delete;
  SpoolFile& operator=(const SpoolFile&) = delete;

  // Throws std::runtime_error on a write error (a full disk).
  void append(const char* data, std::size_t size);
  std::size_t size() const { return size_; }

  // The file for reading, at its start; owned by the SpoolFile.
  std::FILE* read();

 private:
  int fd_ = -1;
  std::FILE* file_ = nullptr;
  std::size_t size_ = 0;
};

}  // namespace compaction::server
