// The engine version the worker leases for is the runner's: read from `compaction-run
// --version`, and a runner that cannot say it is refused with the reason.
#include "runner_version.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>
#include <stdexcept>

#include "temp_dir.hpp"

using compaction::worker::ask_runner_version;
using compaction::worker::parse_runner_version;

namespace {

// An executable shell script in `dir` with the given body.
std::string script(const TempDir& dir, const std::string& name, const std::string& body) {
  const std::string path = dir.file(name);
  std::ofstream(path) << "#!/bin/sh\n" << body << "\n";
  chmod(path.c_str(), 0755);
  return path;
}

std::string failure_of(const std::string& runner, double timeout = 10) {
  try {
    ask_runner_version(runner, timeout);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(RunnerVersionGtest, ReadsTheVersionAndRevisionOfTheRunnersLine) {
  const auto v = parse_runner_version("compaction-run 0.2.1 (0864a1d66b49-dirty)");
  ASSERT_TRUE(v);
  EXPECT_EQ(v->engine_version, "0.2.1");
  EXPECT_EQ(v->source_revision, "0864a1d66b49-dirty");
}

TEST(RunnerVersionGtest, RefusesLinesOfAnotherForm) {
  for (const char* line : {"", "compaction-run", "compaction-run 0.2.1", "compaction-run  (abc)",
                           "compaction-server 0.2.1 (abc)", "true (GNU coreutils) 9.1",
                           "compaction-run 0.2.1 ()", "compaction-run 0 2 (abc)"}) {
    EXPECT_FALSE(parse_runner_version(line)) << line;
  }
}

TEST(RunnerVersionGtest, AsksTheRunnerOnce) {
  TempDir dir;
  const std::string runner = script(dir, "runner",
                                    "[ \"$1\" = --version ] || exit 9\n"
                                    "echo 'compaction-run 9.8.7 (feedbeef)'");
  const auto v = ask_runner_version(runner);
  EXPECT_EQ(v.engine_version, "9.8.7");
  EXPECT_EQ(v.source_revision, "feedbeef");
}

TEST(RunnerVersionGtest, ARunnerThatCannotSayIsRefusedWithTheReason) {
  TempDir dir;
  EXPECT_NE(failure_of(script(dir, "other", "echo 'some tool 1.0'")).find("some tool 1.0"),
            std::string::npos);
  EXPECT_NE(failure_of(script(dir, "failing", "exit 4")).find("exit code 4"), std::string::npos);
  EXPECT_NE(failure_of(script(dir, "silent", "exec sleep 30"), 0.3).find("did not answer"),
            std::string::npos);
}
