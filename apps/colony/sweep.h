// colony sweep: many runs of one experiment over a grid of parameter values
// and seeds, each run its own `colony run` process, resumable, spread over
// MPI ranks or array-job shards, and summarized over seeds. See
// docs/sweeps.md for the user's side; this header is shared by sweep*.cpp.
//
// A sweep folder DIR holds:
//   sweep.xml         the manifest: experiment (+ content hash), params, seeds
//   runs/NNNN/        one folder per run: the run's output contract, run.log,
//                     and row.csv (its row of results.csv, written atomically
//                     when the run ended; its presence means "finished")
//   results.csv       every finished run's row, in grid order
//   summary.csv       from --summarize
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/text.h"

namespace colony::sweep {

// `colony sweep ...`: returns the exit status (0 ok, 2 bad input, 1 failure).
int SweepCommand(const std::vector<std::string>& args);

// A bad command line or sweep file: exit status 2, nothing run.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// A failure while sweeping (exit status 1).
struct Failure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// ---- The grid (sweep_grid.cpp) -------------------------------------------

struct Param {
  std::string path;  // a --set path
  std::vector<std::string> values;
  bool operator==(const Param&) const = default;
};

// What a sweep is. Runs are numbered in grid order: the first parameter
// varies slowest, the seed fastest.
struct Grid {
  std::string experiment;       // absolute path of the experiment file
  std::string experiment_hash;  // of its content (hex); "" when not known
  std::vector<Param> params;
  std::vector<uint64_t> seeds;
  size_t size() const;
};

struct RunSpec {
  size_t index = 0;
  std::string name;                 // folder under runs/, e.g. "0007"
  std::vector<std::string> values;  // one per param
  uint64_t seed = 0;
};
RunSpec RunAt(const Grid& grid, size_t index);

// One slice of a grid: runs whose index % count == index_in_count.
struct Slice {
  size_t index = 0;  // 0-based
  size_t count = 1;
  bool Holds(size_t run) const { return run % count == index; }
  std::string ToString() const;  // "I/N", 1-based
};

// "V1,V2,..." (or "V1;V2;..." when values hold commas) into values.
std::vector<std::string> ParseValueList(const std::string& what, const std::string& text);
// "PATH=V1,V2,...".
Param ParseParam(const std::string& text);
// "1..30", "1,2,5", "1..3,7".
std::vector<uint64_t> ParseSeeds(const std::string& text);
std::string FormatSeeds(const std::vector<uint64_t>& seeds);
// "I/N" with 1 <= I <= N.
Slice ParseShard(const std::string& text);
// Seconds > 0.
double ParseTimeout(const std::string& text);

// A sweep file (root <sweep>): experiment path relative to the file.
struct SweepFile {
  Grid grid;  // seeds empty when the file names none
  std::optional<double> timeout;
};
// True when `path` is an XML file whose root element is <sweep>.
bool IsSweepFile(const std::string& path);
SweepFile ReadSweepFile(const std::string& path);
// The hex FNV-1a hash of a file's content.
std::string HashFile(const std::string& path);
// Writes DIR/sweep.xml atomically.
void WriteManifest(const std::string& dir, const Grid& grid);
// Reads DIR/sweep.xml; throws UsageError when DIR holds no sweep.
Grid ReadManifest(const std::string& dir);
// Why `found` (DIR/sweep.xml) is not the sweep `wanted`; "" when it is.
std::string GridDifference(const Grid& found, const Grid& wanted);

// ---- Rows and tables (sweep_results.cpp) ---------------------------------

// One row of results.csv: (column, value) in column order.
using Row = std::vector<std::pair<std::string, std::string>>;

std::string CsvLine(const std::vector<std::string>& fields);
std::vector<std::string> ParseCsvLine(const std::string& line);
// Writes `text` to `path` through a temporary file and a rename.
void WriteAtomically(const std::string& path, const std::string& text);

struct RunEnd {
  enum class Status { kOk, kFailed, kTimeout } status = Status::kFailed;
  double wall_seconds = 0;
  std::string detail;  // why it failed; "" when ok
};
const char* StatusName(RunEnd::Status status);

std::string RunDir(const std::string& dir, const RunSpec& run);
// The row of a run that ended: its parameters, seed, status, wall time and
// what its folder holds (summary.json, else the last row of metrics.csv).
Row MakeRow(const Grid& grid, const RunSpec& run, const RunEnd& end, const std::string& run_dir);
void WriteRow(const std::string& run_dir, const Row& row);
std::optional<Row> ReadRow(const std::string& run_dir);
std::string RowStatus(const Row& row);
// The rows of finished runs found under DIR/runs, by run index.
std::vector<std::optional<Row>> ReadRows(const std::string& dir, const Grid& grid);
// Writes DIR/results.csv (atomically) from the rows present, in grid order.
void WriteResults(const std::string& dir, const std::vector<std::optional<Row>>& rows);
// `colony sweep --collect DIR... [--out DEST]`.
int Collect(const std::vector<std::string>& dirs, const std::string& out, bool quiet);

// ---- Running (sweep_runner.cpp) ------------------------------------------

struct RunnerOptions {
  std::string exe;  // the colony program
  std::string dir;  // the sweep folder
  int jobs = 1;
  std::optional<double> timeout;
  std::optional<int> threads;  // passed to each run as --threads
  bool progress = false;       // draw the progress line on standard error
};
struct RunnerTotals {
  size_t ok = 0, failed = 0, timeout = 0;
  bool interrupted = false;
  int signal = 0;  // the one that interrupted
};
// Runs `pending` (indices into the grid), `options.jobs` at a time, calling
// `finished` with each run's row as it ends. `already_done` only counts in
// the progress line. SIGINT/SIGTERM/SIGHUP kill the running runs and return
// with interrupted set.
RunnerTotals RunAll(const Grid& grid, const std::vector<size_t>& pending, size_t already_done,
                    const RunnerOptions& options,
                    const std::function<void(size_t, const Row&)>& finished);

// ---- Summaries (sweep_summary.cpp) ---------------------------------------

// `colony sweep --summarize DIR [--plot METRIC:PARAM]`.
int Summarize(const std::string& dir, const std::string& plot, bool quiet);

}  // namespace colony::sweep
