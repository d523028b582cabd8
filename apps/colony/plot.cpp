// colony plot: a metric drawn as PNG with gnuplot, from what runs and sweeps
// wrote: its time series in one run (RUN/metrics.csv), its mean over the
// seeds with a band per parameter combination (a sweep's
// summary_timeseries.csv, from colony sweep --summarize), or its final value
// against a swept parameter (a sweep's results.csv).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "apps/colony/command_line.h"
#include "apps/colony/sweep.h"
#include "core/error.h"
#include "core/table_writer.h"

namespace colony::sweep {

namespace fs = std::filesystem;

namespace {

struct PlotOptions {
  std::string folder, metric, against, band = "quantiles", out;
  bool quiet = false;
};

std::optional<double> Number(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v)) return std::nullopt;
  return v;
}

// "'NAME' is not a metric of FILE; did you mean 'X'?" (or the list).
UsageError UnknownMetric(const std::string& metric, const std::string& file,
                         const std::vector<std::string>& metrics) {
  const std::string guess = DidYouMean(metric, metrics);
  return UsageError(
      "'" + metric + "' is not a metric of " + file +
      (guess.empty() ? "; its metrics are " + Join(metrics) : "; did you mean '" + guess + "'?"));
}

// The column `name` of `header`, or header.size().
size_t Column(const std::vector<std::string>& header, const std::string& name) {
  return std::find(header.begin(), header.end(), name) - header.begin();
}

// A run folder: the metric against simulated time, one line.
void PlotRun(const PlotOptions& o, const std::string& png) {
  const std::string file = (fs::path(o.folder) / "metrics.csv").string();
  const CsvTable csv = ReadCsvFile(file);
  if (csv.records.empty()) throw UsageError(file + " is empty");
  const auto& header = csv.records.front();
  const size_t time = Column(header, "time"), m = Column(header, o.metric);
  std::vector<std::string> metrics;
  for (const auto& c : header) {
    if (c != "tick" && c != "time") metrics.push_back(c);
  }
  if (o.metric == "tick" || o.metric == "time" || m == header.size()) {
    throw UnknownMetric(o.metric, file, metrics);
  }
  if (time == header.size()) throw UsageError(file + " has no 'time' column; not a run's metrics");
  std::string data;
  for (size_t r = 1; r < csv.records.size(); ++r) {
    const auto& row = csv.records[r];
    if (row.size() != header.size()) continue;  // a killed run's last row
    const auto t = Number(row[time]), v = Number(row[m]);
    if (t && v) data += row[time] + " " + row[m] + "\n";
  }
  if (data.empty()) throw UsageError(file + " has no value of '" + o.metric + "' to draw");
  RunGnuplot("set xlabel 'time (s)'\nset ylabel " + GnuplotQuote(o.metric) +
                 " noenhanced\nset title " + GnuplotQuote(o.folder) +
                 " noenhanced\nset grid\nset key off\nplot '$DATA' using 1:2 with lines lw 2",
             data, png);
}

// A sweep's summary_timeseries.csv: per parameter combination the mean over
// the seeds, and a band (q10 to q90, or mean +- standard deviation).
void PlotSweepSeries(const PlotOptions& o, const std::string& png) {
  const std::string file = (fs::path(o.folder) / "summary_timeseries.csv").string();
  if (!fs::exists(file)) {
    throw UsageError(o.folder + " has no summary_timeseries.csv; run 'colony sweep --summarize " +
                     o.folder + "' first");
  }
  const CsvTable csv = ReadCsvFile(file);
  if (csv.records.empty()) throw UsageError(file + " is empty");
  const auto& header = csv.records.front();
  const size_t metric = Column(header, "metric"), tick = Column(header, "tick"),
               time = Column(header, "time"), mean = Column(header, "mean"),
               std_dev = Column(header, "std_dev"), q10 = Column(header, "q10"),
               q90 = Column(header, "q90");
  for (size_t c : {metric, tick, time, mean, std_dev, q10, q90}) {
    if (c == header.size()) {
      throw UsageError(file +
                       " is not a colony sweep summary_timeseries.csv (metric, tick, "
                       "time, mean, std_dev, q10, q90...)");
    }
  }
  // The combinations (the columns before `metric`), in order, and which
  // parameters vary among them (those name the lines).
  std::vector<std::vector<std::string>> combos;
  std::vector<std::string> blocks, metrics;
  for (size_t r = 1; r < csv.records.size(); ++r) {
    const auto& row = csv.records[r];
    if (row.size() != header.size()) {
      throw UsageError(file + ": row " + std::to_string(r) + " has " + std::to_string(row.size()) +
                       " fields, the header " + std::to_string(header.size()));
    }
    if (std::find(metrics.begin(), metrics.end(), row[metric]) == metrics.end()) {
      metrics.push_back(row[metric]);
    }
    if (row[metric] != o.metric) continue;
    const std::vector<std::string> combo(row.begin(),
                                         row.begin() + static_cast<std::ptrdiff_t>(metric));
    const size_t at = std::find(combos.begin(), combos.end(), combo) - combos.begin();
    if (at == combos.size()) {
      combos.push_back(combo);
      blocks.emplace_back();
    }
    const std::string& x = row[time].empty() ? row[tick] : row[time];
    std::string lo = row[q10], hi = row[q90];
    if (o.band == "std") {
      const auto m = Number(row[mean]), s = Number(row[std_dev]);
      lo = hi = row[mean];
      if (m && s) {
        lo = hi = "";
        AppendNumber(lo, *m - *s);
        AppendNumber(hi, *m + *s);
      }
    }
    if (!Number(row[mean])) continue;
    blocks[at] += x + " " + row[mean] + " " + (lo.empty() ? row[mean] : lo) + " " +
                  (hi.empty() ? row[mean] : hi) + "\n";
  }
  if (combos.empty()) throw UnknownMetric(o.metric, file, metrics);
  std::vector<bool> varies(metric, false);
  for (const auto& c : combos) {
    for (size_t k = 0; k < metric; ++k) varies[k] = varies[k] || c[k] != combos[0][k];
  }
  const std::string band = o.band == "std"         ? "mean ± std dev over seeds"
                           : o.band == "quantiles" ? "mean, q10 to q90 over seeds"
                                                   : "mean over seeds";
  std::string data, script = "set xlabel 'time (s)'\nset ylabel " +
                             GnuplotQuote(o.metric + " (" + band + ")") +
                             " noenhanced\nset key below noenhanced\nset grid\nplot";
  for (size_t i = 0; i < combos.size(); ++i) {
    std::string title;
    for (size_t k = 0; k < metric; ++k) {
      if (varies[k]) title += (title.empty() ? "" : ", ") + header[k] + "=" + combos[i][k];
    }
    if (title.empty()) title = combos.size() == 1 && metric > 0 ? "all runs" : o.metric;
    data += blocks[i] + "\n\n";
    const std::string index = " '$DATA' index " + std::to_string(i);
    const std::string color = " lc " + std::to_string(i + 1);
    if (o.band != "none") {
      script += std::string(i ? "," : "") + index +
                " using 1:3:4 with filledcurves fs transparent solid 0.2 noborder" + color +
                " notitle,";
    } else if (i) {
      script += ",";
    }
    script += index + " using 1:2 with lines lw 2" + color + " title " + GnuplotQuote(title);
  }
  RunGnuplot(script, data, png);
}

bool ParsePlotOptions(const std::vector<std::string>& args, PlotOptions& o) {
  CLI::App app{"draws a metric of a run or a sweep as PNG (gnuplot)", "colony plot"};
  cli::SetUpHelp(app);
  app.allow_extras();
  app.add_option("FOLDER", o.folder,
                 "a run folder: the metric's time series (metrics.csv); a sweep folder: its "
                 "mean over the seeds with a band, one line per parameter combination "
                 "(summary_timeseries.csv, from 'colony sweep --summarize'), or with --against "
                 "its final value against a swept parameter (results.csv)");
  app.add_option("--metric", o.metric, "the metric (a column of metrics.csv)")->type_name("NAME");
  app.add_option("--against", o.against,
                 "a swept parameter (its --set path): the metric's final value, mean and std "
                 "dev over seeds, against it")
      ->type_name("PARAM");
  app.add_option("--band", o.band,
                 "around a sweep's mean: quantiles (q10 to q90, the default), std (mean +- "
                 "standard deviation) or none")
      ->type_name("KIND");
  app.add_option("--out", o.out, "the PNG file (default: FOLDER/plot-METRIC[-PARAM].png)")
      ->type_name("FILE.png");
  app.add_flag("--quiet", o.quiet, "print nothing but errors");
  app.footer(
      "Examples:\n"
      "  colony plot runs/diffusion-20250101-120000 --metric mean_displacement\n"
      "  colony sweep --summarize sweeps/scal && colony plot sweeps/scal --metric "
      "mean_displacement\n"
      "  colony plot sweeps/scal --metric robot_steps_per_second --against "
      "arena.distribute.entity.quantity\n"
      "Exit status: 0 drawn, 2 bad input, 1 gnuplot missing or failing.");
  try {
    if (!cli::Parse(app, args)) return false;
  } catch (const cli::UsageError& e) {
    throw UsageError(e.what());
  }
  if (!app.remaining().empty()) {
    throw UsageError("one folder only, not also '" + app.remaining()[0] + "'");
  }
  if (o.folder.empty()) throw UsageError("colony plot needs a run folder or a sweep folder");
  if (o.metric.empty()) throw UsageError("--metric NAME is needed: which metric to draw");
  const std::vector<std::string> bands = {"quantiles", "std", "none"};
  if (std::find(bands.begin(), bands.end(), o.band) == bands.end()) {
    const std::string guess = DidYouMean(o.band, bands);
    throw UsageError("--band: '" + o.band + "' is not accepted; " +
                     (guess.empty() ? "expected " + Join(bands) : "did you mean '" + guess + "'?"));
  }
  if (!o.against.empty() && app.count("--band")) {
    throw UsageError("--band goes with a time series, not with --against");
  }
  if (app.count("--out") && fs::path(o.out).extension() != ".png") {
    throw UsageError("--out '" + o.out + "': colony plot writes PNG; name the file .png");
  }
  return true;
}

}  // namespace

int PlotCommand(const std::vector<std::string>& args) {
  try {
    PlotOptions o;
    if (!ParsePlotOptions(args, o)) return 0;
    const bool sweep = fs::exists(fs::path(o.folder) / "sweep.xml") ||
                       fs::exists(fs::path(o.folder) / "results.csv");
    const bool run = fs::exists(fs::path(o.folder) / "metrics.csv");
    if (!sweep && !run) {
      throw UsageError(o.folder + (fs::is_directory(o.folder) ? " is" : " is not a folder, so") +
                       " neither a run folder (metrics.csv) nor a sweep folder (sweep.xml)");
    }
    if (!o.against.empty() && !sweep) {
      throw UsageError("--against needs a sweep folder; " + o.folder + " is a run folder");
    }
    const std::string png =
        o.out.empty() ? (fs::path(o.folder) / PlotFileName(o.metric, o.against)).string() : o.out;
    if (!o.against.empty()) {
      PlotAgainstParam(o.folder, o.metric, o.against, png);
    } else if (sweep) {
      PlotSweepSeries(o, png);
    } else {
      PlotRun(o, png);
    }
    if (!o.quiet) std::printf("plot: %s\n", png.c_str());
    return 0;
  } catch (const UsageError& e) {
    std::fprintf(stderr, "colony plot: %s\nrun 'colony plot --help' for usage\n", e.what());
    return 2;
  } catch (const Failure& e) {
    std::fprintf(stderr, "colony plot: %s\n", e.what());
    return 1;
  }
}

}  // namespace colony::sweep
