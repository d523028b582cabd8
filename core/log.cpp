#include "core/log.h"

#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <vector>

#include "core/crash_report.h"
#include "core/error.h"

namespace colony {

namespace {

constexpr const char* kNames[] = {"error", "warning", "info", "debug"};
// Back to the start of the line, then erase it (ANSI "erase in line", whole line).
constexpr const char* kEraseLine = "\r\x1b[2K";

std::atomic<int> g_level{static_cast<int>(LogLevel::kInfo)};
std::atomic<int> g_terminal_level{static_cast<int>(LogLevel::kDebug)};
std::atomic<int64_t> g_tick{-1};  // -1: no tick

// Where lines go besides the terminal, and the status line. Guarded by
// Sinks::mutex; a function-local static, since plugins may log during static
// initialisation.
struct Sinks {
  struct HeldLine {
    std::string text;
    bool shown;  // already written to the terminal
  };
  std::mutex mutex;
  bool holding = false;
  std::vector<HeldLine> held;
  std::FILE* file = nullptr;
  std::string file_path;
  bool file_is_stderr = false;  // standard error is the log file itself
  bool status_active = false;
  std::string status;  // kEraseLine + the status line's text
  RobotLogListener robot_listener = nullptr;
  void* robot_listener_context = nullptr;

  // `text` (whole lines) to standard error, under the status line if any.
  void WriteTerminal(const std::string& text) {
    if (status_active) {
      const std::string out = kEraseLine + text + status;
      std::fwrite(out.data(), 1, out.size(), stderr);
    } else {
      std::fwrite(text.data(), 1, text.size(), stderr);
    }
  }

  // `text` to the log file; a failed write is reported once and ends the copy.
  void WriteFile(const std::string& text) {
    if (std::fputs(text.c_str(), file) >= 0 && std::fflush(file) == 0) return;
    const int error = errno;
    std::fclose(file);
    file = nullptr;
    WriteTerminal("colony: warning: cannot write the log file '" + file_path +
                  "': " + std::strerror(error) + "; it is not written any more\n");
  }
};

Sinks& TheSinks() {
  static Sinks sinks;
  return sinks;
}

void Emit(LogLevel level, const char* robot, const std::string& message) {
  if (static_cast<int>(level) > g_level.load()) return;
  // Plugin code running on this thread knows its tick (the one being
  // computed) and robot exactly; other code gets the program's tick.
  const RunningCode& code = CurrentlyRunning();
  const int64_t tick = code.kind ? static_cast<int64_t>(code.tick) : g_tick.load();
  if (!robot) robot = code.robot;
  std::string line = "colony: ";
  line += kNames[static_cast<int>(level)];
  line += ": ";
  if (tick >= 0) line += "[tick " + std::to_string(tick) + "] ";
  if (robot && *robot) {
    line += '[';
    line += robot;
    line += "] ";
  }
  line += message;
  line += '\n';

  Sinks& s = TheSinks();
  std::lock_guard lock(s.mutex);
  const bool terminal = static_cast<int>(level) <= g_terminal_level.load() || s.file_is_stderr;
  if (terminal) s.WriteTerminal(line);
  if (s.robot_listener && robot && *robot) {
    s.robot_listener(s.robot_listener_context, robot, tick, level, message);
  }
  if (s.file) {
    s.WriteFile(line);
  } else if (s.holding) {
    s.held.push_back({std::move(line), terminal});
  }
}

}  // namespace

void SetLogLevel(LogLevel level) { g_level = static_cast<int>(level); }
LogLevel GetLogLevel() { return static_cast<LogLevel>(g_level.load()); }
void SetTerminalLogLevel(LogLevel level) { g_terminal_level = static_cast<int>(level); }

const char* LogLevelName(LogLevel level) { return kNames[static_cast<int>(level)]; }

bool ParseLogLevel(std::string_view text, LogLevel& level) {
  for (int i = 0; i < 4; ++i) {
    if (text == kNames[i]) {
      level = static_cast<LogLevel>(i);
      return true;
    }
  }
  return false;
}

void Log(LogLevel level, const std::string& message) { Emit(level, nullptr, message); }

void LogFor(LogLevel level, const std::string& robot, const std::string& message) {
  Emit(level, robot.c_str(), message);
}

void SetRobotLogListener(RobotLogListener listener, void* context) {
  Sinks& s = TheSinks();
  std::lock_guard lock(s.mutex);
  s.robot_listener = listener;
  s.robot_listener_context = context;
}

void SetLogTick(uint64_t tick) { g_tick = static_cast<int64_t>(tick); }
void ClearLogTick() { g_tick = -1; }

void HoldLogLines() {
  Sinks& s = TheSinks();
  std::lock_guard lock(s.mutex);
  s.holding = true;
}

void OpenLogFile(const std::string& path) {
  Sinks& s = TheSinks();
  std::lock_guard lock(s.mutex);
  if (s.file) std::fclose(s.file);
  s.file = nullptr;
  s.file_path = path;
  // Standard error already is the file: opening it again would write over
  // what goes there through standard error.
  struct stat err {
  }, existing{};
  s.file_is_stderr = fstat(STDERR_FILENO, &err) == 0 && stat(path.c_str(), &existing) == 0 &&
                     err.st_dev == existing.st_dev && err.st_ino == existing.st_ino;
  if (s.file_is_stderr) {
    for (const auto& line : s.held) {
      if (!line.shown) s.WriteTerminal(line.text);
    }
  } else {
    s.file = std::fopen(path.c_str(), "w");
    if (!s.file) {
      throw RuntimeFailure("cannot create the log file '" + path + "': " + std::strerror(errno));
    }
    for (const auto& line : s.held) {
      if (s.file) s.WriteFile(line.text);
    }
  }
  s.held.clear();
  s.holding = false;
}

void CloseLogFile() {
  Sinks& s = TheSinks();
  std::lock_guard lock(s.mutex);
  if (s.file && std::fclose(s.file) != 0) {
    s.WriteTerminal("colony: warning: cannot write the log file '" + s.file_path +
                    "': " + std::strerror(errno) + "\n");
  }
  s.file = nullptr;
  s.file_is_stderr = false;
  s.held.clear();
  s.holding = false;
}

void SetStatusLine(const std::string& text) {
  Sinks& s = TheSinks();
  std::lock_guard lock(s.mutex);
  s.status = kEraseLine + text;
  s.status_active = true;
  std::fwrite(s.status.data(), 1, s.status.size(), stderr);
}

void FinishStatusLine() {
  Sinks& s = TheSinks();
  std::lock_guard lock(s.mutex);
  if (!s.status_active) return;
  std::fputc('\n', stderr);
  s.status_active = false;
}

}  // namespace colony
