// The log (core/log.h) as a reader of the terminal and of run.log sees it:
// the level, the tick and the robot in each line, levels, the log file and
// the lines logged before it was opened, and a status line that log lines
// never run into.
#include "core/log.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "core/crash_report.h"
#include "tests/test_util.h"

namespace colony {
namespace {

namespace fs = std::filesystem;
using colony::testing::ReadFile;

class LogTest : public ::testing::Test {
 protected:
  void TearDown() override {
    SetLogLevel(LogLevel::kInfo);
    SetTerminalLogLevel(LogLevel::kDebug);
    ClearLogTick();
    CloseLogFile();
    fs::remove_all(dir_);
  }
  const fs::path dir_ = colony::testing::FreshTempDir("colony_log_test", "files");
};

TEST_F(LogTest, LinesCarryTheirLevelTickAndRobot) {
  ::testing::internal::CaptureStderr();
  LogInfo("loading");
  SetLogTick(120);
  LogWarning("a tick, no robot");
  LogFor(LogLevel::kWarning, "fb3", "about fb3");
  {
    // Plugin code: its scope's robot and tick (the one being computed).
    RunningScope running({"controller", "diffusion", nullptr, "mb7", 42});
    LogError("from mb7's controller");
    LogFor(LogLevel::kInfo, "mb8", "about another robot");
  }
  ClearLogTick();
  LogInfo("done");
  EXPECT_EQ(::testing::internal::GetCapturedStderr(),
            "colony: info: loading\n"
            "colony: warning: [tick 120] a tick, no robot\n"
            "colony: warning: [tick 120] [fb3] about fb3\n"
            "colony: error: [tick 42] [mb7] from mb7's controller\n"
            "colony: info: [tick 42] [mb8] about another robot\n"
            "colony: info: done\n");
}

TEST_F(LogTest, LevelsDropLinesAndTheTerminalMayShowFewer) {
  const fs::path file = dir_ / "run.log";
  fs::create_directories(dir_);
  OpenLogFile(file.string());
  SetLogLevel(LogLevel::kWarning);
  SetTerminalLogLevel(LogLevel::kError);  // --quiet
  ::testing::internal::CaptureStderr();
  LogDebug("d");
  LogInfo("i");
  LogWarning("w");
  LogError("e");
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "colony: error: e\n");
  CloseLogFile();
  EXPECT_EQ(ReadFile(file), "colony: warning: w\ncolony: error: e\n");
  SetLogLevel(LogLevel::kDebug);
  EXPECT_EQ(GetLogLevel(), LogLevel::kDebug);
}

TEST_F(LogTest, LinesBeforeTheFileIsOpenedAreWrittenFirst) {
  ::testing::internal::CaptureStderr();
  HoldLogLines();
  LogWarning("while loading");
  fs::create_directories(dir_);
  OpenLogFile((dir_ / "run.log").string());
  LogWarning("while running");
  CloseLogFile();
  EXPECT_EQ(::testing::internal::GetCapturedStderr(),
            "colony: warning: while loading\ncolony: warning: while running\n");
  EXPECT_EQ(ReadFile(dir_ / "run.log"),
            "colony: warning: while loading\ncolony: warning: while running\n");
  // Closed: nothing more goes there, and nothing is held.
  ::testing::internal::CaptureStderr();
  LogWarning("after");
  ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(ReadFile(dir_ / "run.log"),
            "colony: warning: while loading\ncolony: warning: while running\n");
}

TEST_F(LogTest, AFileThatCannotBeCreatedIsNamed) {
  try {
    OpenLogFile((dir_ / "no" / "such" / "run.log").string());
    ADD_FAILURE() << "no error";
  } catch (const RuntimeFailure& e) {
    EXPECT_NE(std::string(e.what()).find("cannot create the log file '" +
                                         (dir_ / "no" / "such" / "run.log").string() +
                                         "': No such file or directory"),
              std::string::npos)
        << e.what();
  }
}

// colony sweep sends a run's standard error to its run.log: the lines go
// there once, all of them, even those --quiet keeps off a terminal.
TEST_F(LogTest, StandardErrorAlreadyBeingTheFileGetsEachLineOnce) {
  fs::create_directories(dir_);
  const fs::path file = dir_ / "run.log";
  std::fflush(stderr);
  const int saved = dup(STDERR_FILENO);
  const int fd = open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ASSERT_GE(fd, 0);
  dup2(fd, STDERR_FILENO);
  close(fd);
  SetTerminalLogLevel(LogLevel::kError);
  HoldLogLines();
  LogWarning("held");
  LogError("held error");
  OpenLogFile(file.string());
  LogWarning("after");
  CloseLogFile();
  std::fflush(stderr);
  dup2(saved, STDERR_FILENO);
  close(saved);
  EXPECT_EQ(ReadFile(file),
            "colony: error: held error\ncolony: warning: held\ncolony: warning: after\n");
}

TEST_F(LogTest, LogLinesEraseTheStatusLineAndDrawItAgain) {
  const std::string erase = "\r\x1b[2K";
  ::testing::internal::CaptureStderr();
  SetStatusLine("[====>   ] 50%");
  LogWarning("w");
  SetStatusLine("[========] 100%");
  FinishStatusLine();
  LogInfo("after");
  FinishStatusLine();  // no status line: nothing
  EXPECT_EQ(::testing::internal::GetCapturedStderr(),
            erase + "[====>   ] 50%" + erase + "colony: warning: w\n" + erase + "[====>   ] 50%" +
                erase + "[========] 100%\ncolony: info: after\n");
}

TEST_F(LogTest, LevelNames) {
  LogLevel level = LogLevel::kInfo;
  for (LogLevel l : {LogLevel::kError, LogLevel::kWarning, LogLevel::kInfo, LogLevel::kDebug}) {
    EXPECT_TRUE(ParseLogLevel(LogLevelName(l), level));
    EXPECT_EQ(level, l);
  }
  EXPECT_FALSE(ParseLogLevel("verbose", level));
  EXPECT_FALSE(ParseLogLevel("", level));
}

}  // namespace
}  // namespace colony
