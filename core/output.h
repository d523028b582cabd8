// The output contract of one run (other tools rely on it; docs/data-output.md
// describes it for users). The run folder receives:
//   experiment.xml  the experiment as resolved, so that `colony run
//                   RUN/experiment.xml` reproduces the run from any folder:
//                   overrides applied, the effective seed as random_seed,
//                   relative library= paths and other relative file names
//                   made absolute (ReproducibleXml)
//   metrics.csv     tick, time and the loop functions' metrics, every K
//                   ticks from tick 0 (RFC 4180 CSV)
//   hashes.csv      tick and state hash, every <output hash_every> ticks
//                   from tick 0
//   trajectories.csv / .csv.gz / .h5
//                   every robot's pose and values, every <output
//                   trajectories_every> ticks from tick 0 (core/trajectories.h)
//   frames/         PNG frames, when a renderer draws and no other folder is given
//   summary.json    written last and atomically (synced, then renamed into
//                   place) when the run ended: completed (true only when it
//                   ran to its end), stop_reason (when not), ticks,
//                   simulated_seconds, wall_seconds, step_seconds, robots,
//                   threads, seed, robot_steps_per_second, final_state_hash
//                   (hex), metrics (the last row), and its provenance:
//                   colony_version, git_revision, command_line,
//                   plugin_libraries (path, sha256), start_time, end_time
//                   (ISO 8601, UTC), host
// plus the tables loop functions write there (core/table_writer.h).
// CSV files hold whole rows only and are written out at least every second,
// so a killed run leaves every row it wrote whole. Every write is checked: a
// failed one (a full disk...) ends the run with a RuntimeFailure naming the
// file and the reason.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/run_files.h"
#include "core/simulation.h"
#include "core/trajectories.h"

namespace colony {

struct RunSummary {
  bool completed = true;    // ran to its end (length reached or loop functions ended it)
  std::string stop_reason;  // why not, when not completed
  uint64_t ticks = 0;
  double simulated_seconds = 0;
  double wall_seconds = 0;  // the whole run, loading included
  double step_seconds = 0;  // stepping only
  size_t robots = 0;
  int threads = 0;
  uint64_t seed = 0;
  double robot_steps_per_second = 0;  // robots x ticks / step_seconds
  uint64_t final_state_hash = 0;
  std::vector<std::pair<std::string, double>> metrics;
  // Provenance: what ran, how, where and when.
  std::string colony_version;             // ColonyVersion()
  std::string git_revision;               // ColonyGitRevision()
  std::vector<std::string> command_line;  // the program's arguments, as given (argv)
  struct Library {
    std::string path;    // absolute
    std::string sha256;  // of its content when it was loaded ("" if unreadable)
  };
  std::vector<Library> plugin_libraries;  // every plugin library loaded, once each
  std::string start_time, end_time;       // ISO 8601 UTC: loading began, the run ended
  std::string host;                       // the machine's host name
  std::string ToJson() const;
};

// Colony's version ("0.1.0"), and the git revision of the checkout it was
// built from (read when the build was configured; "unknown" when it was not
// built from a git checkout).
const char* ColonyVersion();
const char* ColonyGitRevision();

// This process's command line (/proc/self/cmdline), one word per argument.
std::vector<std::string> ProcessCommandLine();

// The experiment `sim` runs as XML that reproduces it from any folder:
// Simulation::ResolvedXml (overrides applied) with the effective seed as
// <experiment random_seed>, library= paths made absolute as the loader
// found them (a bare name, looked up in the plugin search path, stays), and
// every other attribute naming an existing file by a relative path (a floor
// image, a Lua script, a mesh: beside the experiment file, else from the
// current folder) made absolute. "" for a simulation without a document.
std::string ReproducibleXml(const Simulation& sim);

// The keys summary.json always has; a file without them all, or whose
// "completed" is not true, is not a finished run. Returns "" when `json_text`
// is a finished run's summary, else what is wrong with it.
std::string SummaryProblem(const std::string& json_text);

// A fresh folder runs/<experiment name>-<date>-<time>[-N] under `root`.
std::string FreshRunDir(const std::string& root, const std::string& experiment_file);

// Makes `dir` ready to receive `what` ("--out", "--frames"): created if
// missing. A folder that is not empty is refused (UsageError-like
// RuntimeFailure naming it and what it holds) unless `overwrite`; then the
// files a run writes there (`run_files`: names, or "*.png") are removed first
// and anything else is left alone.
void PrepareOutputFolder(const std::string& dir, const std::string& what, bool overwrite,
                         const std::vector<std::string>& run_files);
// The names PrepareOutputFolder clears in a run folder.
const std::vector<std::string>& RunFolderFiles();

// Thrown by PrepareOutputFolder for a folder in use (bad command line: exit 2).
class OutputFolderInUse : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class RunOutput {
 public:
  // Creates `dir`, writes experiment.xml (ReproducibleXml) and the rows of
  // the state `sim` is in (tick 0): metrics, state hash, trajectories.
  // Throws RuntimeFailure, or ConfigError for per-robot values that cannot
  // be columns (core/trajectories.h).
  RunOutput(std::string dir, Simulation& sim);
  ~RunOutput();
  // Records what is due after a tick (metrics row, state hash,
  // trajectories); everything when the run is done or `last`.
  void AfterTick(Simulation& sim, bool last = false);
  // Writes the rows out, then summary.json (atomically), with the command
  // line set here if any.
  void Finish(const RunSummary& summary);
  // The command line summary.json records (default: ProcessCommandLine()).
  void set_command_line(std::vector<std::string> words) { command_line_ = std::move(words); }
  const std::string& dir() const { return dir_; }

 private:
  // Writes the rows due at the current tick (`all`: every kind).
  void Record(Simulation& sim, bool all);

  std::string dir_;
  std::unique_ptr<RowFile> metrics_, hashes_;
  std::unique_ptr<Trajectories> trajectories_;
  std::optional<std::vector<std::string>> command_line_;
  std::string row_;  // reused for every row
  bool header_written_ = false;
};

// Steps `sim` until done, recording into `out` (may be null) and calling
// `progress` after every tick (may be empty). `load_seconds` is added to
// wall_seconds. An interrupt (see core/crash_report.h) stops it after the
// current tick: the summary then says completed = false. When a tick
// throws, the summary (completed = false, the error as stop_reason) is
// written if it can be, and the error is rethrown.
RunSummary RunToEnd(Simulation& sim, RunOutput* out, double load_seconds,
                    const std::function<void(const Simulation&)>& progress);

}  // namespace colony
