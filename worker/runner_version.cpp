#include "runner_version.hpp"

#include <chrono>
#include <stdexcept>

#include "child_process.hpp"

namespace compaction::worker {

namespace {

bool version_char(char c) {
  return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '.' ||
         c == '-' || c == '+' || c == '_';
}

}  // namespace

std::optional<RunnerVersion> parse_runner_version(const std::string& line) {
  const std::string prefix = "compaction-run ";
  if (line.rfind(prefix, 0) != 0) return std::nullopt;
  const std::size_t open = line.find(" (", prefix.size());
  if (open == std::string::npos || line.size() < open + 3 || line.back() != ')') {
    return std::nullopt;
  }
  RunnerVersion v{line.substr(prefix.size(), open - prefix.size()),
                  line.substr(open + 2, line.size() - open - 3)};
  if (v.engine_version.empty() || v.engine_version.size() > 100 || v.source_revision.empty()) {
    return std::nullopt;
  }
  for (char c : v.engine_version)
    if (!version_char(c)) return std::nullopt;
  return v;
}

RunnerVersion ask_runner_version(const std::string& runner, double timeout_seconds) {
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                            std::chrono::duration<double>(timeout_seconds));
  ChildProcess child({runner, "--version"}, "/dev/null");
  std::string first;
  bool have_first = false;
  while (!child.eof() && std::chrono::steady_clock::now() < deadline) {
    for (std::string& line : child.read_lines(100)) {
      if (!have_first) first = std::move(line), have_first = true;
    }
  }
  std::optional<ExitStatus> status;
  while (!(status = child.poll_exit()) && std::chrono::steady_clock::now() < deadline) {
    child.read_lines(20);  // eof: a short sleep
  }
  if (!status) {
    child.terminate(1000);
    throw std::runtime_error(runner + " --version did not answer within " +
                             std::to_string(static_cast<int>(timeout_seconds)) + " s");
  }
  if (status->signaled || status->code != 0) {
    throw std::runtime_error(runner + " --version failed (" + status->describe() + ")");
  }
  const auto v = parse_runner_version(first);
  if (!v) {
    throw std::runtime_error(runner + " --version did not say its engine version (expected"
                             " \"compaction-run VERSION (REVISION)\", got \"" +
                             first.substr(0, 200) + "\")");
  }
  return *v;
}

}  // namespace compaction::worker
