// `colony view RUN_FOLDER`: a replay of a recorded run, served to the live
// viewer's page. The scene is the folder's experiment.xml, loaded and never
// stepped; at each recorded tick the robots' poses from its trajectories
// table are put into that simulation's space, and the server (viewer.cpp)
// draws the scene and frames from it as it does for a live run.
#include <zlib.h>

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <stdexcept>

#include "apps/colony/command_line.h"
#include "apps/colony/sweep.h"
#include "apps/colony/viewer/frame_source.h"
#include "apps/colony/viewer/viewer.h"
#include "core/crash_report.h"
#include "core/error.h"
#include "core/log.h"
#include "core/math.h"
#include "core/simulation.h"
#include "core/table_formats.h"
#include "core/trajectories.h"

namespace colony {
namespace {

namespace fs = std::filesystem;

// One robot's recorded pose (the trajectories table's columns).
struct RecordedPose {
  uint64_t tick = 0;
  std::string id;
  double x = 0, y = 0, z = 0, yaw = 0, pitch = 0, roll = 0;
  double led[3] = {0, 0, 0};  // the colour it showed (led_r, led_g, led_b)
};

// The table read into poses, in the file's order.
struct RecordedTable {
  std::vector<RecordedPose> rows;
  bool three_d = false;  // pitch and roll columns
  bool leds = false;     // led_r, led_g and led_b columns
};

[[noreturn]] void Bad(const std::string& file, const std::string& problem) {
  throw ConfigError(file + ": " + problem);
}

constexpr const char* kLedColumns[3] = {"led_r", "led_g", "led_b"};

// Whether a table has the LED columns (all three, or none: else it is bad).
bool HasLeds(const std::string& path, const std::array<bool, 3>& present) {
  if (present[0] && present[1] && present[2]) return true;
  if (present[0] || present[1] || present[2]) {
    Bad(path, "has some of the columns led_r, led_g, led_b but not all three");
  }
  return false;
}

// --- CSV (trajectories.csv, trajectories.csv.gz) ----------------------------

std::string ReadGzip(const std::string& path) {
  gzFile in = gzopen(path.c_str(), "rb");
  if (!in) Bad(path, std::string("cannot read it (") + std::strerror(errno) + ")");
  std::string text;
  char buffer[1 << 16];
  int n = 0;
  while ((n = gzread(in, buffer, sizeof buffer)) > 0) text.append(buffer, n);
  int code = Z_OK;
  const std::string problem = n < 0 || !gzeof(in) ? gzerror(in, &code) : "";
  gzclose(in);
  if (n < 0 || !problem.empty()) Bad(path, "not a whole gzip file (" + problem + ")");
  return text;
}

// The number in CSV field `text`; `what` names it for the message.
double CsvNumber(const std::string& path, size_t line, const std::string& column,
                 const std::string& text) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(value)) {
    Bad(path,
        "line " + std::to_string(line) + ": " + column + " '" + text + "' is not a finite number");
  }
  return value;
}

RecordedTable ReadCsvTable(const std::string& path, bool gzip) {
  sweep::CsvTable csv;
  try {
    csv = gzip ? sweep::ParseCsv(ReadGzip(path), path) : sweep::ReadCsvFile(path);
  } catch (const sweep::UsageError& e) {
    throw ConfigError(e.what());
  }
  if (csv.cut_line != 0) {
    Bad(path, "cut short at line " + std::to_string(csv.cut_line) +
                  " (its last row has no line end: a run killed while writing?)");
  }
  if (csv.records.empty()) Bad(path, "empty: no header");
  const std::vector<std::string>& header = csv.records[0];
  auto column = [&](const std::string& name, bool needed) -> int {
    for (size_t i = 0; i < header.size(); ++i) {
      if (header[i] == name) return static_cast<int>(i);
    }
    if (needed) {
      Bad(path, "no column '" + name +
                    "': not a trajectories table (tick, time, id, type, x, y, z, yaw...)");
    }
    return -1;
  };
  const int tick = column("tick", true), id = column("id", true), x = column("x", true),
            y = column("y", true), z = column("z", true), yaw = column("yaw", true),
            pitch = column("pitch", false), roll = column("roll", false);
  const int led[3] = {column("led_r", false), column("led_g", false), column("led_b", false)};
  RecordedTable table;
  table.three_d = pitch >= 0 && roll >= 0;
  table.leds = HasLeds(path, {led[0] >= 0, led[1] >= 0, led[2] >= 0});
  for (size_t r = 1; r < csv.records.size(); ++r) {
    const auto& record = csv.records[r];
    const size_t line = r + 1;
    if (record.size() != header.size()) {
      Bad(path, "line " + std::to_string(line) + " has " + std::to_string(record.size()) +
                    " fields, the header " + std::to_string(header.size()));
    }
    RecordedPose pose;
    const std::string& t = record[tick];
    if (t.empty() || t.size() > 19 || t.find_first_not_of("0123456789") != std::string::npos) {
      Bad(path, "line " + std::to_string(line) + ": tick '" + t + "' is not a whole number");
    }
    pose.tick = std::stoull(t);
    pose.id = record[id];
    pose.x = CsvNumber(path, line, "x", record[x]);
    pose.y = CsvNumber(path, line, "y", record[y]);
    pose.z = CsvNumber(path, line, "z", record[z]);
    pose.yaw = CsvNumber(path, line, "yaw", record[yaw]);
    if (table.three_d) {
      pose.pitch = CsvNumber(path, line, "pitch", record[pitch]);
      pose.roll = CsvNumber(path, line, "roll", record[roll]);
    }
    for (int k = 0; table.leds && k < 3; ++k)
      pose.led[k] = CsvNumber(path, line, kLedColumns[k], record[led[k]]);
    table.rows.push_back(std::move(pose));
  }
  return table;
}

// --- HDF5 (trajectories.h5) ---------------------------------------------------

// Through the HDF5 plugin (core/table_formats.h), loaded here on first use.
RecordedTable ReadHdf5Table(const std::string& path) {
  using enum ColumnType;
  const std::vector<TableColumn> wanted = {{"tick", kInteger}, {"id", kText},     {"x", kNumber},
                                           {"y", kNumber},     {"z", kNumber},    {"yaw", kNumber},
                                           {"pitch", kNumber}, {"roll", kNumber}, {kLedColumns[0]},
                                           {kLedColumns[1]},   {kLedColumns[2]}};
  enum { kTick, kId, kX, kY, kZ, kYaw, kPitch, kRoll, kLed };
  std::vector<Hdf5Column> columns;
  size_t n = 0;
  try {
    n = Hdf5().read_columns(path, "trajectories", wanted, columns);
  } catch (const RuntimeFailure& e) {
    Bad(path, e.what());
  }
  for (int c = kTick; c <= kYaw; ++c) {
    if (!columns[c].present) {
      Bad(path, "dataset 'trajectories' has no column '" + wanted[c].name +
                    "' (docs/data-output.md, HDF5 layout)");
    }
  }
  RecordedTable table;
  table.three_d = columns[kPitch].present && columns[kRoll].present;
  table.leds =
      HasLeds(path, {columns[kLed].present, columns[kLed + 1].present, columns[kLed + 2].present});
  table.rows.resize(n);
  for (size_t r = 0; r < n; ++r) {
    RecordedPose& pose = table.rows[r];
    const int64_t tick = columns[kTick].integers[r];
    if (tick < 0) Bad(path, "row " + std::to_string(r) + ": tick " + std::to_string(tick));
    pose.tick = static_cast<uint64_t>(tick);
    pose.id = std::move(columns[kId].texts[r]);
    pose.x = columns[kX].numbers[r];
    pose.y = columns[kY].numbers[r];
    pose.z = columns[kZ].numbers[r];
    pose.yaw = columns[kYaw].numbers[r];
    if (table.three_d) {
      pose.pitch = columns[kPitch].numbers[r];
      pose.roll = columns[kRoll].numbers[r];
    }
    for (int k = 0; table.leds && k < 3; ++k) pose.led[k] = columns[kLed + k].numbers[r];
    if (!std::isfinite(pose.x) || !std::isfinite(pose.y) || !std::isfinite(pose.z) ||
        !std::isfinite(pose.yaw) || !std::isfinite(pose.pitch) || !std::isfinite(pose.roll)) {
      Bad(path, "row " + std::to_string(r) + " (robot '" + pose.id + "', tick " +
                    std::to_string(pose.tick) + "): a pose that is not finite");
    }
  }
  return table;
}

// --- The replay -------------------------------------------------------------

// The recorded ticks of a run, shown by putting their poses into `sim`'s
// space (never stepped).
class ReplaySource : public FrameSource {
 public:
  // Checks `table` against `sim`'s robots; throws ConfigError naming `file`.
  ReplaySource(Simulation& sim, const RecordedTable& table, const std::string& file) : sim_(sim) {
    if (table.rows.empty()) Bad(file, "holds no rows (a run that recorded nothing?)");
    const Space& space = sim.space();
    for (size_t r = 0; r < table.rows.size(); ++r) {
      const RecordedPose& p = table.rows[r];
      const EntityHandle h = space.Find(p.id);
      if (!h.valid() || !space.IsAlive(h) || !space.movable(h.index)) {
        Bad(file, "robot '" + p.id + "' (tick " + std::to_string(p.tick) +
                      ") is not in the run's experiment.xml: the table is not this run's, or "
                      "the robot was added while running (replays show the experiment's "
                      "robots only)");
      }
      if (records_.empty() || records_.back().tick != p.tick) {
        if (!records_.empty() && p.tick < records_.back().tick) {
          Bad(file, "tick " + std::to_string(p.tick) + " comes after tick " +
                        std::to_string(records_.back().tick) + ": ticks must not go back");
        }
        records_.push_back({p.tick, r, r});
      }
      ++records_.back().end;
      Pose pose = space.pose(h.index);
      pose.position = Vec3(p.x, p.y, p.z);
      pose.orientation = table.three_d ? FromEulerZYX(p.yaw, p.pitch, p.roll) : FromYaw(p.yaw);
      poses_.push_back({h.index, pose});
      if (table.leds) colors_.push_back(RecordedColor(file, p));
    }
    Show(0);
  }

  uint64_t tick() const override { return records_[shown_].tick; }
  uint64_t next_tick() const override {
    return records_[std::min(shown_ + 1, records_.size() - 1)].tick;
  }
  bool Done() const override { return shown_ + 1 >= records_.size(); }
  void Step() override { Show(shown_ + 1); }
  void Reset(std::optional<uint64_t> seed) override {
    if (seed && *seed != sim_.seed()) {
      throw RuntimeFailure("a replay shows the recorded run (seed " + std::to_string(sim_.seed()) +
                           "); to run with seed " + std::to_string(*seed) +
                           ", serve the experiment live: colony run " + sim_.file() +
                           " --serve PORT --seed " + std::to_string(*seed));
    }
    Show(0);
  }
  std::string Refuses(const std::string& command) const override {
    return command +
           ": this is a replay of recorded poses (colony view); the run's sensors, "
           "controllers and physics are not there to " +
           (command == "move"   ? "move robots in"
            : command == "rays" ? "cast rays"
                                : "inspect") +
           ": serve the experiment live with colony run " + sim_.file() + " --serve PORT";
  }
  bool replay() const override { return true; }

 private:
  struct Record {
    uint64_t tick;
    size_t begin, end;  // its rows in poses_
  };
  // The LED colour of row `p` (led_r, led_g, led_b); throws ConfigError
  // naming `file` for a channel that is not a whole number from 0 to 255.
  static Color RecordedColor(const std::string& file, const RecordedPose& p) {
    uint8_t channel[3];
    for (int k = 0; k < 3; ++k) {
      if (!(p.led[k] >= 0 && p.led[k] <= 255 && p.led[k] == std::floor(p.led[k]))) {
        Bad(file, "robot '" + p.id + "' (tick " + std::to_string(p.tick) + "): " + kLedColumns[k] +
                      " " + std::to_string(p.led[k]) +
                      " is not a colour channel (a whole number from 0 to 255)");
      }
      channel[k] = static_cast<uint8_t>(p.led[k]);
    }
    return Color{channel[0], channel[1], channel[2], 255};
  }

  // Puts record `record`'s poses (and LED colours, when recorded: every LED
  // of the robot shows the colour recorded) into the space.
  void Show(size_t record) {
    shown_ = record;
    Space& space = sim_.space();
    for (size_t i = records_[record].begin; i < records_[record].end; ++i) {
      space.pose(poses_[i].first) = poses_[i].second;
      if (!colors_.empty()) {
        for (Color& led : space.leds(poses_[i].first)) led = colors_[i];
      }
    }
  }

  Simulation& sim_;
  std::vector<Record> records_;
  std::vector<std::pair<uint32_t, Pose>> poses_;  // per row: the slot and its pose
  std::vector<Color> colors_;                     // per row, when LEDs were recorded
  size_t shown_ = 0;
};

// The folder's trajectories file: the one its experiment names, else any.
std::string TrajectoriesFile(const fs::path& folder, const OutputConfig& output) {
  std::error_code ec;
  const fs::path named = folder / Trajectories::FileName(output);
  if (fs::is_regular_file(named, ec)) return named.string();
  for (const char* name : {"trajectories.h5", "trajectories.csv", "trajectories.csv.gz"}) {
    if (fs::is_regular_file(folder / name, ec)) return (folder / name).string();
  }
  throw ConfigError(folder.string() +
                    " has no trajectories (trajectories.csv, trajectories.csv.gz or "
                    "trajectories.h5) to replay: record them with <output "
                    "trajectories_every=\"K\"/> in the experiment, or colony run FILE --set "
                    "output.trajectories_every=K");
}

}  // namespace

int ServeReplay(const std::string& run_folder, const ServeOptions& options) {
  const fs::path folder(run_folder);
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) throw ConfigError(run_folder + " is not a folder");
  if (!fs::is_regular_file(folder / "experiment.xml", ec)) {
    throw ConfigError(run_folder +
                      " is not a run folder: it has no experiment.xml (colony run writes one "
                      "into every run folder)");
  }
  ExperimentOptions load;
  load.file = (folder / "experiment.xml").string();
  const auto sim = Simulation::Load(load);
  const std::string file = TrajectoriesFile(folder, sim->output());
  const bool h5 = file.size() > 3 && file.compare(file.size() - 3, 3, ".h5") == 0;
  const bool gzip = file.size() > 3 && file.compare(file.size() - 3, 3, ".gz") == 0;
  ReplaySource replay(*sim, h5 ? ReadHdf5Table(file) : ReadCsvTable(file, gzip), file);
  LogInfo("viewer: replaying " + file);
  return ServeFrames(*sim, replay, options);
}

int ViewCommand(const std::vector<std::string>& args) {
  CLI::App app{
      "serves a replay of a finished run from its recorded trajectories to the live "
      "viewer's page",
      "colony view"};
  cli::SetUpHelp(app);
  app.allow_extras();
  std::string folder, serve = "8080";
  app.add_option("RUN_FOLDER", folder,
                 "a run folder (colony run --out) with experiment.xml and trajectories.csv, "
                 "trajectories.csv.gz or trajectories.h5 (<output trajectories_every=\"K\"/>)");
  app.add_option("--serve", serve,
                 "where the viewer listens (default 8080, on 127.0.0.1; another address needs "
                 "the printed URL's token)")
      ->type_name("[HOST:]PORT");
  app.footer(
      "Example:\n"
      "  colony run experiments/diffusion.xml --out runs/d --set output.trajectories_every=5\n"
      "  colony view runs/d\n"
      "Exit status: 0 ended from the page, 2 bad input, 1 cannot serve.");
  try {
    try {
      if (!cli::Parse(app, args)) return 0;
      if (!app.remaining().empty()) {
        throw cli::UsageError("one run folder only, not also '" + app.remaining()[0] + "'");
      }
      if (folder.empty()) throw cli::UsageError("colony view needs a run folder");
    } catch (const cli::UsageError& e) {
      std::fprintf(stderr, "colony: %s\nrun 'colony view --help' for usage\n", e.what());
      return 2;
    }
    ServeOptions options;
    try {
      ParseServeAddress(serve, options);
    } catch (const std::invalid_argument& e) {
      std::fprintf(stderr, "colony: --serve %s\nrun 'colony view --help' for usage\n", e.what());
      return 2;
    }
    InstallStopHandlers();
    options.on_listening = [&folder](const std::string& url) {
      std::printf("viewer: open %s in a browser (replay of %s, paused; Ctrl-C ends it)\n",
                  url.c_str(), folder.c_str());
      std::fflush(stdout);
    };
    return ServeReplay(folder, options);
  } catch (const ConfigError& e) {
    for (const auto& d : e.diagnostics()) LogError(d.ToString());
    return 2;
  } catch (const std::exception& e) {
    LogError(std::string("view failed: ") + e.what());
    return 1;
  }
}

}  // namespace colony
