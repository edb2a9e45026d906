#include "scratch.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace compaction::worker {

namespace fs = std::filesystem;

namespace {

// Opens the folder's lock file and takes the lock without waiting: -1 when another process
// holds it (or it cannot be opened).
int try_lock(const fs::path& dir) {
  const int fd = ::open((dir / ".lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) return -1;
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

bool starts_with(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

}  // namespace

ScratchFolder::ScratchFolder(fs::path dir) : dir_(std::move(dir)) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec) throw std::runtime_error("cannot create the work folder " + dir_.string() + ": " + ec.message());
  lock_fd_ = try_lock(dir_);
  if (lock_fd_ < 0) {
    throw std::runtime_error("the work folder " + dir_.string() +
                             " is in use by another worker (give each worker its own --work-dir)");
  }
}

ScratchFolder::~ScratchFolder() {
  if (lock_fd_ >= 0) ::close(lock_fd_);
}

int ScratchFolder::remove_leftovers() {
  int n = 0;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir_, ec)) {
    if (e.is_directory() && starts_with(e.path().filename().string(), "job-")) {
      fs::remove_all(e.path(), ec);
      ++n;
    }
  }
  return n;
}

int ScratchFolder::remove_dead_siblings() {
  int n = 0;
  std::error_code ec;
  const fs::path parent = dir_.parent_path();
  for (const auto& e : fs::directory_iterator(parent, ec)) {
    const std::string name = e.path().filename().string();
    if (!e.is_directory() || e.path() == dir_ || !starts_with(name, default_scratch_prefix)) continue;
    if (name.find_first_not_of("0123456789", std::strlen(default_scratch_prefix)) != std::string::npos) {
      continue;  // not a default name: someone's own folder
    }
    const int fd = try_lock(e.path());
    if (fd < 0) continue;  // a live worker holds it
    fs::remove_all(e.path(), ec);
    ::close(fd);
    ++n;
  }
  return n;
}

void ScratchFolder::remove_if_empty() {
  std::error_code ec;
  fs::remove(dir_ / ".lock", ec);
  fs::remove(dir_, ec);  // only if empty
}

}  // namespace compaction::worker
