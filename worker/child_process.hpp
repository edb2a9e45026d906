// A child process (the runner) with its stdout read line by line through a pipe and its stderr
// written to a file. The child dies with the worker (PR_SET_PDEATHSIG) and runs in its own
// process group, so a terminal's Ctrl-C reaches the worker, which stops it in order.
#pragma once

#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

namespace compaction::worker {

struct ExitStatus {
  bool signaled = false;
  int code = 0;    // exit code, or the signal number when signaled
  std::string describe() const;
};

class ChildProcess {
 public:
  // Starts argv[0] with argv; throws std::runtime_error when it cannot.
  ChildProcess(const std::vector<std::string>& argv, const std::string& stderr_file);
  ~ChildProcess();  // kills and reaps a child still running
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  // Waits up to timeout_ms for output; returns the complete lines read (possibly none).
  // Sets eof once stdout is closed.
  std::vector<std::string> read_lines(int timeout_ms);
  bool eof() const { return eof_; }

  // Non-blocking: the exit status once the child ended.
  std::optional<ExitStatus> poll_exit();
  // SIGTERM, then SIGKILL after grace_ms; reaps the child and returns its status.
  ExitStatus terminate(int grace_ms);
  ExitStatus wait();
  pid_t pid() const { return pid_; }

 private:
  pid_t pid_ = -1;
  int out_fd_ = -1;
  bool eof_ = false;
  std::string buffer_;
  std::optional<ExitStatus> status_;
};

// The last max_bytes of a file (the runner's stderr for failure reasons).
std::string tail_of_file(const std::string& path, std::size_t max_bytes);

}  // namespace compaction::worker
