// colony sweep: the command line, checking the grid before anything runs,
// preparing the sweep folder, choosing this process's runs (shard, MPI rank)
// and, when every rank is done, merging results.csv.
#include "apps/colony/sweep.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <thread>

#include "core/error.h"
#include "core/log.h"
#include "core/simulation.h"

namespace colony::sweep {

namespace fs = std::filesystem;

namespace {

constexpr const char* kUsage =
    "usage:\n"
    "  colony sweep FILE.xml [--param PATH=V1,V2,...]... [--seeds 1..30] [--jobs N] [--out DIR]\n"
    "               [--timeout SECONDS] [--retry-failed] [--shard I/N] [--threads T] [--quiet]\n"
    "      FILE.xml: an experiment, or a sweep file (<sweep experiment=\"...\" seeds=\"...\"> "
    "holding\n"
    "      <param path=\"...\" values=\"...\"/>); values holding commas are separated by ';' "
    "instead\n"
    "  colony sweep --collect DIR... [--out DEST]          merge shards' runs into one "
    "results.csv\n"
    "  colony sweep --summarize DIR [--plot METRIC:PARAM]  mean, std dev, median, count over "
    "seeds\n"
    "See docs/sweeps.md.\n";

struct SweepOptions {
  std::string file;
  std::vector<Param> params;
  std::optional<std::vector<uint64_t>> seeds;
  std::optional<int> jobs;
  std::string out;
  std::optional<double> timeout;
  bool retry_failed = false;
  Slice shard;
  std::optional<int> threads;
  bool quiet = false;
};

// Where this process stands in an MPI job (size 1 when not started by mpirun).
struct MpiPlace {
  size_t rank = 0, size = 1, local_size = 1;
  std::string job;  // shared by the ranks of one job
};

int ParseWhole(const std::string& option, const std::string& text, int min, int max) {
  long long v = 0;
  const std::string problem = ParseWholeOption(option, text, min, max, v);
  if (!problem.empty()) throw UsageError(problem);
  return static_cast<int>(v);
}

SweepOptions ParseSweepOptions(const std::vector<std::string>& args) {
  SweepOptions o;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= args.size()) throw UsageError(a + " needs a value");
      return args[++i];
    };
    if (a == "--param") {
      o.params.push_back(ParseParam(value()));
    } else if (a == "--seeds") {
      o.seeds = ParseSeeds(value());
    } else if (a == "--jobs") {
      o.jobs = ParseWhole(a, value(), 1, 4096);
    } else if (a == "--out") {
      o.out = value();
      if (o.out.empty()) throw UsageError("--out needs a folder");
    } else if (a == "--timeout") {
      o.timeout = ParseTimeout(value());
    } else if (a == "--retry-failed") {
      o.retry_failed = true;
    } else if (a == "--shard") {
      o.shard = ParseShard(value());
    } else if (a == "--threads") {
      o.threads = ParseWhole(a, value(), 0, 256);
    } else if (a == "--quiet") {
      o.quiet = true;
    } else if (!a.empty() && a[0] == '-') {
      throw UsageError("unknown option '" + a + "'");
    } else if (o.file.empty()) {
      o.file = a;
    } else {
      throw UsageError("more than one file given ('" + o.file + "' and '" + a + "')");
    }
  }
  if (o.file.empty()) throw UsageError("colony sweep needs an experiment or sweep file");
  return o;
}

// The grid from the file (an experiment or a sweep file) and the command
// line; a --param replaces the sweep file's parameter of the same path.
Grid BuildGrid(SweepOptions& o) {
  Grid grid;
  if (IsSweepFile(o.file)) {
    const SweepFile file = ReadSweepFile(o.file);
    grid = file.grid;
    if (!o.timeout) o.timeout = file.timeout;
  } else {
    grid.experiment = fs::absolute(o.file).lexically_normal().string();
  }
  const std::string hash = HashFile(grid.experiment);
  if (!grid.experiment_hash.empty() && grid.experiment_hash != hash) {
    throw UsageError(o.file + ": experiment_hash does not match " + grid.experiment +
                     " (the file has changed)");
  }
  grid.experiment_hash = hash;
  std::set<std::string> given;
  for (const auto& p : o.params) {
    if (!given.insert(p.path).second) throw UsageError("--param " + p.path + " is given twice");
    auto same = std::find_if(grid.params.begin(), grid.params.end(),
                             [&](const Param& q) { return q.path == p.path; });
    if (same != grid.params.end()) {
      *same = p;
    } else {
      grid.params.push_back(p);
    }
  }
  if (o.seeds) grid.seeds = *o.seeds;
  return grid;
}

// Loads the experiment once per parameter value (the other parameters at
// their first value), so a bad path or value stops the sweep before any run.
// Without seeds, the sweep runs the experiment's own seed.
void CheckGrid(Grid& grid) {
  auto load = [&](const std::vector<std::string>& overrides) {
    ExperimentOptions options;
    options.file = grid.experiment;
    options.overrides = overrides;
    options.threads = 1;
    if (!grid.seeds.empty()) options.seed = grid.seeds.front();
    try {
      return Simulation::Load(options)->seed();
    } catch (const ConfigError&) {
      std::string sets;
      for (const auto& o : overrides) sets += " --set " + o;
      std::fprintf(stderr, "colony sweep: the experiment does not load with%s\n",
                   sets.empty() ? " no overrides" : sets.c_str());
      throw;
    }
  };
  std::vector<std::string> first;
  for (const auto& p : grid.params) first.push_back(p.path + "=" + p.values.front());
  const uint64_t seed = load(first);
  if (grid.seeds.empty()) grid.seeds = {seed};
  for (size_t k = 0; k < grid.params.size(); ++k) {
    for (size_t v = 1; v < grid.params[k].values.size(); ++v) {
      std::vector<std::string> overrides = first;
      overrides[k] = grid.params[k].path + "=" + grid.params[k].values[v];
      load(overrides);
    }
  }
}

MpiPlace DetectMpi() {
  auto number = [](const char* name) -> std::optional<size_t> {
    const char* v = std::getenv(name);
    if (!v || !*v) return std::nullopt;
    char* end = nullptr;
    const unsigned long n = std::strtoul(v, &end, 10);
    return *end == '\0' ? std::optional<size_t>(n) : std::nullopt;
  };
  MpiPlace place;
  for (auto [rank, size] : {std::pair{"OMPI_COMM_WORLD_RANK", "OMPI_COMM_WORLD_SIZE"},
                            std::pair{"PMI_RANK", "PMI_SIZE"}}) {
    const auto r = number(rank), s = number(size);
    if (r && s && *r < *s) {
      place.rank = *r;
      place.size = *s;
      break;
    }
  }
  for (const char* name : {"OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS"}) {
    if (const auto n = number(name); n && *n > 0) {
      place.local_size = *n;
      break;
    }
  }
  // The job's id names its folder of completion marks.
  place.job = "job";
  for (const char* name :
       {"COLONY_SWEEP_JOB", "PMIX_NAMESPACE", "OMPI_MCA_ess_base_jobid", "SLURM_JOB_ID"}) {
    if (const char* v = std::getenv(name); v && *v) {
      place.job = v;
      if (std::string(name) == "SLURM_JOB_ID" && std::getenv("SLURM_STEP_ID")) {
        place.job += std::string(".") + std::getenv("SLURM_STEP_ID");
      }
      break;
    }
  }
  for (char& c : place.job) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-') c = '_';
  }
  return place;
}

// Creates or checks the sweep folder: one holding another sweep, or other
// files, is refused.
void PrepareFolder(const std::string& dir, const Grid& grid) {
  if (fs::exists(fs::path(dir) / "sweep.xml")) {
    const std::string why = GridDifference(ReadManifest(dir), grid);
    if (!why.empty()) {
      throw UsageError(dir + " holds another sweep (" + why + "); choose another --out");
    }
    return;
  }
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    // Another process of the same sweep (a shard, a rank) may be creating it.
    const bool ours = name == "runs" || name == ".mpi" || name.rfind(".lock-", 0) == 0 ||
                      name.rfind("sweep.xml", 0) == 0;
    if (!ours) throw UsageError(dir + " exists and is not a sweep folder; choose another --out");
  }
  fs::create_directories(fs::path(dir) / "runs");
  WriteManifest(dir, grid);
}

// Locks this process's share of the folder until the process ends, so the
// same runs are not run twice at once.
void LockShare(const std::string& dir, const std::string& share) {
  const std::string path = (fs::path(dir) / (".lock-" + share)).string();
  const int fd = open(path.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0 || flock(fd, LOCK_EX | LOCK_NB) != 0) {
    throw Failure("another colony sweep is running the same runs in " + dir + " (" + path +
                  " is locked)");
  }
}

// The runs of this process: its shard, then its rank's part of it.
std::vector<size_t> ShareOf(const Grid& grid, const Slice& shard, const MpiPlace& mpi) {
  std::vector<size_t> share;
  size_t position = 0;
  for (size_t i = 0; i < grid.size(); ++i) {
    if (shard.Holds(i) && position++ % mpi.size == mpi.rank) share.push_back(i);
  }
  return share;
}

std::string ShareName(const Slice& shard, const MpiPlace& mpi) {
  std::string name = shard.count > 1 ? "shard-" + std::to_string(shard.index + 1) + "-of-" +
                                           std::to_string(shard.count)
                                     : "";
  if (mpi.size > 1) {
    name += (name.empty() ? "" : "-") +
            ("rank-" + std::to_string(mpi.rank) + "-of-" + std::to_string(mpi.size));
  }
  return name.empty() ? "all" : name;
}

// Rewrites results.csv as runs finish, at most every second or so (less
// often when the table is long).
class ResultsWriter {
 public:
  ResultsWriter(std::string dir, const std::vector<std::optional<Row>>& rows)
      : dir_(std::move(dir)), rows_(rows) {}
  void Changed() {
    if (std::chrono::steady_clock::now() >= next_) Write();
  }
  void Write() {
    const auto t0 = std::chrono::steady_clock::now();
    WriteResults(dir_, rows_);
    const auto took = std::chrono::steady_clock::now() - t0;
    next_ = std::chrono::steady_clock::now() +
            std::max<std::chrono::steady_clock::duration>(std::chrono::seconds(1), 20 * took);
  }

 private:
  std::string dir_;
  const std::vector<std::optional<Row>>& rows_;
  std::chrono::steady_clock::time_point next_{};
};

fs::path RankMark(const std::string& dir, const MpiPlace& mpi, size_t rank) {
  return fs::path(dir) / ".mpi" / mpi.job / ("rank-" + std::to_string(rank));
}

// Marks this rank done, and on rank 0 waits until every rank is.
void MeetRanks(const std::string& dir, const MpiPlace& mpi) {
  const fs::path marks = RankMark(dir, mpi, 0).parent_path();
  fs::create_directories(marks);
  WriteAtomically(RankMark(dir, mpi, mpi.rank).string(), "done\n");
  if (mpi.rank != 0) return;
  for (size_t r = 0; r < mpi.size;) {
    if (fs::exists(RankMark(dir, mpi, r))) {
      ++r;
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
  }
  fs::remove_all(marks);
  std::error_code ec;
  fs::remove(marks.parent_path(), ec);  // .mpi, when no other job uses it
}

struct Counts {
  size_t ok = 0, failed = 0, timeout = 0, missing = 0;
};
Counts CountRows(const std::vector<std::optional<Row>>& rows, const std::vector<size_t>& share) {
  Counts c;
  for (size_t i : share) {
    const std::string s = rows[i] ? RowStatus(*rows[i]) : "";
    (s == "ok" ? c.ok : s == "timeout" ? c.timeout : s.empty() ? c.missing : c.failed)++;
  }
  return c;
}

// How this process starts its runs.
RunnerOptions MakeRunnerOptions(const SweepOptions& o, const Grid& grid, const MpiPlace& mpi,
                                const std::string& dir) {
  RunnerOptions runner;
  runner.exe = fs::read_symlink("/proc/self/exe").string();
  runner.dir = dir;
  runner.jobs = o.jobs.value_or(
      std::max<int>(1, static_cast<int>(std::thread::hardware_concurrency() / mpi.local_size)));
  runner.timeout = o.timeout;
  // Runs are the parallelism: one thread each, unless the sweep varies it.
  const bool threads_swept =
      std::any_of(grid.params.begin(), grid.params.end(),
                  [](const Param& p) { return p.path == "framework.system.threads"; });
  if (!threads_swept) runner.threads = o.threads.value_or(1);
  runner.progress = !o.quiet && isatty(STDERR_FILENO);
  return runner;
}

std::string Runs(size_t n) { return std::to_string(n) + (n == 1 ? " run" : " runs"); }

// Prints the totals of the sweep (or shard) and returns the exit status.
int Report(const SweepOptions& o, const Grid& grid, const std::vector<std::optional<Row>>& rows,
           const std::string& dir, std::optional<size_t> run_now) {
  const std::vector<size_t> share = ShareOf(grid, o.shard, MpiPlace{});
  const Counts c = CountRows(rows, share);
  if (!o.quiet) {
    const std::string what = o.shard.count > 1 ? "shard " + o.shard.ToString() + ": " : "";
    std::printf("%s%s: %zu ok, %zu failed, %zu timeout", what.c_str(), Runs(share.size()).c_str(),
                c.ok, c.failed, c.timeout);
    if (run_now) std::printf(" (%zu of them run now)", *run_now);
    std::printf("\n");
    if (o.shard.count > 1) {
      std::printf("when every shard is done: colony sweep --collect %s\n", dir.c_str());
    } else {
      std::printf("results in %s/results.csv\n", dir.c_str());
    }
    if (c.failed + c.timeout > 0) {
      std::printf("--retry-failed runs the failed ones again (logs: runs/*/run.log)\n");
    }
  }
  return c.ok == share.size() ? 0 : 1;
}

int RunSweep(const std::vector<std::string>& args) {
  SweepOptions o = ParseSweepOptions(args);
  if (o.quiet) SetLogLevel(LogLevel::kError);
  Grid grid = BuildGrid(o);
  CheckGrid(grid);
  const MpiPlace mpi = DetectMpi();
  const std::string dir = o.out.empty() ? "sweeps/" + fs::path(o.file).stem().string() : o.out;
  PrepareFolder(dir, grid);
  LockShare(dir, ShareName(o.shard, mpi));
  fs::remove(RankMark(dir, mpi, mpi.rank));  // a mark left by an interrupted job

  // What is left to run of this process's share.
  const std::vector<size_t> share = ShareOf(grid, o.shard, mpi);
  std::vector<std::optional<Row>> rows = ReadRows(dir, grid);
  std::vector<size_t> pending;
  for (size_t i : share) {
    if (!rows[i] || (o.retry_failed && RowStatus(*rows[i]) != "ok")) pending.push_back(i);
  }

  // Only a process running the whole grid keeps results.csv up to date as it goes.
  const bool whole = o.shard.count == 1 && mpi.size == 1;
  ResultsWriter results(dir, rows);
  const RunnerTotals t =
      RunAll(grid, pending, share.size() - pending.size(), MakeRunnerOptions(o, grid, mpi, dir),
             [&](size_t i, const Row& row) {
               rows[i] = row;
               if (whole) results.Changed();
             });
  if (whole) results.Write();
  const size_t run_now = t.ok + t.failed + t.timeout;
  if (t.interrupted) {
    std::fprintf(stderr,
                 "colony sweep: interrupted; %zu of %s have finished; run the same command again "
                 "to finish\n",
                 share.size() - pending.size() + run_now, Runs(share.size()).c_str());
    return 128 + t.signal;
  }
  if (mpi.size == 1) return Report(o, grid, rows, dir, run_now);

  // Under MPI, rank 0 merges once every rank is done; the others end here.
  MeetRanks(dir, mpi);
  if (mpi.rank != 0) return 0;
  rows = ReadRows(dir, grid);
  if (o.shard.count == 1) WriteResults(dir, rows);
  return Report(o, grid, rows, dir, std::nullopt);
}

int CollectCommand(const std::vector<std::string>& args) {
  std::vector<std::string> dirs;
  std::string out;
  bool quiet = false;
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--collect") continue;
    if (args[i] == "--out") {
      if (i + 1 >= args.size() || args[i + 1].empty()) throw UsageError("--out needs a folder");
      out = args[++i];
    } else if (args[i] == "--quiet") {
      quiet = true;
    } else if (!args[i].empty() && args[i][0] == '-') {
      throw UsageError("'" + args[i] +
                       "' does not go with --collect (which takes DIR... [--out DEST])");
    } else {
      dirs.push_back(args[i]);
    }
  }
  if (dirs.empty()) throw UsageError("--collect needs the sweep folder(s) to merge");
  return Collect(dirs, out, quiet);
}

int SummarizeCommand(const std::vector<std::string>& args) {
  std::string dir, plot;
  bool quiet = false;
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--summarize") continue;
    if (args[i] == "--plot") {
      if (i + 1 >= args.size()) {
        throw UsageError(
            "--plot needs METRIC:PARAM, e.g. mean_displacement:arena.distribute.entity.quantity");
      }
      plot = args[++i];
    } else if (args[i] == "--quiet") {
      quiet = true;
    } else if ((!args[i].empty() && args[i][0] == '-') || !dir.empty()) {
      throw UsageError("'" + args[i] +
                       "' does not go with --summarize (which takes DIR [--plot METRIC:PARAM])");
    } else {
      dir = args[i];
    }
  }
  if (dir.empty()) throw UsageError("--summarize needs a sweep folder");
  return Summarize(dir, plot, quiet);
}

}  // namespace

int SweepCommand(const std::vector<std::string>& args) {
  try {
    if (!args.empty() && (args[0] == "--help" || args[0] == "-h" || args[0] == "help")) {
      std::fputs(kUsage, stdout);
      return 0;
    }
    const bool collect = std::find(args.begin(), args.end(), "--collect") != args.end();
    const bool summarize = std::find(args.begin(), args.end(), "--summarize") != args.end();
    if (collect && summarize) throw UsageError("--collect and --summarize are separate commands");
    if (collect) return CollectCommand(args);
    if (summarize) return SummarizeCommand(args);
    return RunSweep(args);
  } catch (const UsageError& e) {
    std::fprintf(stderr, "colony sweep: %s\n%s", e.what(), kUsage);
    return 2;
  } catch (const Failure& e) {
    std::fprintf(stderr, "colony sweep: %s\n", e.what());
    return 1;
  }
}

}  // namespace colony::sweep
