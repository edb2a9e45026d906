// The worker's flags: defaults, both value forms, ranges, the errors' exit code and the
// environment fallback of the token.
#include "options.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

using compaction::worker::parse_worker_options;
using compaction::worker::WorkerOptions;

namespace {

// Parses {"compaction-worker", args...} with /bin/sh as the runner (an executable file).
std::optional<WorkerOptions> parse(std::vector<std::string> args, int& code) {
  args.insert(args.begin(), {"compaction-worker", "--runner", "/bin/sh"});
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  return parse_worker_options(static_cast<int>(argv.size()), argv.data(), code);
}

}  // namespace

TEST(WorkerOptionsGtest, DefaultsNameTheLocalServerAndOneThread) {
  unsetenv("COMPACTION_WORKER_TOKEN");
  int code = -1;
  const auto o = parse({}, code);
  ASSERT_TRUE(o);
  EXPECT_EQ(code, 0);
  EXPECT_EQ(o->server, "http://127.0.0.1:8080");
  EXPECT_EQ(o->threads, 1);
  EXPECT_EQ(o->max_jobs, 0);
  EXPECT_EQ(o->poll_interval, 2.0);
  EXPECT_FALSE(o->keep_work);
  EXPECT_EQ(o->runner, "/bin/sh");
  EXPECT_NE(o->work_dir.find("compaction-worker-"), std::string::npos);
  EXPECT_NE(o->name.find(':'), std::string::npos);  // host:pid
}

TEST(WorkerOptionsGtest, ValuesMayFollowTheFlagOrAnEqualsSign) {
  int code = -1;
  const auto o = parse({"--threads=3", "--max-jobs", "5", "--server", "http://h:1//",
                        "--poll-interval=0.5", "--keep-work", "--name", "w1"},
                       code);
  ASSERT_TRUE(o);
  EXPECT_EQ(o->threads, 3);
  EXPECT_EQ(o->max_jobs, 5);
  EXPECT_EQ(o->server, "http://h:1");  // trailing slashes dropped
  EXPECT_EQ(o->poll_interval, 0.5);
  EXPECT_TRUE(o->keep_work);
  EXPECT_EQ(o->name, "w1");
}

TEST(WorkerOptionsGtest, TheLastOfARepeatedFlagWins) {
  int code = -1;
  const auto o = parse({"--threads", "2", "--threads", "4"}, code);
  ASSERT_TRUE(o);
  EXPECT_EQ(o->threads, 4);
}

TEST(WorkerOptionsGtest, BadValuesExitTwo) {
  for (const std::vector<std::string>& args :
       std::vector<std::vector<std::string>>{{"--threads", "0"},
                                             {"--threads", "257"},
                                             {"--threads", "2.5"},
                                             {"--threads", "0x10"},
                                             {"--max-jobs", "-1"},
                                             {"--idle-exit", "nan"},
                                             {"--poll-interval", "0.01"},
                                             {"--server", "ftp://x"},
                                             {"--name", ""},
                                             {"--work-dir", ""},
                                             {"--log-level", "loud"},
                                             {"--bogus", "1"},
                                             {"--threads"}}) {
    int code = -1;
    EXPECT_FALSE(parse(args, code)) << args[0];
    EXPECT_EQ(code, 2) << args[0];
  }
}

TEST(WorkerOptionsGtest, ARunnerThatIsNotExecutableIsRefused) {
  int code = -1;
  EXPECT_FALSE(parse({"--runner", "/nonexistent/compaction-run"}, code));
  EXPECT_EQ(code, 2);
}

TEST(WorkerOptionsGtest, HelpAndVersionExitZero) {
  int code = -1;
  testing::internal::CaptureStdout();
  EXPECT_FALSE(parse({"--help"}, code));
  const std::string help = testing::internal::GetCapturedStdout();
  EXPECT_EQ(code, 0);
  EXPECT_NE(help.find("--poll-interval S"), std::string::npos);
  EXPECT_NE(help.find("in [1, 256] [1]"), std::string::npos);  // --threads: range and default
  code = -1;
  testing::internal::CaptureStdout();
  EXPECT_FALSE(parse({"--version"}, code));
  EXPECT_EQ(testing::internal::GetCapturedStdout().rfind("compaction-worker ", 0), 0u);
  EXPECT_EQ(code, 0);
}

TEST(WorkerOptionsGtest, TheTokenFallsBackOnTheEnvironment) {
  setenv("COMPACTION_WORKER_TOKEN", "from-env", 1);
  int code = -1;
  auto o = parse({}, code);
  ASSERT_TRUE(o);
  EXPECT_EQ(o->token, "from-env");
  o = parse({"--token", "from-flag"}, code);
  ASSERT_TRUE(o);
  EXPECT_EQ(o->token, "from-flag");
  unsetenv("COMPACTION_WORKER_TOKEN");
}
