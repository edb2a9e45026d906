#include "child_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <thread>

namespace compaction::worker {

std::string ExitStatus::describe() const {
  if (signaled) {
    const char* name = strsignal(code);
    return "killed by signal " + std::to_string(code) + " (" + (name ? name : "?") + ")";
  }
  return "exit code " + std::to_string(code);
}

namespace {
ExitStatus from_wait_status(int status) {
  if (WIFSIGNALED(status)) return {true, WTERMSIG(status)};
  return {false, WEXITSTATUS(status)};
}
}  // namespace

ChildProcess::ChildProcess(const std::vector<std::string>& argv, const std::string& stderr_file) {
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error(std::string("pipe: ") + strerror(errno));
  const int err_fd = open(stderr_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (err_fd < 0) {
    close(fds[0]);
    close(fds[1]);
    throw std::runtime_error("cannot create " + stderr_file + ": " + strerror(errno));
  }
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const pid_t parent = getpid();

  pid_ = fork();
  if (pid_ < 0) {
    close(fds[0]);
    close(fds[1]);
    close(err_fd);
    throw std::runtime_error(std::string("fork: ") + strerror(errno));
  }
  if (pid_ == 0) {
    // Child: only async-signal-safe calls until exec.
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(127);
    setpgid(0, 0);
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);
    signal(SIGPIPE, SIG_DFL);
    dup2(fds[1], STDOUT_FILENO);
    dup2(err_fd, STDERR_FILENO);
    execv(args[0], args.data());
    const char* msg = "compaction-worker: exec of the runner failed\n";
    (void)!write(STDERR_FILENO, msg, strlen(msg));
    _exit(127);
  }
  close(fds[1]);
  close(err_fd);
  out_fd_ = fds[0];
}

ChildProcess::~ChildProcess() {
  if (!status_ && pid_ > 0) terminate(2000);
  if (out_fd_ >= 0) close(out_fd_);
}

std::vector<std::string> ChildProcess::read_lines(int timeout_ms) {
  std::vector<std::string> lines;
  if (eof_) {
    std::this_thread::sleep_for(std::chrono::milliseconds(std::min(timeout_ms, 50)));
    return lines;
  }
  pollfd p{out_fd_, POLLIN, 0};
  const int n = poll(&p, 1, timeout_ms);
  if (n > 0) {
    char buf[4096];
    const ssize_t got = read(out_fd_, buf, sizeof buf);
    if (got > 0) {
      buffer_.append(buf, static_cast<std::size_t>(got));
    } else if (got == 0 || (errno != EINTR && errno != EAGAIN)) {
      eof_ = true;
    }
  }
  std::size_t start = 0, nl;
  while ((nl = buffer_.find('\n', start)) != std::string::npos) {
    lines.push_back(buffer_.substr(start, nl - start));
    start = nl + 1;
  }
  buffer_.erase(0, start);
  if (eof_ && !buffer_.empty()) {
    lines.push_back(buffer_);
    buffer_.clear();
  }
  return lines;
}

std::optional<ExitStatus> ChildProcess::poll_exit() {
  if (status_) return status_;
  int st = 0;
  const pid_t r = waitpid(pid_, &st, WNOHANG);
  if (r == pid_) status_ = from_wait_status(st);
  return status_;
}

ExitStatus ChildProcess::wait() {
  if (status_) return *status_;
  int st = 0;
  while (waitpid(pid_, &st, 0) < 0 && errno == EINTR) {
  }
  status_ = from_wait_status(st);
  return *status_;
}

ExitStatus ChildProcess::terminate(int grace_ms) {
  if (poll_exit()) return *status_;
  kill(pid_, SIGTERM);
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(grace_ms);
  while (std::chrono::steady_clock::now() < until) {
    if (poll_exit()) return *status_;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  kill(pid_, SIGKILL);
  return wait();
}

std::string tail_of_file(const std::string& path, std::size_t max_bytes) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return "";
  f.seekg(0, std::ios::end);
  const auto size = static_cast<std::size_t>(f.tellg());
  const std::size_t from = size > max_bytes ? size - max_bytes : 0;
  f.seekg(static_cast<std::streamoff>(from));
  std::string s(size - from, '\0');
  f.read(s.data(), static_cast<std::streamsize>(s.size()));
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s;
}

}  // namespace compaction::worker
