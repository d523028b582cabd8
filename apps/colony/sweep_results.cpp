// Rows and tables: a finished run's row (row.csv in its folder), results.csv,
// and --collect.
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "apps/colony/sweep.h"
#include "core/log.h"
#include "core/output.h"
#include "core/table_writer.h"

namespace colony::sweep {

namespace fs = std::filesystem;

namespace {

// Columns from summary.json, in this order, after the fixed ones.
constexpr const char* kSummaryColumns[] = {
    "ticks",        "simulated_seconds",      "robots",
    "step_seconds", "robot_steps_per_second", "final_state_hash"};

// A JSON value as a results.csv field: strings unquoted, null empty,
// whole numbers without a decimal point (10, not 10.0), others in the
// shortest form that reads back the same.
std::string FieldText(const nlohmann::json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_null()) return "";
  if (v.is_number_float()) {
    const double d = v.get<double>();
    if (d == std::floor(d) && std::fabs(d) < 1e15) {
      char text[32];
      std::snprintf(text, sizeof text, "%.0f", d);
      return text;
    }
  }
  return v.dump();
}

// The header and last complete row of metrics.csv, if it has one (a killed
// run may have left half a row; a row of another length is not complete).
std::optional<std::pair<std::vector<std::string>, std::vector<std::string>>> LastMetricsRow(
    const fs::path& path) {
  if (!fs::exists(path)) return std::nullopt;
  const CsvTable csv = ReadCsvFile(path.string());
  if (csv.records.empty()) return std::nullopt;
  const auto& header = csv.records.front();
  for (size_t i = csv.records.size(); i-- > 1;) {
    if (csv.records[i].size() == header.size()) return std::make_pair(header, csv.records[i]);
  }
  return std::nullopt;
}

void Set(Row& row, const std::string& column, const std::string& value) {
  for (auto& [c, v] : row) {
    if (c == column) {
      v = value;
      return;
    }
  }
  row.emplace_back(column, value);
}

// Appends a loop-functions metric, prefixed "metrics." if its name is taken
// (or is one of the columns that come after the metrics).
void AddMetric(Row& row, const std::string& name, const std::string& value) {
  const bool taken =
      name == "code" || name == "stale" || name == "detail" ||
      std::any_of(row.begin(), row.end(), [&](const auto& cv) { return cv.first == name; });
  row.emplace_back(taken ? "metrics." + name : name, value);
}

// What the run left: summary.json when it completed, else the last row of
// metrics.csv (how far it got).
void AddRunOutput(Row& row, const fs::path& run_dir, const nlohmann::ordered_json* summary) {
  for (const char* c : kSummaryColumns) row.emplace_back(c, "");
  if (summary) {
    for (const char* c : kSummaryColumns) {
      if (summary->contains(c)) Set(row, c, FieldText((*summary)[c]));
    }
    for (const auto& [name, value] : (*summary)["metrics"].items()) {
      AddMetric(row, name, FieldText(value));
    }
    return;
  }
  std::optional<std::pair<std::vector<std::string>, std::vector<std::string>>> last;
  try {
    last = LastMetricsRow(run_dir / "metrics.csv");
  } catch (const UsageError& e) {
    LogWarning(std::string(e.what()) + " (the row of run " + run_dir.filename().string() +
               " has no metrics)");
  }
  if (!last) return;
  const auto& [header, values] = *last;
  for (size_t i = 0; i < header.size(); ++i) {
    if (header[i] == "tick") {
      Set(row, "ticks", values[i]);
    } else if (header[i] == "time") {
      Set(row, "simulated_seconds", values[i]);
    } else {
      AddMetric(row, header[i], values[i]);
    }
  }
}

}  // namespace

std::string CsvLine(const std::vector<std::string>& fields) {
  std::string line;
  for (size_t i = 0; i < fields.size(); ++i) {
    if (i) line += ',';
    AppendCsvField(line, fields[i]);
  }
  return line;
}

CsvTable ParseCsv(const std::string& text, const std::string& what) {
  CsvTable csv;
  std::vector<std::string> record;
  std::string field;
  bool quoted = false;      // inside a quoted field
  bool was_quoted = false;  // the current field was quoted (then only a separator may follow)
  size_t line = 1, record_line = 1;
  auto end_field = [&] {
    record.push_back(std::move(field));
    field.clear();
    was_quoted = false;
  };
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        line += c == '\n';
        field += c;
      }
      continue;
    }
    if (c == ',') {
      end_field();
    } else if (c == '\n' || (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n')) {
      if (c == '\r') ++i;
      end_field();
      csv.records.push_back(std::move(record));
      record.clear();
      record_line = ++line;
    } else if (c == '"' && field.empty() && !was_quoted) {
      quoted = was_quoted = true;
    } else if (was_quoted) {
      throw UsageError(what + ":" + std::to_string(line) +
                       ": a character after a quoted field's closing quote; not CSV (RFC 4180)");
    } else {
      field += c;
    }
  }
  // A record without its line end, or with a quote never closed, was cut
  // short (a killed writer); it is dropped.
  if (quoted || !field.empty() || !record.empty() || was_quoted) csv.cut_line = record_line;
  return csv;
}

CsvTable ReadCsvFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw UsageError(path + ": cannot read it (" + std::strerror(errno) + ")");
  std::stringstream s;
  s << in.rdbuf();
  return ParseCsv(s.str(), path);
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void WriteAtomically(const std::string& path, const std::string& text) {
  char host[256] = "host";
  gethostname(host, sizeof host - 1);
  // Ranks on several hosts may share the folder: each its own temporary file.
  const std::string tmp = path + "." + host + "." + std::to_string(getpid()) + ".tmp";
  try {
    WriteFileAtomically(path, text, /*sync=*/true, tmp);
  } catch (const RuntimeFailure& e) {
    throw Failure(e.what());
  }
}

const char* StatusName(RunEnd::Status status) {
  switch (status) {
    case RunEnd::Status::kOk:
      return "ok";
    case RunEnd::Status::kTimeout:
      return "timeout";
    default:
      return "failed";
  }
}

std::string RunDir(const std::string& dir, const RunSpec& run) {
  return (fs::path(dir) / "runs" / run.name).string();
}

Row MakeRow(const Grid& grid, const RunSpec& run, const RunEnd& end, const std::string& run_dir,
            const std::string& code) {
  RunEnd result = end;
  // Finished means a summary that parses, has every key and says completed.
  const fs::path summary_file = fs::path(run_dir) / "summary.json";
  const std::string text = fs::exists(summary_file) ? ReadText(summary_file.string()) : "";
  const std::string problem =
      fs::exists(summary_file) ? SummaryProblem(text) : "there is no summary.json";
  const bool completed = problem.empty() && result.status == RunEnd::Status::kOk;
  if (result.status == RunEnd::Status::kOk && !problem.empty()) {
    result = {RunEnd::Status::kFailed, end.wall_seconds,
              "exited with status 0 but is not a finished run: " +
                  (fs::exists(summary_file) ? "summary.json: " + problem : problem)};
  }
  Row row{{"run", run.name}};
  for (size_t k = 0; k < grid.params.size(); ++k) {
    row.emplace_back(grid.params[k].path, run.values[k]);
  }
  row.emplace_back("seed", std::to_string(run.seed));
  row.emplace_back("status", StatusName(result.status));
  char wall[32];
  std::snprintf(wall, sizeof wall, "%.3f", result.wall_seconds);
  row.emplace_back("wall_seconds", wall);
  if (completed) {
    // SummaryProblem has checked that it parses and has every key.
    const auto summary = nlohmann::ordered_json::parse(text);
    AddRunOutput(row, run_dir, &summary);
  } else {
    AddRunOutput(row, run_dir, nullptr);
  }
  row.emplace_back("code", code);
  row.emplace_back("detail", result.detail);
  return row;
}

void WriteRow(const std::string& run_dir, const Row& row) {
  std::vector<std::string> header, values;
  for (const auto& [c, v] : row) {
    header.push_back(c);
    values.push_back(v);
  }
  WriteAtomically((fs::path(run_dir) / "row.csv").string(),
                  CsvLine(header) + "\n" + CsvLine(values) + "\n");
}

std::optional<Row> ReadRow(const std::string& run_dir) {
  const fs::path path = fs::path(run_dir) / "row.csv";
  if (!fs::exists(path)) return std::nullopt;
  // Written atomically: anything but a header and one row of its length is
  // not ours (the run counts as unfinished and runs again).
  const CsvTable csv = ReadCsvFile(path.string());
  if (csv.cut_line || csv.records.size() != 2 || csv.records[0].size() != csv.records[1].size()) {
    return std::nullopt;
  }
  Row row;
  for (size_t i = 0; i < csv.records[0].size(); ++i) {
    row.emplace_back(csv.records[0][i], csv.records[1][i]);
  }
  return row;
}

std::string RowValue(const Row& row, const std::string& column) {
  for (const auto& [c, v] : row) {
    if (c == column) return v;
  }
  return "";
}

std::string RowStatus(const Row& row) { return RowValue(row, "status"); }

std::vector<std::optional<Row>> ReadRows(const std::string& dir, const Grid& grid) {
  std::vector<std::optional<Row>> rows(grid.size());
  for (size_t i = 0; i < rows.size(); ++i) rows[i] = ReadRow(RunDir(dir, RunAt(grid, i)));
  return rows;
}

void WriteResults(const std::string& dir, const std::vector<std::optional<Row>>& rows,
                  const std::string& code) {
  // Columns: every row's, in order of first appearance, `stale` after
  // `status`; detail last.
  std::vector<std::string> header;
  for (const auto& row : rows) {
    if (!row) continue;
    for (const auto& [c, v] : *row) {
      if (c != "detail" && std::find(header.begin(), header.end(), c) == header.end()) {
        header.push_back(c);
        if (c == "status") header.push_back("stale");
      }
    }
  }
  header.push_back("detail");
  std::string text = CsvLine(header) + "\n";
  for (const auto& row : rows) {
    if (!row) continue;
    std::vector<std::string> fields(header.size());
    for (const auto& [c, v] : *row) {
      fields[std::find(header.begin(), header.end(), c) - header.begin()] = v;
    }
    const std::string made_with = RowValue(*row, "code");
    const size_t stale = std::find(header.begin(), header.end(), "stale") - header.begin();
    if (stale < header.size() && !made_with.empty() && !code.empty()) {
      fields[stale] = made_with == code ? "false" : "true";
    }
    text += CsvLine(fields) + "\n";
  }
  WriteAtomically((fs::path(dir) / "results.csv").string(), text);
}

int Collect(const std::vector<std::string>& dirs, const std::string& out, bool quiet) {
  const Manifest manifest = ReadManifest(dirs[0]);
  const Grid& grid = manifest.grid;
  for (size_t d = 1; d < dirs.size(); ++d) {
    const Grid other = ReadManifest(dirs[d]).grid;
    std::string why = GridDifference(other, grid);
    if (why.empty()) why = GridChange(other, grid);
    if (why.empty() && other.run_folders != grid.run_folders) {
      why = "its run folders are named otherwise (made by another version of colony sweep)";
    }
    if (!why.empty()) {
      throw UsageError(dirs[d] + " holds another sweep than " + dirs[0] + ": " + why);
    }
  }
  // Each run's row: an ok one if any folder has it, else the first found.
  std::vector<std::optional<Row>> rows(grid.size());
  std::vector<std::string> missing;
  size_t ok = 0, failed = 0, timeout = 0;
  for (size_t i = 0; i < rows.size(); ++i) {
    const RunSpec run = RunAt(grid, i);
    for (const auto& dir : dirs) {
      auto row = ReadRow(RunDir(dir, run));
      if (row && (!rows[i] || RowStatus(*row) == "ok")) rows[i] = std::move(row);
      if (rows[i] && RowStatus(*rows[i]) == "ok") break;
    }
    if (!rows[i]) {
      missing.push_back(run.name);
      continue;
    }
    const std::string status = RowStatus(*rows[i]);
    (status == "ok" ? ok : status == "timeout" ? timeout : failed)++;
  }
  const std::string dest = out.empty() ? dirs[0] : out;
  fs::create_directories(dest);
  if (!fs::exists(fs::path(dest) / "sweep.xml")) WriteManifest(dest, manifest);
  WriteResults(dest, rows, manifest.code ? manifest.code->Fingerprint() : "");
  if (!quiet) {
    std::printf("collected %zu of %zu runs (%zu ok, %zu failed, %zu timeout) into %s/results.csv\n",
                grid.size() - missing.size(), grid.size(), ok, failed, timeout, dest.c_str());
  }
  if (missing.empty()) return 0;
  std::string list;
  for (size_t i = 0; i < missing.size() && i < 10; ++i) list += (i ? ", " : "") + missing[i];
  if (missing.size() > 10) list += ", ...";
  std::fprintf(stderr,
               "colony sweep: %zu runs have not finished (%s); run the unfinished shards again\n",
               missing.size(), list.c_str());
  return 1;
}

}  // namespace colony::sweep
