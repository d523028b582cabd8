// --summarize: per parameter combination, count, mean, standard deviation,
// median, min and max of every numeric column of results.csv over the ok
// runs (the seeds), printed and written to summary.csv; and per tick the
// same and quantiles of every metric of the runs' metrics.csv, written to
// summary_timeseries.csv. --plot (and colony plot) draws one metric against
// one parameter with gnuplot.
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "apps/colony/sweep.h"
#include "core/error.h"
#include "core/table_writer.h"

namespace colony::sweep {

namespace fs = std::filesystem;

namespace {

// Columns of results.csv that are not measurements.
bool IsMeasurement(const std::string& column) {
  return column != "run" && column != "seed" && column != "status" && column != "stale" &&
         column != "detail" && column != "final_state_hash" && column != "code";
}

std::optional<double> Number(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v)) return std::nullopt;
  return v;
}

struct Stats {
  size_t count = 0;
  double mean = 0, std_dev = NAN, median = 0, min = 0, max = 0;
  double q10 = 0, q25 = 0, q75 = 0, q90 = 0;
};

// The p-quantile of sorted `v`, interpolated linearly between the order
// statistics at (n - 1) p (numpy.quantile's and R's default, type 7).
double Quantile(const std::vector<double>& v, double p) {
  const double h = static_cast<double>(v.size() - 1) * p;
  const size_t below = static_cast<size_t>(std::floor(h));
  if (below + 1 >= v.size()) return v.back();
  return v[below] + (h - static_cast<double>(below)) * (v[below + 1] - v[below]);
}

Stats Describe(std::vector<double> v) {
  Stats s;
  s.count = v.size();
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  s.min = v.front();
  s.max = v.back();
  const size_t n = v.size();
  s.median = n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
  s.q10 = Quantile(v, 0.1);
  s.q25 = Quantile(v, 0.25);
  s.q75 = Quantile(v, 0.75);
  s.q90 = Quantile(v, 0.9);
  for (double x : v) s.mean += x;
  s.mean /= n;
  if (n > 1) {
    double sum = 0;
    for (double x : v) sum += (x - s.mean) * (x - s.mean);
    s.std_dev = std::sqrt(sum / (n - 1));  // sample standard deviation
  }
  return s;
}

// A number for a CSV file: the shortest text that reads back as the same
// double; "" for none (NaN).
std::string Format(double v) {
  if (std::isnan(v)) return "";
  std::string text;
  AppendNumber(text, v);
  return text;
}

// A number for the terminal.
std::string Format(double v, const char* format) {
  if (std::isnan(v)) return "";
  char text[64];
  std::snprintf(text, sizeof text, format, v);
  return text;
}

// results.csv as read back: header, rows, and which columns are parameters
// (those between "run" and "seed").
struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  size_t params = 0;  // columns 1..params
  size_t Column(const std::string& name) const {
    return std::find(header.begin(), header.end(), name) - header.begin();
  }
};

Table ReadTable(const std::string& dir) {
  const fs::path path = fs::path(dir) / "results.csv";
  if (!fs::exists(path)) {
    throw UsageError(dir + " has no results.csv (run the sweep first, or --collect its shards)");
  }
  CsvTable csv = ReadCsvFile(path.string());
  if (csv.cut_line) {
    throw UsageError(path.string() + ":" + std::to_string(csv.cut_line) +
                     ": the last row is cut short (no line end, or a quote never closed)");
  }
  Table t;
  if (!csv.records.empty()) t.header = std::move(csv.records.front());
  if (t.header.empty() || t.header[0] != "run" || t.Column("seed") == t.header.size() ||
      t.Column("status") == t.header.size()) {
    throw UsageError(path.string() +
                     " is not a colony sweep results table (run, ..., seed, status...)");
  }
  t.params = t.Column("seed") - 1;
  for (size_t i = 1; i < csv.records.size(); ++i) {
    if (csv.records[i].size() != t.header.size()) {
      throw UsageError(path.string() + ": row " + std::to_string(i) + " has " +
                       std::to_string(csv.records[i].size()) + " fields, the header " +
                       std::to_string(t.header.size()));
    }
    t.rows.push_back(std::move(csv.records[i]));
  }
  return t;
}

// One parameter combination: its values, its runs' statuses, and per
// measurement column the values of its ok runs.
struct Group {
  std::vector<std::string> values;
  size_t ok = 0, failed = 0, timeout = 0, stale = 0;
  std::vector<std::string> runs;  // the ok runs' folders under runs/
  std::map<size_t, std::vector<double>> samples;
};

std::vector<Group> GroupRuns(const Table& t) {
  std::vector<Group> groups;
  const size_t status = t.Column("status"), stale = t.Column("stale");
  for (const auto& row : t.rows) {
    const std::vector<std::string> values(row.begin() + 1,
                                          row.begin() + 1 + static_cast<std::ptrdiff_t>(t.params));
    auto g = std::find_if(groups.begin(), groups.end(),
                          [&](const Group& x) { return x.values == values; });
    if (g == groups.end()) {
      g = groups.emplace(groups.end());
      g->values = values;
    }
    if (row[status] != "ok") {
      (row[status] == "timeout" ? g->timeout : g->failed)++;
      continue;
    }
    ++g->ok;
    g->stale += stale < row.size() && row[stale] == "true";
    g->runs.push_back(row[0]);
    for (size_t c = 1 + t.params; c < row.size(); ++c) {
      if (!IsMeasurement(t.header[c])) continue;
      if (const auto v = Number(row[c])) g->samples[c].push_back(*v);
    }
  }
  return groups;
}

std::string Label(const Table& t, const Group& g) {
  std::string label;
  for (size_t k = 0; k < t.params; ++k) {
    label += (k ? "  " : "") + t.header[1 + k] + "=" + g.values[k];
  }
  return label.empty() ? "(no parameters)" : label;
}

void Print(const Table& t, const std::vector<Group>& groups) {
  for (const auto& g : groups) {
    std::printf("%s: %zu ok", Label(t, g).c_str(), g.ok);
    if (g.failed) std::printf(", %zu failed", g.failed);
    if (g.timeout) std::printf(", %zu timeout", g.timeout);
    if (g.stale) std::printf(" (%zu of them stale: made with older code)", g.stale);
    std::printf("\n  %-28s %6s %14s %14s %14s\n", "metric", "count", "mean", "std_dev", "median");
    for (const auto& [column, values] : g.samples) {
      const Stats s = Describe(values);
      std::printf("  %-28s %6zu %14s %14s %14s\n", t.header[column].c_str(), s.count,
                  Format(s.mean, "%.6g").c_str(),
                  std::isnan(s.std_dev) ? "-" : Format(s.std_dev, "%.6g").c_str(),
                  Format(s.median, "%.6g").c_str());
    }
  }
}

std::vector<std::string> ParamColumns(const Table& t) {
  return {t.header.begin() + 1, t.header.begin() + 1 + static_cast<std::ptrdiff_t>(t.params)};
}

void WriteSummary(const std::string& dir, const Table& t, const std::vector<Group>& groups) {
  std::vector<std::string> header = ParamColumns(t);
  header.insert(header.end(), {"metric", "count", "mean", "std_dev", "median", "min", "max"});
  std::string text = CsvLine(header) + "\n";
  for (const auto& g : groups) {
    for (const auto& [column, values] : g.samples) {
      const Stats s = Describe(values);
      std::vector<std::string> fields = g.values;
      fields.insert(fields.end(),
                    {t.header[column], std::to_string(s.count), Format(s.mean), Format(s.std_dev),
                     Format(s.median), Format(s.min), Format(s.max)});
      text += CsvLine(fields) + "\n";
    }
  }
  WriteAtomically((fs::path(dir) / "summary.csv").string(), text);
}

// The metrics of one combination's runs, tick by tick: per metric (in order
// of first appearance) and per tick, the values over the runs.
struct Series {
  std::vector<std::string> metrics;
  std::map<uint64_t, double> time;  // tick -> simulated seconds
  // metric -> tick -> values over the runs
  std::vector<std::map<uint64_t, std::vector<double>>> values;
};

// Adds one run's metrics.csv to `series`.
void AddRun(Series& series, const fs::path& metrics_csv) {
  const CsvTable csv = ReadCsvFile(metrics_csv.string());
  if (csv.records.empty()) return;
  const auto& header = csv.records.front();
  const size_t tick = std::find(header.begin(), header.end(), "tick") - header.begin(),
               time = std::find(header.begin(), header.end(), "time") - header.begin();
  if (tick == header.size()) {
    throw UsageError(metrics_csv.string() + ": has no 'tick' column; not a run's metrics.csv");
  }
  // Where each of the file's metric columns goes in `series`.
  std::vector<size_t> slot(header.size(), SIZE_MAX);
  for (size_t c = 0; c < header.size(); ++c) {
    if (c == tick || c == time) continue;
    slot[c] =
        std::find(series.metrics.begin(), series.metrics.end(), header[c]) - series.metrics.begin();
    if (slot[c] == series.metrics.size()) {
      series.metrics.push_back(header[c]);
      series.values.emplace_back();
    }
  }
  for (size_t r = 1; r < csv.records.size(); ++r) {
    const auto& record = csv.records[r];
    if (record.size() != header.size()) {
      throw UsageError(metrics_csv.string() + ": row " + std::to_string(r) + " has " +
                       std::to_string(record.size()) + " fields, the header " +
                       std::to_string(header.size()));
    }
    const auto t = Number(record[tick]);
    if (!t || *t < 0) {
      throw UsageError(metrics_csv.string() + ": row " + std::to_string(r) + ": tick '" +
                       record[tick] + "' is not a whole number");
    }
    const auto at = static_cast<uint64_t>(*t);
    if (time < header.size()) {
      if (const auto seconds = Number(record[time])) series.time.emplace(at, *seconds);
    }
    for (size_t c = 0; c < header.size(); ++c) {
      if (slot[c] == SIZE_MAX) continue;
      if (const auto v = Number(record[c])) series.values[slot[c]][at].push_back(*v);
    }
  }
}

// DIR/summary_timeseries.csv: per combination, metric and tick, statistics
// over the ok runs' metrics.csv (one combination read at a time).
void WriteTimeseries(const std::string& dir, const Table& t, const std::vector<Group>& groups) {
  std::vector<std::string> header = ParamColumns(t);
  header.insert(header.end(), {"metric", "tick", "time", "count", "mean", "std_dev", "min", "q10",
                               "q25", "median", "q75", "q90", "max"});
  std::string text = CsvLine(header) + "\n";
  for (const auto& g : groups) {
    Series series;
    for (const auto& run : g.runs) {
      const fs::path csv = fs::path(dir) / "runs" / run / "metrics.csv";
      if (!fs::exists(csv)) {
        throw UsageError(csv.string() + " is missing (run " + run + " is ok in results.csv)");
      }
      AddRun(series, csv);
    }
    for (size_t m = 0; m < series.metrics.size(); ++m) {
      for (const auto& [tick, values] : series.values[m]) {
        const Stats s = Describe(values);
        const auto time = series.time.find(tick);
        std::vector<std::string> fields = g.values;
        fields.insert(fields.end(), {series.metrics[m], std::to_string(tick),
                                     time == series.time.end() ? "" : Format(time->second),
                                     std::to_string(s.count), Format(s.mean), Format(s.std_dev),
                                     Format(s.min), Format(s.q10), Format(s.q25), Format(s.median),
                                     Format(s.q75), Format(s.q90), Format(s.max)});
        text += CsvLine(fields) + "\n";
      }
    }
  }
  WriteAtomically((fs::path(dir) / "summary_timeseries.csv").string(), text);
}

// The lines of a plot of column `m` against parameter column `p`: one per
// combination of the other parameters that vary, each a gnuplot data block
// of "x-position label mean std-dev" rows.
struct PlotLines {
  bool numeric = true;  // x values are numbers (else categories at 0, 1, ...)
  std::vector<std::string> titles, blocks;
};

PlotLines LinesOf(const Table& t, const std::vector<Group>& groups, size_t m, size_t p) {
  PlotLines lines;
  std::vector<std::string> xs;
  std::vector<bool> varies(t.params, false);
  for (const auto& g : groups) {
    if (std::find(xs.begin(), xs.end(), g.values[p - 1]) == xs.end()) xs.push_back(g.values[p - 1]);
    for (size_t k = 0; k < t.params; ++k) {
      varies[k] = varies[k] || g.values[k] != groups[0].values[k];
    }
  }
  lines.numeric =
      std::all_of(xs.begin(), xs.end(), [](const auto& x) { return Number(x).has_value(); });
  for (const auto& g : groups) {
    const auto samples = g.samples.find(m);
    if (samples == g.samples.end()) continue;
    std::string title;
    for (size_t k = 0; k < t.params; ++k) {
      if (k + 1 != p && varies[k]) {
        title += (title.empty() ? "" : ", ") + t.header[1 + k] + "=" + g.values[k];
      }
    }
    if (title.empty()) title = t.header[m];
    const size_t line =
        std::find(lines.titles.begin(), lines.titles.end(), title) - lines.titles.begin();
    if (line == lines.titles.size()) {
      lines.titles.push_back(title);
      lines.blocks.emplace_back();
    }
    const Stats s = Describe(samples->second);
    const std::string& x = g.values[p - 1];
    const std::string position =
        lines.numeric ? x : std::to_string(std::find(xs.begin(), xs.end(), x) - xs.begin());
    std::string label = x;
    std::replace(label.begin(), label.end(), '"', '\'');
    lines.blocks[line] += position + " \"" + label + "\" " + Format(s.mean) + " " +
                          (std::isnan(s.std_dev) ? "0" : Format(s.std_dev)) + "\n";
  }
  return lines;
}

// The x axis is logarithmic when numeric, positive and spanning 100x or more
// (swarm sizes).
bool LogScale(const PlotLines& lines) {
  double lo = INFINITY, hi = 0;
  for (const auto& block : lines.blocks) {
    std::istringstream rows(block);
    for (std::string row; std::getline(rows, row);) {
      const double x = std::strtod(row.c_str(), nullptr);
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
  }
  return lines.numeric && lo > 0 && hi >= 100 * lo;
}

// Draws the mean of `metric` (error bars: standard deviation) against
// `param` into `png`.
void Plot(const Table& t, const std::vector<Group>& groups, const std::string& metric,
          const std::string& param, const std::string& png) {
  const size_t m = t.Column(metric), p = t.Column(param);
  if (m == t.header.size() || m <= t.params || !IsMeasurement(metric)) {
    std::vector<std::string> measured;
    for (size_t c = 1 + t.params; c < t.header.size(); ++c) {
      if (IsMeasurement(t.header[c])) measured.push_back(t.header[c]);
    }
    const std::string guess = DidYouMean(metric, measured);
    throw UsageError(
        "'" + metric + "' is not a measured column of results.csv" +
        (guess.empty() ? "; they are " + Join(measured) : "; did you mean '" + guess + "'?"));
  }
  if (p < 1 || p > t.params) {
    const std::vector<std::string> params = ParamColumns(t);
    throw UsageError("'" + param + "' is not a swept parameter; " +
                     (params.empty() ? "the sweep sweeps none" : "they are " + Join(params)));
  }
  const PlotLines lines = LinesOf(t, groups, m, p);
  std::string data, script = "set xlabel " + GnuplotQuote(param) + " noenhanced\nset ylabel " +
                             GnuplotQuote(metric + " (mean and std dev over seeds)") +
                             " noenhanced\nset key below noenhanced\nset grid\n"
                             "set offsets graph 0.03, graph 0.03\n" +
                             (LogScale(lines) ? "set logscale x\n" : "") + "plot";
  for (size_t i = 0; i < lines.titles.size(); ++i) {
    data += lines.blocks[i] + "\n\n";
    script += std::string(i ? "," : "") + " '$DATA' index " + std::to_string(i) + " using 1:3:4" +
              (lines.numeric ? "" : ":xtic(2)") + " with yerrorlines title " +
              GnuplotQuote(lines.titles[i]);
  }
  RunGnuplot(script, data, png);
}

}  // namespace

std::string GnuplotQuote(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

std::string PlotFileName(const std::string& metric, const std::string& param) {
  std::string stem = "plot-" + metric + (param.empty() ? "" : "-" + param);
  for (char& c : stem) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.') c = '_';
  }
  return stem + ".png";
}

void RunGnuplot(const std::string& script, const std::string& data, const std::string& png) {
  if (!OnPath("gnuplot")) {
    throw Failure(
        "plotting needs gnuplot, which is not installed (Debian: apt-get install "
        "gnuplot-nox)");
  }
  // The data goes in a file of its own, beside nothing of the user's.
  char folder[] = "/tmp/colony-plot-XXXXXX";
  if (!mkdtemp(folder)) throw Failure("cannot make a temporary folder for gnuplot's data");
  const std::string data_file = std::string(folder) + "/data";
  std::error_code ec;
  if (!(std::ofstream(data_file) << data)) {
    fs::remove_all(folder, ec);
    throw Failure("cannot write gnuplot's data to " + data_file);
  }
  std::string body = script;
  for (size_t at = body.find("$DATA"); at != std::string::npos; at = body.find("$DATA", at)) {
    body.replace(at, 5, data_file);
    at += data_file.size();
  }
  const fs::path out = fs::absolute(png);
  fs::remove(out, ec);  // so that a PNG there afterwards is this one
  const std::string full = "set terminal pngcairo size 900,600\nset output " +
                           GnuplotQuote(out.string()) + "\n" + body + "\n";
  FILE* gnuplot = popen(("gnuplot > '" + std::string(folder) + "/log' 2>&1").c_str(), "w");
  if (!gnuplot) {
    fs::remove_all(folder, ec);
    throw Failure("cannot start gnuplot");
  }
  std::fputs(full.c_str(), gnuplot);
  const int status = pclose(gnuplot);
  const std::string log = ReadText(std::string(folder) + "/log");
  fs::remove_all(folder, ec);
  if (status != 0 || !fs::exists(out) || fs::file_size(out, ec) == 0) {
    throw Failure("gnuplot could not draw " + out.string() + (log.empty() ? "" : ":\n" + log));
  }
}

void PlotAgainstParam(const std::string& dir, const std::string& metric, const std::string& param,
                      const std::string& png) {
  const Table t = ReadTable(dir);
  Plot(t, GroupRuns(t), metric, param, png);
}

int Summarize(const std::string& dir, const std::string& plot, bool quiet) {
  const Table t = ReadTable(dir);
  const auto groups = GroupRuns(t);
  if (!quiet) Print(t, groups);
  WriteSummary(dir, t, groups);
  WriteTimeseries(dir, t, groups);
  if (!quiet) {
    std::printf("summary in %s/summary.csv, per tick in %s/summary_timeseries.csv\n", dir.c_str(),
                dir.c_str());
  }
  if (plot.empty()) return 0;
  const size_t colon = plot.find(':');
  if (colon == std::string::npos) {
    throw UsageError("--plot '" + plot + "': expected METRIC:PARAM");
  }
  const std::string png =
      (fs::path(dir) / PlotFileName(plot.substr(0, colon), plot.substr(colon + 1))).string();
  try {
    Plot(t, groups, plot.substr(0, colon), plot.substr(colon + 1), png);
  } catch (const UsageError& e) {
    throw UsageError("--plot '" + plot + "': " + e.what());
  } catch (const Failure& e) {
    throw Failure(std::string(e.what()) + "; the summaries were written, the plot was not");
  }
  std::printf("plot: %s\n", png.c_str());
  return 0;
}

}  // namespace colony::sweep
