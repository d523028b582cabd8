// The output contract of one run (other tools rely on it). The run folder
// receives:
//   experiment.xml  the experiment as resolved (overrides applied)
//   metrics.csv     tick, time and the loop functions' metrics, every K ticks
//   hashes.csv      tick and state hash, when <output hash_every> is set
//   frames/         PNG frames, when a renderer draws and no other folder is given
//   summary.json    written last and atomically (synced, then renamed into
//                   place) when the run ended: completed (true only when it
//                   ran to its end), stop_reason (when not), ticks,
//                   simulated_seconds, wall_seconds, step_seconds, robots,
//                   threads, seed, robot_steps_per_second, final_state_hash
//                   (hex), metrics (the last row)
// CSV files hold whole rows only and are written out at least every second,
// so a killed run leaves every row it wrote whole. Every write is checked: a
// failed one (a full disk...) ends the run with a RuntimeFailure naming the
// file and the reason.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/run_files.h"
#include "core/simulation.h"

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
  std::string ToJson() const;
};

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
  // Creates `dir` and writes experiment.xml. Throws RuntimeFailure.
  RunOutput(std::string dir, const Simulation& sim);
  // Records what is due after a tick (metrics row, state hash); everything
  // when the run is done or `last`.
  void AfterTick(Simulation& sim, bool last = false);
  // Writes the rows out, then summary.json (atomically).
  void Finish(const RunSummary& summary);
  const std::string& dir() const { return dir_; }

 private:
  std::string dir_;
  std::unique_ptr<RowFile> metrics_, hashes_;
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
