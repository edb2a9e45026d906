#include "store/artifact_files.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "store/artifact.hpp"

namespace compaction::server {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void io_error(const std::string& what, const fs::path& p) {
  throw std::runtime_error(what + " " + p.string() + ": " + std::strerror(errno));
}

void write_file(const fs::path& p, const std::string& data) {
  const int fd = ::open(p.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) io_error("cannot create", p);
  std::size_t done = 0;
  while (done < data.size()) {
    const ssize_t n = ::write(fd, data.data() + done, data.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      ::close(fd);
      io_error("cannot write", p);
    }
    done += static_cast<std::size_t>(n);
  }
  if (::close(fd) != 0) io_error("cannot write", p);
}

}  // namespace

ArtifactFiles::ArtifactFiles(fs::path root) : root_(std::move(root)), group_([this] { sync(); }) {
  fs::create_directories(root_);
  root_fd_ = ::open(root_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (root_fd_ < 0) io_error("cannot open", root_);
}

ArtifactFiles::~ArtifactFiles() { ::close(root_fd_); }

std::vector<std::string> ArtifactFiles::write(const std::string& folder,
                                              const std::vector<Artifact>& artifacts, bool synced) {
  const fs::path dir = root_ / folder;
  std::vector<std::string> paths;
  try {
    // The root exists (the constructor made it) and the folder is new (named after the lease):
    // one mkdir, without create_directories' stat of every level first.
    if (::mkdir(dir.c_str(), 0755) != 0 && errno != EEXIST) io_error("cannot create", dir);
    for (const Artifact& a : artifacts) {
      write_file(dir / a.name, a.data);
      paths.push_back(folder + "/" + a.name);
    }
    if (synced) group_.wait();
  } catch (...) {
    remove(folder);
    throw;
  }
  return paths;
}

void ArtifactFiles::sync() {
  // One syncfs writes every dirty file and folder of the file system and flushes the disk's
  // cache once: the files, folders and root entries of all the uploads written before it. A
  // sync of each file, its folder and the root costs a cache flush each on ext4 without a
  // journal (this machine's disk), and their serial form in one thread was slower than the
  // uploads' own; the price of syncfs is the other programs' writes on the same file system,
  // which it flushes too (bench/results/queue_bench.md measures both).
  if (::syncfs(root_fd_) != 0) io_error("cannot flush the file system of", root_);
}

bool ArtifactFiles::same_file_system(const fs::path& path) const {
  struct stat a {}, b {};
  return ::fstat(root_fd_, &a) == 0 && ::stat(path.c_str(), &b) == 0 && a.st_dev == b.st_dev;
}

std::string ArtifactFiles::read(const std::string& relative_path) const {
  const fs::path p = root_ / relative_path;
  std::ifstream f(p, std::ios::binary);
  if (!f) throw std::runtime_error("artifact file missing: " + p.string());
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

void ArtifactFiles::remove(const std::string& folder) noexcept {
  std::error_code ec;
  fs::remove_all(root_ / folder, ec);
}

int ArtifactFiles::remove_all_but(const std::set<std::string>& keep) noexcept {
  int removed = 0;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(root_, ec)) {
    const std::string name = entry.path().filename().string();
    if (keep.count(name)) continue;
    remove(name);
    ++removed;
  }
  return removed;
}

}  // namespace compaction::server
