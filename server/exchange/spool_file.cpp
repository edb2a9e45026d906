#include "exchange/spool_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>

namespace compaction::server {

namespace {

[[noreturn]] void io_error(const std::string& what, const std::filesystem::path& p) {
  throw std::runtime_error(what + " " + p.string() + ": " + std::strerror(errno));
}

}  // namespace

SpoolFile::SpoolFile(const std::filesystem::path& folder) {
  fd_ = ::open(folder.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
  if (fd_ < 0 && (errno == EOPNOTSUPP || errno == EISDIR || errno == EINVAL)) {
    std::string name = (folder / "spool-XXXXXX").string();
    fd_ = ::mkostemp(name.data(), O_CLOEXEC);
    if (fd_ >= 0) ::unlink(name.c_str());
  }
  if (fd_ < 0) io_error("cannot make a spool file in", folder);
}

SpoolFile::~SpoolFile() {
  if (file_) {
    std::fclose(file_);  // closes fd_ too
  } else if (fd_ >= 0) {
    ::close(fd_);
  }
}

void SpoolFile::append(const char* data, std::size_t size) {
  std::size_t done = 0;
  while (done < size) {
    const ssize_t n = ::write(fd_, data + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) io_error("cannot write the spool file of", "a request body");
    done += static_cast<std::size_t>(n);
  }
  size_ += size;
}

std::FILE* SpoolFile::read() {
  if (!file_) {
    file_ = ::fdopen(fd_, "rb");
    if (!file_) io_error("cannot read the spool file of", "a request body");
    // Big reads: the parser takes the file a byte at a time from this buffer.
    std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
  }
  std::rewind(file_);
  return file_;
}

}  // namespace compaction::server
