#include "core/crash_report.h"

#include <signal.h>
#include <unistd.h>

#include <cstring>
#include <memory>

#include "core/run_files.h"

namespace colony {

namespace {

thread_local RunningCode running;
volatile sig_atomic_t stop_signal = 0;

// A line built without allocating, for the signal handler.
class Line {
 public:
  Line& operator<<(const char* s) {
    while (s && *s && size_ < sizeof text_) text_[size_++] = *s++;
    return *this;
  }
  Line& operator<<(uint64_t v) {
    char digits[24];
    int n = 0;
    do {
      digits[n++] = static_cast<char>('0' + v % 10);
      v /= 10;
    } while (v);
    while (n > 0 && size_ < sizeof text_) text_[size_++] = digits[--n];
    return *this;
  }
  void WriteTo(int fd) const {
    size_t done = 0;
    while (done < size_) {
      const ssize_t n = ::write(fd, text_ + done, size_ - done);
      if (n <= 0) return;
      done += static_cast<size_t>(n);
    }
  }

 private:
  char text_[1024];
  size_t size_ = 0;
};

const char* SignalMeaning(int s) {
  switch (s) {
    case SIGSEGV:
      return "segmentation fault";
    case SIGBUS:
      return "bus error";
    case SIGFPE:
      return "arithmetic error";
    case SIGILL:
      return "illegal instruction";
    case SIGABRT:
      return "aborted";
    default:
      return "signal";
  }
}

void OnCrash(int signal_number) {
  const RunningCode code = running;
  Line line;
  line << "\ncolony: crashed with " << SignalName(signal_number) << " ("
       << SignalMeaning(signal_number) << ") ";
  if (code.kind) {
    line << "in " << code.kind << " '" << code.label << "'";
    if (code.robot) line << " of robot '" << code.robot << "'";
    line << " at tick " << code.tick << " (library "
         << (code.library ? code.library : "built into Colony") << ")";
  } else {
    line << "in Colony itself, not in a plugin; please report it";
  }
  line << "; metrics and hashes up to the last finished tick are written\n";
  line.WriteTo(STDERR_FILENO);
  RowFile::FlushAllAfterCrash();
  // The handler was reset (SA_RESETHAND): the signal, delivered again once
  // this returns, ends the process with its usual status.
  ::raise(signal_number);
}

void OnStop(int signal_number) { stop_signal = signal_number; }

}  // namespace

RunningScope::RunningScope(const RunningCode& code) : previous_(running), current_(&running) {
  running = code;
}
RunningScope::~RunningScope() { running = previous_; }

const RunningCode& CurrentlyRunning() { return running; }

void UseAlternateSignalStack() {
  constexpr size_t kSize = 1 << 16;
  // A stack the thread already has (its own, or one a sanitizer runtime gave
  // it and will unmap when the thread ends) is kept.
  stack_t current{};
  if (sigaltstack(nullptr, &current) == 0 && !(current.ss_flags & SS_DISABLE)) return;
  // Freed when the thread ends, once it no longer is the thread's signal stack.
  struct Alternate {
    std::unique_ptr<char[]> memory;
    ~Alternate() {
      stack_t off{};
      off.ss_flags = SS_DISABLE;
      sigaltstack(&off, nullptr);
    }
  };
  thread_local Alternate alternate;
  alternate.memory.reset(new char[kSize]);
  stack_t stack{};
  stack.ss_sp = alternate.memory.get();
  stack.ss_size = kSize;
  sigaltstack(&stack, nullptr);
}

void InstallCrashHandlers() {
  UseAlternateSignalStack();
  struct sigaction action {};
  action.sa_handler = OnCrash;
  action.sa_flags = SA_RESETHAND | SA_ONSTACK;
  sigemptyset(&action.sa_mask);
  for (int s : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) sigaction(s, &action, nullptr);
}

void InstallStopHandlers() {
  struct sigaction action {};
  action.sa_handler = OnStop;
  action.sa_flags = SA_RESETHAND;  // a second interrupt ends the process at once
  sigemptyset(&action.sa_mask);
  for (int s : {SIGINT, SIGTERM, SIGHUP}) sigaction(s, &action, nullptr);
}

int StopSignal() { return stop_signal; }

const char* SignalName(int s) {
  switch (s) {
    case SIGINT:
      return "SIGINT";
    case SIGTERM:
      return "SIGTERM";
    case SIGHUP:
      return "SIGHUP";
    case SIGSEGV:
      return "SIGSEGV";
    case SIGBUS:
      return "SIGBUS";
    case SIGFPE:
      return "SIGFPE";
    case SIGILL:
      return "SIGILL";
    case SIGABRT:
      return "SIGABRT";
    default:
      return "a signal";
  }
}

}  // namespace colony
