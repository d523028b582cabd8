// colony sweep: the command line (CLI11: apps/colony/command_line.h),
// checking the grid before anything runs, preparing the sweep folder
// (extending a sweep, refusing runs made with other code), choosing this
// process's runs (shard, MPI rank) and, when every rank is done, merging
// results.csv.
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

#include "apps/colony/command_line.h"
#include "core/error.h"
#include "core/log.h"
#include "core/simulation.h"

namespace colony::sweep {

namespace fs = std::filesystem;

namespace {

struct SweepOptions {
  std::string file;
  std::vector<Param> params;
  std::optional<std::vector<uint64_t>> seeds;
  std::optional<int> jobs;
  std::string out;
  std::optional<double> timeout;
  bool retry_failed = false;
  bool rerun_stale = false, keep_stale = false;
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

// Parses `args` into `app` (CLI11); false when --help was given (and
// printed).
bool ParseCommandLine(CLI::App& app, const std::vector<std::string>& args) {
  try {
    return cli::Parse(app, args);
  } catch (const cli::UsageError& e) {
    throw UsageError(e.what());
  }
}

// The modes' help pages name each other.
constexpr const char* kModes =
    "Other modes:\n"
    "  colony sweep --collect DIR... [--out DEST]          merge shards' runs into one "
    "results.csv\n"
    "  colony sweep --summarize DIR [--plot METRIC:PARAM]  statistics over seeds, per tick too\n"
    "each with its own --help. See docs/sweeps.md.";

// `colony sweep FILE.xml ...`: false after --help.
bool ParseSweepOptions(const std::vector<std::string>& args, SweepOptions& o) {
  CLI::App app{
      "many runs of an experiment over parameter values and seeds, resumable and extendable",
      "colony sweep"};
  cli::SetUpHelp(app);
  app.allow_extras();
  app.add_option("FILE.xml", o.file,
                 "an experiment, or a sweep file: <sweep experiment=\"...\" seeds=\"...\"> "
                 "holding <param path=\"...\" values=\"...\"/>");
  std::vector<std::string> params;
  cli::AddListOption(app, "--param", params,
                     "a swept parameter: a --set path and its values (separated by ';' when "
                     "they hold commas); repeatable")
      ->type_name("PATH=V1,V2,...");
  std::string seeds, jobs, timeout, shard, threads;
  app.add_option("--seeds", seeds, "seeds: 1..30, 1,2,5 or 1..3,7 (default: the experiment's)")
      ->type_name("LIST");
  app.add_option("--jobs", jobs, "runs at a time (default: the number of cores)")->type_name("N");
  app.add_option("--out", o.out, "the sweep folder (default: sweeps/<file name>)")
      ->type_name("DIR");
  app.add_option("--timeout", timeout, "stop a run after this long (then SIGKILL 2 s later)")
      ->type_name("SECONDS");
  app.add_flag("--retry-failed", o.retry_failed, "run the failed and timed-out runs again too");
  auto* rerun = app.add_flag("--rerun-stale", o.rerun_stale,
                             "run again the runs made with other code (a rebuilt plugin, "
                             "another Colony) than the sweep's now");
  app.add_flag("--keep-stale", o.keep_stale,
               "keep the runs made with other code; results.csv marks them stale")
      ->excludes(rerun);
  app.add_option("--shard", shard, "run only the I-th of N slices (array jobs)")->type_name("I/N");
  app.add_option("--threads", threads, "threads of each run (default 1)")->type_name("T");
  app.add_flag("--quiet", o.quiet, "print nothing but errors");
  // Listed so that a mistyped mode gets a suggestion; SweepCommand picks the mode.
  app.add_flag("--collect")
      ->description("merge shards' runs into one results.csv ('--collect --help')");
  app.add_flag("--summarize")->description("statistics over seeds ('--summarize --help')");
  app.footer(std::string("Exit status: 0 every run ok, 1 some run failed or timed out, 2 bad "
                         "input, 128 + N after signal N.\n") +
             kModes);
  if (!ParseCommandLine(app, args)) return false;
  if (!app.remaining().empty()) {
    throw UsageError("more than one file given ('" + o.file + "' and '" + app.remaining()[0] +
                     "')");
  }
  if (o.file.empty()) throw UsageError("colony sweep needs an experiment or sweep file");
  // The values, checked once CLI11 has sorted them out; each message names its option.
  for (const auto& p : params) o.params.push_back(ParseParam(p));
  if (app.count("--seeds")) o.seeds = ParseSeeds(seeds);
  if (app.count("--jobs")) o.jobs = ParseWhole("--jobs", jobs, 1, 4096);
  if (app.count("--out") && o.out.empty()) throw UsageError("--out needs a folder");
  if (app.count("--timeout")) o.timeout = ParseTimeout(timeout);
  if (app.count("--shard")) o.shard = ParseShard(shard);
  if (app.count("--threads")) o.threads = ParseWhole("--threads", threads, 0, 256);
  return true;
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

std::string Runs(size_t n) { return std::to_string(n) + (n == 1 ? " run" : " runs"); }

// Creates the sweep folder, or checks that it holds this sweep (perhaps
// with other values or seeds) and returns its manifest. A folder holding
// another sweep, an older sweep's layout, or other files is refused.
std::optional<Manifest> PrepareFolder(const std::string& dir, const Grid& grid, const Code& code) {
  if (fs::exists(fs::path(dir) / "sweep.xml")) {
    Manifest found = ReadManifest(dir);
    if (found.grid.run_folders == RunFolders::kNumbered) {
      throw UsageError(dir +
                       " was made by an older colony sweep, which numbered its run folders and "
                       "did not record the code its runs were made with: --collect and "
                       "--summarize read it, but it cannot be resumed; choose another --out");
    }
    const std::string why = GridDifference(found.grid, grid);
    if (!why.empty()) {
      throw UsageError(dir + " holds another sweep (" + why + "); choose another --out");
    }
    return found;
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
  WriteManifest(dir, {grid, code});
  return std::nullopt;
}

// The finished runs of the grid made with other code than `code`.
std::vector<size_t> StaleRuns(const std::vector<std::optional<Row>>& rows,
                              const std::string& code) {
  std::vector<size_t> stale;
  for (size_t i = 0; i < rows.size(); ++i) {
    if (rows[i] && RowValue(*rows[i], "code") != code) stale.push_back(i);
  }
  return stale;
}

// On resuming: refuses (UsageError) when the code has changed since the
// manifest was written and finished runs were made with the old one, unless
// --rerun-stale or --keep-stale says what to do with them.
void CheckCode(const std::string& dir, const Manifest& found, const Code& code, size_t stale,
               const SweepOptions& o) {
  if (stale == 0 || (found.code && *found.code == code)) return;
  if (o.rerun_stale || o.keep_stale) {
    if (!o.quiet) {
      std::printf("%s %s made with other code than now (%s)\n",
                  o.rerun_stale ? "running again" : "keeping", Runs(stale).c_str(),
                  o.rerun_stale ? "--rerun-stale" : "--keep-stale: stale=true in results.csv");
    }
    return;
  }
  std::string changes;
  if (found.code) {
    for (const auto& c : CodeChanges(*found.code, code)) changes += "\n  " + c;
  }
  if (changes.empty()) changes = "\n  (its runs were made with other code than the manifest's)";
  throw UsageError(dir + ": the code has changed since its runs were made:" + changes + "\n" +
                   Runs(stale) + (stale == 1 ? " was" : " were") +
                   " made with the old code: give --rerun-stale to run them again, or "
                   "--keep-stale to keep them (results.csv marks them stale)");
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
  ResultsWriter(std::string dir, const std::vector<std::optional<Row>>& rows, std::string code)
      : dir_(std::move(dir)), rows_(rows), code_(std::move(code)) {}
  void Changed() {
    if (std::chrono::steady_clock::now() >= next_) Write();
  }
  void Write() {
    const auto t0 = std::chrono::steady_clock::now();
    WriteResults(dir_, rows_, code_);
    const auto took = std::chrono::steady_clock::now() - t0;
    next_ = std::chrono::steady_clock::now() +
            std::max<std::chrono::steady_clock::duration>(std::chrono::seconds(1), 20 * took);
  }

 private:
  std::string dir_;
  const std::vector<std::optional<Row>>& rows_;
  std::string code_;
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
                                const std::string& dir, const std::string& code) {
  RunnerOptions runner;
  runner.exe = fs::read_symlink("/proc/self/exe").string();
  runner.dir = dir;
  runner.code = code;
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

// Prints the totals of the sweep (or shard) and returns the exit status.
int Report(const SweepOptions& o, const Grid& grid, const std::vector<std::optional<Row>>& rows,
           const std::string& dir, const std::string& code, std::optional<size_t> run_now) {
  const std::vector<size_t> share = ShareOf(grid, o.shard, MpiPlace{});
  const Counts c = CountRows(rows, share);
  if (!o.quiet) {
    const std::string what = o.shard.count > 1 ? "shard " + o.shard.ToString() + ": " : "";
    std::printf("%s%s: %zu ok, %zu failed, %zu timeout", what.c_str(), Runs(share.size()).c_str(),
                c.ok, c.failed, c.timeout);
    if (run_now) std::printf(" (%zu of them run now)", *run_now);
    std::printf("\n");
    size_t stale = 0;
    for (size_t i : share) stale += rows[i] && RowValue(*rows[i], "code") != code;
    if (stale > 0) {
      std::printf(
          "%s made with other code than now (stale=true in results.csv; --rerun-stale "
          "runs them again)\n",
          Runs(stale).c_str());
    }
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
  SweepOptions o;
  if (!ParseSweepOptions(args, o)) return 0;
  if (o.quiet) SetLogLevel(LogLevel::kError);
  Grid grid = BuildGrid(o);
  CheckGrid(grid);
  // The experiment is loaded: its plugin libraries are known.
  const Code code = CurrentCode();
  const std::string fingerprint = code.Fingerprint();
  const MpiPlace mpi = DetectMpi();
  const std::string dir = o.out.empty() ? "sweeps/" + fs::path(o.file).stem().string() : o.out;
  const std::optional<Manifest> found = PrepareFolder(dir, grid, code);
  LockShare(dir, ShareName(o.shard, mpi));
  fs::remove(RankMark(dir, mpi, mpi.rank));  // a mark left by an interrupted job

  // A sweep resumed: runs made with other code are refused, rerun or kept;
  // other values or seeds extend it (finished runs keep their folders).
  std::vector<std::optional<Row>> rows = ReadRows(dir, grid);
  const std::vector<size_t> stale = StaleRuns(rows, fingerprint);
  if (found) {
    CheckCode(dir, *found, code, stale.size(), o);
    const std::string change = GridChange(found->grid, grid);
    if (!change.empty() && !o.quiet) {
      size_t reused = 0;
      for (const auto& row : rows) reused += row.has_value();
      std::printf("%s: %s (%s of the sweep reused)\n", dir.c_str(), change.c_str(),
                  Runs(reused).c_str());
    }
    if (!change.empty() || !found->code || !(*found->code == code))
      WriteManifest(dir, {grid, code});
  }

  // What is left to run of this process's share.
  const std::vector<size_t> share = ShareOf(grid, o.shard, mpi);
  std::vector<size_t> pending;
  for (size_t i : share) {
    const bool old_code = std::binary_search(stale.begin(), stale.end(), i);
    if (!rows[i] || (o.retry_failed && RowStatus(*rows[i]) != "ok") ||
        (o.rerun_stale && old_code)) {
      pending.push_back(i);
    }
  }

  // Only a process running the whole grid keeps results.csv up to date as it goes.
  const bool whole = o.shard.count == 1 && mpi.size == 1;
  ResultsWriter results(dir, rows, fingerprint);
  const RunnerTotals t =
      RunAll(grid, pending, share.size() - pending.size(),
             MakeRunnerOptions(o, grid, mpi, dir, fingerprint), [&](size_t i, const Row& row) {
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
  if (mpi.size == 1) return Report(o, grid, rows, dir, fingerprint, run_now);

  // Under MPI, rank 0 merges once every rank is done; the others end here.
  MeetRanks(dir, mpi);
  if (mpi.rank != 0) return 0;
  rows = ReadRows(dir, grid);
  if (o.shard.count == 1) WriteResults(dir, rows, fingerprint);
  return Report(o, grid, rows, dir, fingerprint, std::nullopt);
}

// `colony sweep --collect DIR... [--out DEST]`.
int CollectCommand(const std::vector<std::string>& args) {
  CLI::App app{"merges the runs of a sweep's shards into one results.csv",
               "colony sweep --collect"};
  cli::SetUpHelp(app);
  app.allow_extras();
  app.add_flag("--collect")->description("this mode")->required();
  std::vector<std::string> dirs;
  std::string out;
  bool quiet = false;
  app.add_option("DIR", dirs,
                 "the sweep folders (array-job tasks, MPI ranks, or folders copied back from "
                 "nodes); every one must hold the same sweep");
  app.add_option("--out", out, "where results.csv goes (default: the first DIR)")
      ->type_name("DEST");
  app.add_flag("--quiet", quiet, "print nothing but errors");
  app.footer(std::string("Exit status 1, naming them, when some runs have not finished.\n") +
             kModes);
  if (!ParseCommandLine(app, args)) return 0;
  if (app.count("--out") && out.empty()) throw UsageError("--out needs a folder");
  if (dirs.empty()) throw UsageError("--collect needs the sweep folder(s) to merge");
  return Collect(dirs, out, quiet);
}

// `colony sweep --summarize DIR [--plot METRIC:PARAM]`.
int SummarizeCommand(const std::vector<std::string>& args) {
  CLI::App app{"statistics of a sweep over its seeds: summary.csv and summary_timeseries.csv",
               "colony sweep --summarize"};
  cli::SetUpHelp(app);
  app.allow_extras();
  app.add_flag("--summarize")->description("this mode")->required();
  std::string dir, plot;
  bool quiet = false;
  app.add_option("DIR", dir,
                 "the sweep folder: per parameter combination, count, mean, standard deviation, "
                 "median, min and max of every numeric column of results.csv go to "
                 "DIR/summary.csv (and are printed); per tick, the mean, standard deviation and "
                 "quantiles of every metric of the runs' metrics.csv to "
                 "DIR/summary_timeseries.csv");
  app.add_option("--plot", plot,
                 "also draw METRIC's mean against PARAM into DIR/plot-METRIC-PARAM.png "
                 "(gnuplot; 'colony plot' draws more)")
      ->type_name("METRIC:PARAM");
  app.add_flag("--quiet", quiet, "print nothing but errors");
  app.footer(kModes);
  if (!ParseCommandLine(app, args)) return 0;
  if (!app.remaining().empty()) {
    throw UsageError("--summarize takes one sweep folder, not also '" + app.remaining()[0] + "'");
  }
  if (dir.empty()) throw UsageError("--summarize needs a sweep folder");
  if (app.count("--plot") && plot.empty()) {
    throw UsageError(
        "--plot needs METRIC:PARAM, e.g. mean_displacement:arena.distribute.entity.quantity");
  }
  return Summarize(dir, plot, quiet);
}

}  // namespace

int SweepCommand(const std::vector<std::string>& args) {
  // The mode, for the help hint of an error.
  const bool collect = std::find(args.begin(), args.end(), "--collect") != args.end();
  const bool summarize = std::find(args.begin(), args.end(), "--summarize") != args.end();
  const std::string command = std::string("colony sweep") + (collect     ? " --collect"
                                                             : summarize ? " --summarize"
                                                                         : "");
  try {
    if (!args.empty() && args[0] == "help") return SweepCommand({"--help"});
    if (collect && summarize) throw UsageError("--collect and --summarize are separate modes");
    if (collect) return CollectCommand(args);
    if (summarize) return SummarizeCommand(args);
    return RunSweep(args);
  } catch (const UsageError& e) {
    std::fprintf(stderr, "colony sweep: %s\nrun '%s --help' for usage\n", e.what(),
                 command.c_str());
    return 2;
  } catch (const Failure& e) {
    std::fprintf(stderr, "colony sweep: %s\n", e.what());
    return 1;
  }
}

}  // namespace colony::sweep
