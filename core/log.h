// Logging to standard error, safe from any thread. Loop functions and
// plugins use it for messages a researcher should see.
//
// A line reads "colony: LEVEL: [tick T] [ROBOT] message": the tick and the
// robot appear where there is one. The robot is the one given to LogFor, else
// the one whose controller the calling thread is running (core/crash_report.h:
// RunningScope); the tick is that scope's, else the one the program stepping
// the simulation last set with SetLogTick.
//
// `colony run` chooses the level (--log-level), limits the terminal to
// errors (--quiet), copies every logged line to the run folder's run.log
// (OpenLogFile) and keeps its progress bar on a status line that log lines
// never run into (SetStatusLine).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace colony {

enum class LogLevel { kError = 0, kWarning = 1, kInfo = 2, kDebug = 3 };

// What is logged at all, to the terminal and the log file: lines of a level
// above `level` are dropped. Default kInfo.
void SetLogLevel(LogLevel level);
LogLevel GetLogLevel();
// A further limit for the terminal alone (colony run --quiet: kError); the log
// file still receives every logged line. Default kDebug (no further limit).
void SetTerminalLogLevel(LogLevel level);
// "error", "warning", "info", "debug".
const char* LogLevelName(LogLevel level);
// Reads one of the names above into `level`; false for anything else.
bool ParseLogLevel(std::string_view text, LogLevel& level);

// Writes "colony: <level>: [tick T] [robot] message" when `level` is enabled.
void Log(LogLevel level, const std::string& message);
// The same, about robot `robot` (its id): "[robot]" whatever the calling
// thread runs.
void LogFor(LogLevel level, const std::string& robot, const std::string& message);
inline void LogError(const std::string& message) { Log(LogLevel::kError, message); }
inline void LogWarning(const std::string& message) { Log(LogLevel::kWarning, message); }
inline void LogInfo(const std::string& message) { Log(LogLevel::kInfo, message); }
inline void LogDebug(const std::string& message) { Log(LogLevel::kDebug, message); }

// Sees every line logged about a robot, as it is logged (the live viewer
// keeps each robot's last lines while it serves a run): the robot's id, the
// tick (-1: none), the level and the message. Lines of levels not logged
// (SetLogLevel) never reach it. Called on the logging thread (a pool thread
// for a controller) under the log's lock: it must be quick and must not log.
using RobotLogListener = void (*)(void* context, std::string_view robot, int64_t tick,
                                  LogLevel level, std::string_view message);
// Installs `listener` (nullptr: none) with the `context` it is called with.
void SetRobotLogListener(RobotLogListener listener, void* context);

// The tick shown in lines logged outside plugin code (actuators, engines,
// renderers...): the program stepping the simulation sets it to the tick
// being computed, and to the last tick once the run is done. Until set, and
// after ClearLogTick, lines carry no tick.
void SetLogTick(uint64_t tick);
void ClearLogTick();

// The log file (colony run: the run folder's run.log). After HoldLogLines,
// logged lines are kept in memory until OpenLogFile names the file (the run
// folder may only be created after loading), then written there first.
void HoldLogLines();
// Creates or truncates `path` and copies every logged line there from now
// on, whatever the terminal shows; each line is flushed as it is written, so
// a killed run keeps them. When standard error already is that file (colony
// sweep sends each run's output there), the lines go to it once, through
// standard error. Throws RuntimeFailure naming the file when it cannot be
// created. A write that fails later is reported once on standard error and
// ends the copy.
void OpenLogFile(const std::string& path);
// Closes the log file (and drops held lines); no-op without one.
void CloseLogFile();

// A status line at the bottom of the terminal (colony run's progress bar):
// drawn on standard error after "\r" and the ANSI erase-line sequence. Each
// log line erases it first and draws it again after, so neither runs into
// the other. Only for a terminal: the caller checks isatty(STDERR_FILENO).
void SetStatusLine(const std::string& text);
// Ends the status line with a newline, leaving its last text on screen, and
// stops redrawing it; no-op without one.
void FinishStatusLine();

}  // namespace colony
