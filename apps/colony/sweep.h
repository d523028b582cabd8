// colony sweep: many runs of one experiment over a grid of parameter values
// and seeds, each run its own `colony run` process, resumable, spread over
// MPI ranks or array-job shards, and summarized over seeds; and colony plot,
// which draws what runs and sweeps wrote. See docs/sweeps.md for the user's
// side; this header is shared by sweep*.cpp and plot.cpp.
//
// A sweep folder DIR holds:
//   sweep.xml         the manifest: experiment (+ content hash), params,
//                     seeds, and the code the runs are made with (Colony's
//                     version, the program, libcolony and the plugin
//                     libraries, with their SHA-256)
//   runs/NAME/        one folder per run, named after its parameter values
//                     and seed (RunName): the run's output contract, run.log,
//                     and row.csv (its row of results.csv, written atomically
//                     when the run ended; its presence means "finished")
//   results.csv       every finished run's row, in grid order
//   summary.csv       from --summarize, and summary_timeseries.csv
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
// `colony plot ...` (plot.cpp): a metric's time series, or a final value
// against a parameter, drawn as PNG with gnuplot. Same exit statuses.
int PlotCommand(const std::vector<std::string>& args);

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

// How a sweep folder names its runs' folders.
enum class RunFolders {
  kByValues,  // RunName: from the parameter values and the seed
  kNumbered,  // by position in the grid, "0007" (sweeps made before run
              // folders were named by values; read, not resumed)
};

// What a sweep is. Runs are numbered in grid order: the first parameter
// varies slowest, the seed fastest.
struct Grid {
  std::string experiment;       // absolute path of the experiment file
  std::string experiment_hash;  // of its content (hex); "" when not known
  std::vector<Param> params;
  std::vector<uint64_t> seeds;
  RunFolders run_folders = RunFolders::kByValues;
  size_t size() const;
};

struct RunSpec {
  size_t index = 0;
  std::string name;                 // folder under runs/, e.g. "quantity=10_seed=3"
  std::vector<std::string> values;  // one per param
  uint64_t seed = 0;
};
RunSpec RunAt(const Grid& grid, size_t index);
// The folder name of the run with these values (one per param) and seed:
// "SHORT=VALUE_..._seed=S", SHORT the last word of the parameter's path
// ("quantity" for arena.distribute.entity.quantity), VALUE with every
// character other than letters, digits, '.', '+' and '-' written %XX (so
// "_" separates the parts, and two runs never share a name); a name longer
// than 200 characters is cut and ends with a hash of the whole.
std::string RunName(const Grid& grid, const std::vector<std::string>& values, uint64_t seed);

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

// ---- The code runs are made with (sweep_code.cpp) ------------------------

// What makes a run's results besides its experiment, parameters and seed:
// Colony's version and the content of the program, of libcolony and of every
// plugin library the experiment loads (by library= or by name from the
// plugin search path). A sweep records it in its manifest and each run's
// fingerprint in its row, so that a resumed sweep notices a rebuilt plugin.
struct Code {
  struct File {
    std::string path;    // absolute
    std::string sha256;  // of its content
    bool operator==(const File&) const = default;
  };
  std::string colony_version;
  std::vector<File> files;  // sorted by path
  // 16 hex digits over the version and the files' names and hashes (not
  // their folders: a build moved elsewhere is the same code).
  std::string Fingerprint() const;
  bool operator==(const Code&) const = default;
};
// The code of this process: the running program, libcolony, and every plugin
// library loaded so far (call after loading the experiment).
Code CurrentCode();
// What changed from `then` to `now`, one line per file or version:
// "/x/libdiffusion.so has changed (SHA-256 1a2b3c4d... then, 5e6f7a8b...
// now)", "... is no longer loaded", "... is newly loaded",
// "Colony's version: 0.1.0 then, 0.2.0 now".
std::vector<std::string> CodeChanges(const Code& then, const Code& now);

// ---- Sweep files and the manifest (sweep_grid.cpp) -----------------------

// A sweep file (root <sweep>): experiment path relative to the file.
struct SweepFile {
  Grid grid;  // seeds empty when the file names none
  std::optional<double> timeout;
  std::optional<Code> code;  // a manifest's <code> (ignored in a sweep file)
};
// True when `path` is an XML file whose root element is <sweep>.
bool IsSweepFile(const std::string& path);
SweepFile ReadSweepFile(const std::string& path);
// The hex FNV-1a hash of a file's content, and of a text.
std::string HashFile(const std::string& path);
std::string HashText(const std::string& text);

// DIR/sweep.xml: the grid and the code its runs are made with.
struct Manifest {
  Grid grid;
  std::optional<Code> code;  // none in manifests of older sweeps
};
// Writes DIR/sweep.xml atomically.
void WriteManifest(const std::string& dir, const Manifest& manifest);
// Reads DIR/sweep.xml; throws UsageError when DIR holds no sweep.
Manifest ReadManifest(const std::string& dir);
// Why `found` (DIR/sweep.xml) is another sweep than `wanted` (another
// experiment, its content changed, other parameter paths); "" when it is the
// same sweep, perhaps with other values or seeds (GridChange).
std::string GridDifference(const Grid& found, const Grid& wanted);
// The values and seeds `wanted` adds to or drops from `found`, e.g. "seeds
// 1..2 -> 1..4"; "" when the grids are the same.
std::string GridChange(const Grid& found, const Grid& wanted);

// ---- CSV, rows and tables (sweep_results.cpp) ----------------------------

// CSV as RFC 4180 has it: fields holding a comma, a quote, CR or LF are
// quoted, their quotes doubled; a quoted field may span lines.
std::string CsvLine(const std::vector<std::string>& fields);
struct CsvTable {
  std::vector<std::vector<std::string>> records;  // the header first
  // The line where a last record cut short begins (no line end after it, or
  // a quote never closed: a killed writer's last row), which is left out of
  // `records`; 0 when the text ends with a whole record.
  size_t cut_line = 0;
};
// Parses CSV text. Throws UsageError naming `what` (the file) and the line
// of a character after a closing quote.
CsvTable ParseCsv(const std::string& text, const std::string& what);
// Reads and parses a CSV file; throws UsageError naming it when it cannot be
// read.
CsvTable ReadCsvFile(const std::string& path);
// Writes `text` to `path` through a temporary file and a rename.
void WriteAtomically(const std::string& path, const std::string& text);
std::string ReadText(const std::string& path);

// One row of results.csv: (column, value) in column order.
using Row = std::vector<std::pair<std::string, std::string>>;

struct RunEnd {
  enum class Status { kOk, kFailed, kTimeout } status = Status::kFailed;
  double wall_seconds = 0;
  std::string detail;  // why it failed; "" when ok
};
const char* StatusName(RunEnd::Status status);

std::string RunDir(const std::string& dir, const RunSpec& run);
// The row of a run that ended: its parameters, seed, status, wall time, what
// its folder holds (summary.json, else the last row of metrics.csv) and the
// fingerprint of the code that made it (`code`).
Row MakeRow(const Grid& grid, const RunSpec& run, const RunEnd& end, const std::string& run_dir,
            const std::string& code);
void WriteRow(const std::string& run_dir, const Row& row);
std::optional<Row> ReadRow(const std::string& run_dir);
// The value of `column` in `row`, "" when it has none.
std::string RowValue(const Row& row, const std::string& column);
std::string RowStatus(const Row& row);
// The rows of finished runs found under DIR/runs, by run index.
std::vector<std::optional<Row>> ReadRows(const std::string& dir, const Grid& grid);
// Writes DIR/results.csv (atomically) from the rows present, in grid order,
// with a `stale` column: "true" for a row whose code is not `code` (the
// fingerprint the manifest records), "" when either is unknown.
void WriteResults(const std::string& dir, const std::vector<std::optional<Row>>& rows,
                  const std::string& code);
// `colony sweep --collect DIR... [--out DEST]`.
int Collect(const std::vector<std::string>& dirs, const std::string& out, bool quiet);

// ---- Running (sweep_runner.cpp) ------------------------------------------

struct RunnerOptions {
  std::string exe;   // the colony program
  std::string dir;   // the sweep folder
  std::string code;  // the fingerprint of the code, for the rows
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

// ---- Summaries and plots (sweep_summary.cpp) -----------------------------

// `colony sweep --summarize DIR [--plot METRIC:PARAM]`: summary.csv and
// summary_timeseries.csv.
int Summarize(const std::string& dir, const std::string& plot, bool quiet);
// Draws the mean of METRIC (error bars: standard deviation over seeds)
// against the swept parameter PARAM, from DIR/results.csv, into `png`.
void PlotAgainstParam(const std::string& dir, const std::string& metric, const std::string& param,
                      const std::string& png);
// "plot-METRIC[-PARAM].png" with characters other than letters, digits,
// '-', '_' and '.' replaced by '_'.
std::string PlotFileName(const std::string& metric, const std::string& param = "");
// Runs gnuplot on `script` (which sets the output to `png`), with `data`
// written to a temporary file whose path replaces every "$DATA" in the
// script. Throws Failure when gnuplot is missing or draws nothing.
void RunGnuplot(const std::string& script, const std::string& data, const std::string& png);
// `text` as a gnuplot string literal ('...', quotes doubled).
std::string GnuplotQuote(const std::string& text);

}  // namespace colony::sweep
