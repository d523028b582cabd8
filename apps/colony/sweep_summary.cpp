// --summarize: per parameter combination, count, mean, standard deviation,
// median, min and max of every numeric column of results.csv over the ok
// runs (the seeds); printed and written to summary.csv. --plot draws one
// metric against one parameter with gnuplot, when it is installed.
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

namespace colony::sweep {

namespace fs = std::filesystem;

namespace {

// Columns of results.csv that are not measurements.
bool IsMeasurement(const std::string& column) {
  return column != "run" && column != "seed" && column != "status" && column != "detail" &&
         column != "final_state_hash";
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
};

Stats Describe(std::vector<double> v) {
  Stats s;
  s.count = v.size();
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  s.min = v.front();
  s.max = v.back();
  const size_t n = v.size();
  s.median = n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
  for (double x : v) s.mean += x;
  s.mean /= n;
  if (n > 1) {
    double sum = 0;
    for (double x : v) sum += (x - s.mean) * (x - s.mean);
    s.std_dev = std::sqrt(sum / (n - 1));  // sample standard deviation
  }
  return s;
}

std::string Format(double v, const char* format = "%.10g") {
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
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line)) {
    throw UsageError(dir + " has no results.csv (run the sweep first, or --collect its shards)");
  }
  Table t;
  t.header = ParseCsvLine(line);
  if (t.header.empty() || t.header[0] != "run" || t.Column("seed") == t.header.size()) {
    throw UsageError(path.string() + " is not a colony sweep results table");
  }
  t.params = t.Column("seed") - 1;
  while (std::getline(in, line)) {
    auto fields = ParseCsvLine(line);
    if (fields.size() == t.header.size()) t.rows.push_back(std::move(fields));
  }
  return t;
}

// One parameter combination: its values, its runs' statuses, and per
// measurement column the values of its ok runs.
struct Group {
  std::vector<std::string> values;
  size_t ok = 0, failed = 0, timeout = 0;
  std::map<size_t, std::vector<double>> samples;
};

std::vector<Group> GroupRuns(const Table& t) {
  std::vector<Group> groups;
  const size_t status = t.Column("status");
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

void WriteSummary(const std::string& dir, const Table& t, const std::vector<Group>& groups) {
  std::vector<std::string> header(t.header.begin() + 1,
                                  t.header.begin() + 1 + static_cast<std::ptrdiff_t>(t.params));
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

std::string GnuplotQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
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
    lines.blocks[line] += position + " \"" + x + "\" " + Format(s.mean) + " " +
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

// Draws the mean of a metric (error bars: standard deviation) against a
// parameter, given as "METRIC:PARAM", into DIR/plot-METRIC-PARAM.png.
void Plot(const std::string& dir, const Table& t, const std::vector<Group>& groups,
          const std::string& spec) {
  const size_t colon = spec.find(':');
  const std::string metric = spec.substr(0, colon),
                    param = colon == std::string::npos ? "" : spec.substr(colon + 1);
  const size_t m = t.Column(metric), p = t.Column(param);
  if (colon == std::string::npos || m == t.header.size() || m <= t.params ||
      !IsMeasurement(metric)) {
    throw UsageError("--plot '" + spec +
                     "': expected METRIC:PARAM with METRIC a measured column of results.csv");
  }
  if (p < 1 || p > t.params) {
    throw UsageError("--plot '" + spec + "': '" + param + "' is not a swept parameter");
  }
  if (!OnPath("gnuplot")) {
    throw Failure(
        "--plot needs gnuplot, which is not installed (Debian: apt-get install gnuplot-nox); "
        "summary.csv was written, the plot was not");
  }
  const PlotLines lines = LinesOf(t, groups, m, p);
  std::string stem = "plot-" + metric + "-" + param;
  for (char& c : stem) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.') c = '_';
  }
  const std::string data = (fs::path(dir) / (stem + ".dat")).string(),
                    png = (fs::path(dir) / (stem + ".png")).string();
  std::ofstream(data) << [&] {
    std::string text;
    for (const auto& block : lines.blocks) text += block + "\n\n";
    return text;
  }();
  std::string script =
      "set terminal pngcairo size 900,600\nset output " + GnuplotQuote(png) + "\nset xlabel " +
      GnuplotQuote(param) + " noenhanced\nset ylabel " +
      GnuplotQuote(metric + " (mean and std dev over seeds)") +
      " noenhanced\nset key below noenhanced\nset grid\nset offsets graph 0.03, graph 0.03\n" +
      (LogScale(lines) ? "set logscale x\n" : "") + "plot";
  for (size_t i = 0; i < lines.titles.size(); ++i) {
    script += std::string(i ? "," : "") + " " + GnuplotQuote(data) + " index " + std::to_string(i) +
              " using 1:3:4" + (lines.numeric ? "" : ":xtic(2)") + " with yerrorlines title " +
              GnuplotQuote(lines.titles[i]);
  }
  FILE* gnuplot = popen("gnuplot", "w");
  if (!gnuplot) throw Failure("cannot start gnuplot");
  std::fputs((script + "\n").c_str(), gnuplot);
  if (pclose(gnuplot) != 0 || !fs::exists(png)) throw Failure("gnuplot could not draw " + png);
  std::printf("plot: %s\n", png.c_str());
}

}  // namespace

int Summarize(const std::string& dir, const std::string& plot, bool quiet) {
  const Table t = ReadTable(dir);
  const auto groups = GroupRuns(t);
  if (!quiet) Print(t, groups);
  WriteSummary(dir, t, groups);
  if (!quiet) std::printf("summary in %s/summary.csv\n", dir.c_str());
  if (!plot.empty()) Plot(dir, t, groups, plot);
  return 0;
}

}  // namespace colony::sweep
