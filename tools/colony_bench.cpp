// colony_bench: speed and memory of fixed benchmark scenes.
//
//   colony_bench FILE.xml... [--threads N] [--repeat K] [--ticks T] [--set PATH=VALUE]...
//                [--max-bytes-per-robot B]
//   (CLI11, as colony: apps/colony/command_line.h; colony_bench --help)
//
// For each scene: loads it K times (default 3); each time runs T ticks (default:
// the file's length) and measures
//   - robot-steps per second: robots x ticks / seconds spent inside
//     Simulation::Step (loading and set-up excluded);
//   - load seconds (Simulation::Load: parsing, placement, plugin set-up), with
//     the CPU seconds the process spent in it (steadier than wall time on a
//     shared machine), and teardown seconds (deleting the simulation);
//   - memory per robot: (peak resident set during load + run - resident set
//     before loading) / robots, in bytes; and the resident set growth during
//     the load alone.
// Peak memory is the kernel's VmHWM. Before each repetition the previous
// simulation is destroyed, freed memory is handed back to the system
// (malloc_trim) and VmHWM is reset to the current resident set (writing 5 to
// /proc/self/clear_refs), so each repetition measures its own peak. Where
// the reset is not allowed, the first repetition is still exact and later
// ones are marked "(hwm not reset)".
//
// It also reports the CPU time of the process over the stepping loop: as
// "cores busy" (CPU seconds / step seconds; below the thread count when
// threads wait, or when other programs take the cores) and per robot-step,
// which is steadier than wall time on a shared machine.
//
// It prints each phase's share of the step time (Simulation::profile: act,
// physics, media, loop functions, sense + control), and how long the threads
// waited on each other (ThreadPool::waits): a worker's mean delay in taking
// up a job (us) and the caller's waits for other threads' last chunks (% of
// the step time); both 0 with one thread.
//
// Prints one line per repetition, the medians, and one machine-readable line
// per scene:
//   RESULT scene=NAME robots=N threads=T ticks=K steps_per_s_median=...
//          load_s_median=... load_cpu_s_median=... teardown_s_median=... bytes_per_robot=...
//          load_bytes_per_robot=...
//          cpu_ns_per_robot_step=... state_hash=... act_pct=... physics_pct=...
//          media_pct=... loop_functions_pct=... sense_control_pct=...
//          worker_start_us=... caller_wait_pct=...
// (threads as resolved: 0 and 1 both mean the calling thread only, shown as 1; the state
// hash is that of the first repetition, and a warning is printed if the
// repetitions disagree.)
// With --max-bytes-per-robot B, a scene whose median peak bytes per robot
// exceed B is reported ("OVER BUDGET ...") and the exit status is 1: the
// test suite's memory budget check, a count of bytes rather than a timing.
// Exit status: 0 success, 2 bad arguments or experiment file, 1 failure while running
// or over the memory budget.
#include <malloc.h>
#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "apps/colony/command_line.h"
#include "core/error.h"
#include "core/log.h"
#include "core/simulation.h"
#include "core/state_hash.h"
#include "core/text.h"
#include "core/thread_pool.h"

namespace {

using colony::cli::UsageError;

// A "Vm...:  1234 kB" field of /proc/self/status, in bytes (-1 if absent).
long long ProcStatusBytes(const char* field) {
  std::ifstream f("/proc/self/status");
  std::string line;
  const size_t n = std::strlen(field);
  while (std::getline(f, line)) {
    if (line.compare(0, n, field) == 0 && line.size() > n && line[n] == ':') {
      return std::atoll(line.c_str() + n + 1) * 1024;
    }
  }
  return -1;
}

long long PeakBytes() {
  const long long hwm = ProcStatusBytes("VmHWM");
  if (hwm >= 0) return hwm;
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<long long>(u.ru_maxrss) * 1024;
}

long long CurrentBytes() { return ProcStatusBytes("VmRSS"); }

// Resets VmHWM to the current resident set; false if not allowed.
bool ResetPeak() {
  std::FILE* f = std::fopen("/proc/self/clear_refs", "w");
  if (!f) return false;
  const bool ok = std::fputs("5", f) >= 0;
  return std::fclose(f) == 0 && ok;
}

// CPU time of the whole process (every thread), in seconds.
double CpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n == 0 ? 0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct Options {
  std::vector<std::string> files;
  std::vector<std::string> overrides;
  std::optional<int> threads;
  int repeat = 3;
  long long ticks = 0;  // 0: the file's length
  // Exit status 1 when a scene's median peak bytes per robot exceed it (0: no limit).
  long long max_bytes_per_robot = 0;
};

// The command line into `o`; false when --help was given (and printed).
// Throws UsageError.
bool ParseArgs(const std::vector<std::string>& args, Options& o) {
  CLI::App app{
      "Speed and memory of fixed benchmark scenes (docs/benchmarks.md): each scene "
      "loaded and run K times, one line per repetition, the medians, and a RESULT line.",
      "colony_bench"};
  colony::cli::SetUpHelp(app);
  app.allow_extras();
  std::string threads, repeat, ticks;
  app.add_option("FILE", o.files, "benchmark scenes, e.g. experiments/benchmarks/*.xml")
      ->type_name("FILE.xml");
  app.add_option("--threads", threads,
                 "threads, 0 to 256 (default: the file's <system threads>; 0 and 1 both mean the "
                 "calling thread only)")
      ->type_name("N");
  app.add_option("--repeat", repeat,
                 "loads and runs of each scene, 1 to 1000 (default 3); medians are reported")
      ->type_name("K");
  app.add_option("--ticks", ticks, "ticks per run, 1 to 10^9 (default: the file's length)")
      ->type_name("T");
  std::string max_bytes;
  app.add_option("--max-bytes-per-robot", max_bytes,
                 "a memory budget: exit status 1 when a scene's median peak bytes per robot "
                 "exceed B (the test suite's check on diffusion_10000)")
      ->type_name("B");
  colony::cli::AddListOption(app, "--set", o.overrides,
                             "overrides an attribute, as in colony run; repeatable")
      ->type_name("PATH=VALUE");
  if (!colony::cli::Parse(app, args)) return false;
  if (app.count("--threads"))
    o.threads = static_cast<int>(colony::cli::ParseWhole("--threads", threads, 0, 256));
  if (app.count("--repeat"))
    o.repeat = static_cast<int>(colony::cli::ParseWhole("--repeat", repeat, 1, 1000));
  if (app.count("--ticks")) o.ticks = colony::cli::ParseWhole("--ticks", ticks, 1, 1'000'000'000);
  if (app.count("--max-bytes-per-robot"))
    o.max_bytes_per_robot =
        colony::cli::ParseWhole("--max-bytes-per-robot", max_bytes, 1, 1'000'000'000);
  if (o.files.empty()) throw UsageError("no experiment file given: colony_bench FILE.xml...");
  return true;
}

struct Repetition {
  double load_s = 0, load_cpu_s = 0, step_s = 0, steps_per_s = 0, teardown_s = 0;
  double cpu_s = 0;  // process CPU time over the stepping loop (all threads)
  double bytes_per_robot = 0, load_bytes_per_robot = 0;
  size_t robots = 0;
  int threads = 0;
  uint64_t ticks = 0;
  uint64_t hash = 0;
  bool peak_reset = true;
  colony::StepProfile profile;
  // Threads waiting on each other over the stepping loop (core/thread_pool.h):
  // a worker's mean delay in taking up a job (us), and the caller's waits for
  // other threads' last chunks as a share of the step time (%).
  double worker_start_us = 0, caller_wait_pct = 0;
};

// Loads and runs `file` once.
Repetition RunOnce(const Options& o, const std::string& file, bool first) {
  using Clock = std::chrono::steady_clock;
  Repetition r;
  malloc_trim(0);
  r.peak_reset = ResetPeak() || first;
  const long long rss0 = CurrentBytes();
  const long long peak0 = PeakBytes();

  colony::ExperimentOptions eo;
  eo.file = file;
  eo.overrides = o.overrides;
  eo.threads = o.threads;
  const double load_cpu0 = CpuSeconds();
  const auto t0 = Clock::now();
  auto sim = colony::Simulation::Load(eo);
  r.load_s = std::chrono::duration<double>(Clock::now() - t0).count();
  r.load_cpu_s = CpuSeconds() - load_cpu0;
  const long long rss_loaded = CurrentBytes();

  const uint64_t ticks = o.ticks > 0 ? static_cast<uint64_t>(o.ticks) : sim->length_ticks();
  if (ticks == 0) {
    throw UsageError(file + ": the experiment has no length (unlimited); give --ticks T");
  }
  double robot_ticks = 0;
  sim->ResetProfile();
  sim->pool().ResetWaits();
  const double cpu0 = CpuSeconds();
  for (uint64_t t = 0; t < ticks; ++t) {
    const auto s0 = Clock::now();
    sim->Step();
    r.step_s += std::chrono::duration<double>(Clock::now() - s0).count();
    robot_ticks += static_cast<double>(sim->robot_count());
    // Loop functions may end the experiment early; --ticks runs past the length.
    if (o.ticks == 0 && sim->Done()) break;
  }
  r.cpu_s = CpuSeconds() - cpu0;
  r.ticks = sim->tick();
  r.robots = sim->robot_count();
  r.threads = sim->threads();
  r.steps_per_s = r.step_s > 0 ? robot_ticks / r.step_s : 0;
  r.hash = sim->StateHash();
  r.profile = sim->profile();
  const colony::ThreadPool::Waits waits = sim->pool().waits();
  if (waits.worker_starts > 0) r.worker_start_us = 1e6 * waits.worker_start_s / waits.worker_starts;
  if (r.step_s > 0) r.caller_wait_pct = 100 * waits.caller_wait_s / r.step_s;
  const long long peak = PeakBytes();
  const double robots = static_cast<double>(std::max<size_t>(r.robots, 1));
  r.bytes_per_robot = static_cast<double>(peak - peak0) / robots;
  r.load_bytes_per_robot = static_cast<double>(rss_loaded - rss0) / robots;
  const auto t1 = Clock::now();
  sim.reset();
  r.teardown_s = std::chrono::duration<double>(Clock::now() - t1).count();
  return r;
}

int Bench(const Options& o) {
  int status = 0;
  for (const auto& file : o.files) {
    const std::string scene = std::filesystem::path(file).stem().string();
    std::vector<Repetition> reps;
    for (int k = 0; k < o.repeat; ++k) {
      Repetition r = RunOnce(o, file, reps.empty() && &file == &o.files.front());
      reps.push_back(r);
      std::printf(
          "%s rep %d: %zu robots, %llu ticks, %.0f robot-steps/s (step %.3f s, %.2f cores busy), "
          "load %.3f s (%.3f CPU s), "
          "peak %.0f B/robot, load growth %.0f B/robot%s, hash %s\n",
          scene.c_str(), k + 1, r.robots, static_cast<unsigned long long>(r.ticks), r.steps_per_s,
          r.step_s, r.step_s > 0 ? r.cpu_s / r.step_s : 0.0, r.load_s, r.load_cpu_s,
          r.bytes_per_robot, r.load_bytes_per_robot, r.peak_reset ? "" : " (hwm not reset)",
          colony::StateHasher::Hex(r.hash).c_str());
      std::fflush(stdout);
    }
    std::vector<double> sps, load, load_cpu, teardown, bpr, lbpr, cpu_ns, worker_start, caller_wait;
    bool same_hash = true;
    for (const auto& r : reps) {
      sps.push_back(r.steps_per_s);
      cpu_ns.push_back(r.steps_per_s > 0 ? 1e9 * r.cpu_s / (r.step_s * r.steps_per_s) : 0.0);
      load.push_back(r.load_s);
      load_cpu.push_back(r.load_cpu_s);
      teardown.push_back(r.teardown_s);
      if (r.peak_reset) bpr.push_back(r.bytes_per_robot);
      lbpr.push_back(r.load_bytes_per_robot);
      worker_start.push_back(r.worker_start_us);
      caller_wait.push_back(r.caller_wait_pct);
      same_hash = same_hash && r.hash == reps.front().hash;
    }
    // Where a tick's time goes: each phase's share, medians over repetitions.
    const char* phases[] = {"act", "physics", "media", "loop_functions", "sense_control"};
    std::vector<double> share[5];
    for (const auto& r : reps) {
      const colony::StepProfile& p = r.profile;
      const double total = std::max(p.total(), 1e-12);
      const double parts[5] = {p.act, p.physics, p.media, p.loop_functions, p.sense_control};
      for (int i = 0; i < 5; ++i) share[i].push_back(100 * parts[i] / total);
    }
    std::printf("%s step profile (median share of step time):", scene.c_str());
    for (int i = 0; i < 5; ++i) std::printf(" %s %.1f%%", phases[i], Median(share[i]));
    std::printf("\n");
    const Repetition& first = reps.front();
    std::printf(
        "%s median of %zu: %.0f robot-steps/s, load %.3f s, peak %.0f B/robot, load growth %.0f "
        "B/robot%s\n",
        scene.c_str(), reps.size(), Median(sps), Median(load), Median(bpr), Median(lbpr),
        same_hash ? "" : " (WARNING: state hashes differ between repetitions)");
    std::printf(
        "RESULT scene=%s robots=%zu threads=%d ticks=%llu steps_per_s_median=%.0f "
        "load_s_median=%.3f load_cpu_s_median=%.3f teardown_s_median=%.3f "
        "bytes_per_robot=%.0f load_bytes_per_robot=%.0f cpu_ns_per_robot_step=%.0f state_hash=%s "
        "act_pct=%.1f physics_pct=%.1f media_pct=%.1f loop_functions_pct=%.1f "
        "sense_control_pct=%.1f worker_start_us=%.2f caller_wait_pct=%.1f\n",
        scene.c_str(), first.robots, first.threads, static_cast<unsigned long long>(first.ticks),
        Median(sps), Median(load), Median(load_cpu), Median(teardown), Median(bpr), Median(lbpr),
        Median(cpu_ns), colony::StateHasher::Hex(first.hash).c_str(), Median(share[0]),
        Median(share[1]), Median(share[2]), Median(share[3]), Median(share[4]),
        Median(worker_start), Median(caller_wait));
    if (o.max_bytes_per_robot > 0 && Median(bpr) > static_cast<double>(o.max_bytes_per_robot)) {
      std::printf("OVER BUDGET %s: %.0f bytes per robot at the peak, more than the %lld allowed\n",
                  scene.c_str(), Median(bpr), o.max_bytes_per_robot);
      status = 1;
    }
    std::fflush(stdout);
  }
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    Options options;
    if (!ParseArgs({argv + 1, argv + argc}, options)) return 0;
    colony::SetLogLevel(colony::LogLevel::kError);
    return Bench(options);
  } catch (const UsageError& e) {
    std::fprintf(stderr, "colony_bench: %s\nrun 'colony_bench --help' for usage\n", e.what());
    return 2;
  } catch (const colony::ConfigError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "colony_bench: %s\n", e.what());
    return 1;
  }
}
