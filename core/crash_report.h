// Signals during a run. Interrupts (SIGINT, SIGTERM, SIGHUP) ask the run to
// stop after the current tick; crashes (SIGSEGV, SIGBUS, SIGFPE, SIGILL,
// SIGABRT) write one line naming the plugin code that was running (robot,
// controller or loop functions, library, tick), write out the rows already
// computed (RowFile), then end the process with the signal as before.
#pragma once

#include <cstdint>

namespace colony {

// What plugin code the calling thread is running now, for the crash line.
// Pointers must outlive the scope (robot ids, plugin labels and library
// paths live as long as the simulation).
struct RunningCode {
  const char* kind = nullptr;     // "controller", "loop functions", "sensor", ...
  const char* label = nullptr;    // the plugin's label
  const char* library = nullptr;  // the shared library it came from, or null (built in)
  const char* robot = nullptr;    // the robot's id, or null
  uint64_t tick = 0;              // the tick being computed
};

// Marks the calling thread as running `code` until the scope ends. A loop
// over robots opens one scope and updates code() per robot: plain stores,
// no thread-local lookup per robot.
class RunningScope {
 public:
  explicit RunningScope(const RunningCode& code);
  ~RunningScope();
  RunningScope(const RunningScope&) = delete;
  RunningScope& operator=(const RunningScope&) = delete;
  RunningCode& code() { return *current_; }

 private:
  RunningCode previous_;
  RunningCode* current_;
};

// What the calling thread is running now (kind null outside plugin code);
// the log (core/log.h) tags its lines with its robot and tick.
const RunningCode& CurrentlyRunning();

// Installs the crash handlers (process-wide; on an alternate stack for the
// calling thread, so a stack overflow is reported too).
void InstallCrashHandlers();

// Gives the calling thread its own stack for signal handlers, so a stack
// overflow on it is reported too (thread pool workers call it).
void UseAlternateSignalStack();

// Installs the interrupt handlers. A second interrupt ends the process at
// once, as if there were no handler.
void InstallStopHandlers();
// The interrupting signal received since InstallStopHandlers, or 0.
int StopSignal();
// "SIGINT", "SIGSEGV"...
const char* SignalName(int signal_number);

}  // namespace colony
