// Rows and tables: a finished run's row (row.csv in its folder), results.csv,
// and --collect.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "apps/colony/sweep.h"
#include "core/output.h"

namespace colony::sweep {

namespace fs = std::filesystem;

namespace {

// Columns from summary.json, in this order, after the fixed ones.
constexpr const char* kSummaryColumns[] = {
    "ticks",        "simulated_seconds",      "robots",
    "step_seconds", "robot_steps_per_second", "final_state_hash"};

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

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

// The header and last complete row of metrics.csv, if it has one.
std::optional<std::pair<std::vector<std::string>, std::vector<std::string>>> LastMetricsRow(
    const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string header_line;
  if (!std::getline(in, header_line)) return std::nullopt;
  const auto header = ParseCsvLine(header_line);
  // Only the tail is read: the last row is in it, the file may be long.
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  const std::streamoff start =
      std::max<std::streamoff>(static_cast<std::streamoff>(header_line.size()) + 1, size - 65536);
  in.seekg(start);
  std::string tail(static_cast<size_t>(std::max<std::streamoff>(0, size - start)), '\0');
  in.read(tail.data(), static_cast<std::streamsize>(tail.size()));
  // Complete lines only (a killed run may have left half a line), last first.
  std::vector<std::string> lines;
  std::istringstream s(tail);
  for (std::string line; std::getline(s, line);) lines.push_back(line);
  if (!tail.empty() && tail.back() != '\n' && !lines.empty()) lines.pop_back();
  for (size_t i = lines.size(); i-- > 0;) {
    auto fields = ParseCsvLine(lines[i]);
    if (fields.size() == header.size()) return std::make_pair(header, fields);
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

// Appends a loop-functions metric, prefixed "metrics." if its name is taken.
void AddMetric(Row& row, const std::string& name, const std::string& value) {
  for (const auto& [c, v] : row) {
    if (c == name) {
      row.emplace_back("metrics." + name, value);
      return;
    }
  }
  row.emplace_back(name, value);
}

// What the run left: summary.json when it completed, else the last row of
// metrics.csv (how far it got).
void AddRunOutput(Row& row, const fs::path& run_dir, bool completed) {
  for (const char* c : kSummaryColumns) row.emplace_back(c, "");
  if (completed) {
    // MakeRow has checked that it parses and has every key.
    const auto summary = nlohmann::ordered_json::parse(ReadText(run_dir / "summary.json"));
    for (const char* c : kSummaryColumns) {
      if (summary.contains(c)) Set(row, c, FieldText(summary[c]));
    }
    for (const auto& [name, value] : summary["metrics"].items())
      AddMetric(row, name, FieldText(value));
    return;
  }
  const auto last = LastMetricsRow(run_dir / "metrics.csv");
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
    const std::string& f = fields[i];
    if (f.find_first_of(",\"\r\n") == std::string::npos) {
      line += f;
      continue;
    }
    line += '"';
    for (char c : f) line += c == '"' ? std::string("\"\"") : std::string(1, c);
    line += '"';
  }
  return line;
}

std::vector<std::string> ParseCsvLine(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
      fields.back() += '"';
      ++i;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      fields.emplace_back();
    } else if (c != '\r' || quoted) {
      fields.back() += c;
    }
  }
  return fields;
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

Row MakeRow(const Grid& grid, const RunSpec& run, const RunEnd& end, const std::string& run_dir) {
  RunEnd result = end;
  // Finished means a summary that parses, has every key and says completed.
  const fs::path summary_file = fs::path(run_dir) / "summary.json";
  const std::string problem = fs::exists(summary_file) ? SummaryProblem(ReadText(summary_file))
                                                       : "there is no summary.json";
  const bool completed = problem.empty();
  if (result.status == RunEnd::Status::kOk && !completed) {
    result = {RunEnd::Status::kFailed, end.wall_seconds,
              "exited with status 0 but is not a finished run: " + problem};
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
  AddRunOutput(row, run_dir, completed && result.status == RunEnd::Status::kOk);
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
  std::ifstream in(fs::path(run_dir) / "row.csv");
  std::string header_line, values_line;
  if (!std::getline(in, header_line) || !std::getline(in, values_line)) return std::nullopt;
  const auto header = ParseCsvLine(header_line), values = ParseCsvLine(values_line);
  if (header.size() != values.size()) return std::nullopt;
  Row row;
  for (size_t i = 0; i < header.size(); ++i) row.emplace_back(header[i], values[i]);
  return row;
}

std::string RowStatus(const Row& row) {
  for (const auto& [c, v] : row) {
    if (c == "status") return v;
  }
  return "";
}

std::vector<std::optional<Row>> ReadRows(const std::string& dir, const Grid& grid) {
  std::vector<std::optional<Row>> rows(grid.size());
  for (size_t i = 0; i < rows.size(); ++i) rows[i] = ReadRow(RunDir(dir, RunAt(grid, i)));
  return rows;
}

void WriteResults(const std::string& dir, const std::vector<std::optional<Row>>& rows) {
  // Columns: every row's, in order of first appearance; detail last.
  std::vector<std::string> header;
  for (const auto& row : rows) {
    if (!row) continue;
    for (const auto& [c, v] : *row) {
      if (c != "detail" && std::find(header.begin(), header.end(), c) == header.end()) {
        header.push_back(c);
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
    text += CsvLine(fields) + "\n";
  }
  WriteAtomically((fs::path(dir) / "results.csv").string(), text);
}

int Collect(const std::vector<std::string>& dirs, const std::string& out, bool quiet) {
  const Grid grid = ReadManifest(dirs[0]);
  for (size_t d = 1; d < dirs.size(); ++d) {
    const std::string why = GridDifference(ReadManifest(dirs[d]), grid);
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
  if (!fs::exists(fs::path(dest) / "sweep.xml")) WriteManifest(dest, grid);
  WriteResults(dest, rows);
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
