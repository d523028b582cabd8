// The output contract of one run (other tools rely on it). The run folder
// receives:
//   experiment.xml  the experiment as resolved (overrides applied)
//   metrics.csv     tick, time and the loop functions' metrics, every K ticks
//   hashes.csv      tick and state hash, when <output hash_every> is set
//   frames/         PNG frames, when a renderer draws and no other folder is given
//   summary.json    written last and atomically, only when the run completed:
//                   ticks, simulated_seconds, wall_seconds, step_seconds,
//                   robots, threads, seed, robot_steps_per_second,
//                   final_state_hash (hex), metrics (the last row)
#pragma once

#include <cstdio>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/simulation.h"

namespace colony {

struct RunSummary {
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

// A fresh folder runs/<experiment name>-<date>-<time>[-N] under `root`.
std::string FreshRunDir(const std::string& root, const std::string& experiment_file);

class RunOutput {
 public:
  // Creates `dir` and writes experiment.xml. Throws RuntimeFailure.
  RunOutput(std::string dir, const Simulation& sim);
  ~RunOutput();
  // Records what is due after a tick (metrics row, state hash).
  void AfterTick(Simulation& sim);
  // Writes summary.json (atomically).
  void Finish(const RunSummary& summary);
  const std::string& dir() const { return dir_; }

 private:
  std::string dir_;
  std::FILE* metrics_ = nullptr;
  std::FILE* hashes_ = nullptr;
  bool header_written_ = false;
};

// Steps `sim` until done, recording into `out` (may be null) and calling
// `progress` after every tick (may be empty). `load_seconds` is added to
// wall_seconds.
RunSummary RunToEnd(Simulation& sim, RunOutput* out, double load_seconds,
                    const std::function<void(const Simulation&)>& progress);

}  // namespace colony
