// Running the runs: each one a `colony run` process in its own process group,
// N at a time, killed at its timeout or when the sweep is interrupted, with a
// progress line on a terminal.
#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "apps/colony/sweep.h"
#include "core/log.h"

namespace colony::sweep {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

struct Running {
  pid_t pid = 0;
  size_t index = 0;
  Clock::time_point start;
  bool timed_out = false;
  Clock::time_point kill_at;  // after a timeout: SIGKILL if still running then
};

// After its timeout a run gets SIGTERM (it stops after the current tick and
// writes what it has), then SIGKILL if it is still running this much later.
constexpr std::chrono::seconds kTimeoutGrace(2);

// Blocks SIGCHLD and the interrupting signals while alive, so the loop waits
// for them with sigtimedwait (no handlers, no races); children get the mask
// the sweep started with.
class BlockedSignals {
 public:
  BlockedSignals() {
    sigemptyset(&set_);
    for (int s : {SIGCHLD, SIGINT, SIGTERM, SIGHUP}) sigaddset(&set_, s);
    sigprocmask(SIG_BLOCK, &set_, &old_);
  }
  ~BlockedSignals() { sigprocmask(SIG_SETMASK, &old_, nullptr); }
  const sigset_t& set() const { return set_; }
  const sigset_t& old() const { return old_; }

 private:
  sigset_t set_, old_;
};

// The command line of one run. --overwrite: the folder holds the run's log,
// and a run tried again replaces what the last try left.
std::vector<std::string> RunArgs(const Grid& grid, const RunSpec& run,
                                 const RunnerOptions& options) {
  std::vector<std::string> args{options.exe, "run", grid.experiment};
  for (size_t k = 0; k < grid.params.size(); ++k) {
    args.push_back("--set");
    args.push_back(grid.params[k].path + "=" + run.values[k]);
  }
  args.insert(args.end(), {"--seed", std::to_string(run.seed), "--out", RunDir(options.dir, run),
                           "--overwrite", "--quiet"});
  if (options.threads) args.insert(args.end(), {"--threads", std::to_string(*options.threads)});
  return args;
}

// Starts `args` in a new process group with standard output and error going
// to `log`. The child dies with the sweep (PR_SET_PDEATHSIG), so killing the
// sweep, even with SIGKILL, leaves no run behind.
pid_t Spawn(const std::vector<std::string>& args, const std::string& log,
            const sigset_t& child_mask) {
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) throw Failure(std::string("cannot start a run: ") + std::strerror(errno));
  if (pid == 0) {
    setpgid(0, 0);
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(127);
    const int out = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int in = open("/dev/null", O_RDONLY);
    if (out >= 0) {
      dup2(out, STDOUT_FILENO);
      dup2(out, STDERR_FILENO);
    }
    if (in >= 0) dup2(in, STDIN_FILENO);
    sigprocmask(SIG_SETMASK, &child_mask, nullptr);
    execv(argv[0], argv.data());
    dprintf(STDERR_FILENO, "colony sweep: cannot start %s: %s\n", argv[0], std::strerror(errno));
    _exit(127);
  }
  setpgid(pid, pid);  // also here, so a kill right away reaches the group
  return pid;
}

// The last non-empty line the run printed (its error message, if any).
std::string LastLogLine(const std::string& log) {
  std::ifstream in(log, std::ios::binary);
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size <= 0) return "";
  in.seekg(std::max<std::streamoff>(0, size - 4096));
  std::string tail(static_cast<size_t>(size - in.tellg()), '\0');
  in.read(tail.data(), static_cast<std::streamsize>(tail.size()));
  std::replace(tail.begin(), tail.end(), '\r', '\n');
  const size_t end = tail.find_last_not_of(" \n\t");
  if (end == std::string::npos) return "";
  const size_t newline = tail.rfind('\n', end);
  const size_t begin = newline == std::string::npos ? 0 : newline + 1;
  const std::string line = tail.substr(begin, end + 1 - begin);
  return line.size() > 300 ? line.substr(0, 300) + "..." : line;
}

RunEnd EndOf(const Running& r, int wait_status, const RunnerOptions& options,
             const std::string& log) {
  RunEnd end;
  end.wall_seconds = std::chrono::duration<double>(Clock::now() - r.start).count();
  if (r.timed_out) {
    end.status = RunEnd::Status::kTimeout;
    char text[96];
    std::snprintf(text, sizeof text, "stopped after the timeout of %g s", *options.timeout);
    end.detail = text;
    return end;
  }
  if (WIFEXITED(wait_status) && WEXITSTATUS(wait_status) == 0) {
    end.status = RunEnd::Status::kOk;
    return end;
  }
  end.status = RunEnd::Status::kFailed;
  if (WIFSIGNALED(wait_status)) {
    end.detail = "killed by signal " + std::to_string(WTERMSIG(wait_status)) + " (" +
                 strsignal(WTERMSIG(wait_status)) + ")";
  } else {
    end.detail = "exit status " + std::to_string(WEXITSTATUS(wait_status));
  }
  const std::string line = LastLogLine(log);
  if (!line.empty()) end.detail += ": " + line;
  return end;
}

std::string Duration(double seconds) {
  const long s = static_cast<long>(seconds + 0.5);
  char text[32];
  if (s >= 3600) {
    std::snprintf(text, sizeof text, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  } else {
    std::snprintf(text, sizeof text, "%ld:%02ld", s / 60, s % 60);
  }
  return text;
}

// The progress line on standard error, redrawn at most ten times a second.
class Progress {
 public:
  Progress(bool enabled, size_t total, size_t already_done)
      : enabled_(enabled), total_(total), already_done_(already_done) {}
  void Draw(const RunnerTotals& t, size_t running, bool force = false) {
    if (!enabled_) return;
    const auto now = Clock::now();
    if (!force && now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const size_t finished = t.ok + t.failed + t.timeout;
    const size_t left = total_ - already_done_ - finished;
    const std::string eta =
        finished ? "~" + Duration(elapsed / finished * left) + " left" : "time left unknown";
    char text[256];
    std::snprintf(text, sizeof text,
                  "  sweep: %zu/%zu done (%zu failed, %zu timeout), %zu running, %s elapsed, %s",
                  already_done_ + finished, total_, t.failed, t.timeout, running,
                  Duration(elapsed).c_str(), eta.c_str());
    // A status line: log lines (a warning about a run) erase it and draw it again.
    SetStatusLine(text);
  }
  void Finish() {
    if (enabled_) FinishStatusLine();
  }

 private:
  bool enabled_;
  size_t total_, already_done_;
  Clock::time_point start_ = Clock::now(), last_{};
};

void KillGroup(pid_t pid) {
  kill(-pid, SIGKILL);
  kill(pid, SIGKILL);
}

// Waits up to `limit` for a signal; returns it, or 0.
int WaitForSignal(const sigset_t& set, std::chrono::milliseconds limit) {
  timespec ts{static_cast<time_t>(limit.count() / 1000),
              static_cast<long>(limit.count() % 1000) * 1'000'000};
  const int sig = sigtimedwait(&set, nullptr, &ts);
  return sig > 0 ? sig : 0;
}

}  // namespace

RunnerTotals RunAll(const Grid& grid, const std::vector<size_t>& pending, size_t already_done,
                    const RunnerOptions& options,
                    const std::function<void(size_t, const Row&)>& finished) {
  BlockedSignals signals;
  RunnerTotals totals;
  Progress progress(options.progress, pending.size() + already_done, already_done);
  std::vector<Running> running;
  size_t next = 0;
  while (next < pending.size() || !running.empty()) {
    // Reap the runs that ended and record them.
    for (size_t i = 0; i < running.size();) {
      int status = 0;
      if (waitpid(running[i].pid, &status, WNOHANG) != running[i].pid) {
        ++i;
        continue;
      }
      const RunSpec run = RunAt(grid, running[i].index);
      const std::string dir = RunDir(options.dir, run);
      const Row row = MakeRow(grid, run, EndOf(running[i], status, options, dir + "/run.log"), dir,
                              options.code);
      WriteRow(dir, row);
      const std::string s = RowStatus(row);
      (s == "ok" ? totals.ok : s == "timeout" ? totals.timeout : totals.failed)++;
      finished(run.index, row);
      running.erase(running.begin() + static_cast<std::ptrdiff_t>(i));
    }
    if (totals.interrupted) break;
    // Start runs up to the number of jobs.
    while (running.size() < static_cast<size_t>(options.jobs) && next < pending.size()) {
      const RunSpec run = RunAt(grid, pending[next++]);
      const std::string dir = RunDir(options.dir, run);
      fs::remove_all(dir);
      fs::create_directories(dir);
      const auto start = Clock::now();
      running.push_back({Spawn(RunArgs(grid, run, options), dir + "/run.log", signals.old()),
                         run.index,
                         start,
                         false,
                         {}});
    }
    // Kill the runs past their timeout (their end is recorded when reaped).
    auto wait = std::chrono::milliseconds(100);
    for (auto& r : running) {
      if (!options.timeout) continue;
      if (r.timed_out) {
        if (Clock::now() >= r.kill_at) KillGroup(r.pid);
        continue;
      }
      const auto deadline = r.start + std::chrono::duration_cast<Clock::duration>(
                                          std::chrono::duration<double>(*options.timeout));
      if (Clock::now() >= deadline) {
        kill(-r.pid, SIGTERM);
        kill(r.pid, SIGTERM);
        r.timed_out = true;
        r.kill_at = Clock::now() + kTimeoutGrace;
      } else {
        wait =
            std::min(wait, std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now()));
      }
    }
    progress.Draw(totals, running.size());
    if (running.empty() && next >= pending.size()) break;
    const int sig = WaitForSignal(signals.set(), wait);
    if (sig == SIGINT || sig == SIGTERM || sig == SIGHUP) {
      totals.interrupted = true;
      totals.signal = sig;
    }
  }
  // Interrupted: the running runs are killed and stay unfinished.
  for (const auto& r : running) {
    KillGroup(r.pid);
    waitpid(r.pid, nullptr, 0);
  }
  progress.Draw(totals, 0, true);
  progress.Finish();
  return totals;
}

}  // namespace colony::sweep
