#include "core/trajectories.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/crash_report.h"
#include "core/entity_type.h"
#include "core/error.h"
#include "core/registry.h"
#include "core/simulation.h"
#include "core/text.h"

namespace colony {

namespace {

// The table's own columns, before the robots' values.
const std::vector<std::string>& OwnColumns() {
  static const std::vector<std::string> columns = {"tick",  "time",  "id",   "type",  "x",
                                                   "y",     "z",     "yaw",  "pitch", "roll",
                                                   "led_r", "led_g", "led_b"};
  return columns;
}

// A value that cannot be a column (thrown through the plugin's code as no
// std::exception, so that a plugin catching those does not swallow it).
struct ValueError {
  std::string message;
  bool at_load;  // found at the first record: a ConfigError
};

}  // namespace

// The values of the robot being recorded, per column of robot values: its
// number or label and who gave it (null: none yet).
class Trajectories::Values final : public RobotValues {
 public:
  struct Column {
    std::string name;
    bool label = false;
  };
  struct Row {
    std::vector<double> numbers;
    std::vector<std::string> labels;
    std::vector<const std::string*> given_by;
  };

  void Set(std::string_view name, double value) override { row.numbers[Slot(name, false)] = value; }
  void SetLabel(std::string_view name, std::string_view label) override {
    row.labels[Slot(name, true)].assign(label);
  }

  // Ready for the next robot.
  void Clear(const std::string& robot_id) {
    std::fill(row.given_by.begin(), row.given_by.end(), nullptr);
    robot = &robot_id;
    next = 0;
  }

  std::vector<Column> columns;
  Row row;
  bool frozen = false;                  // the columns are fixed (after the first record)
  const std::string* source = nullptr;  // who is giving values: "controller 'x'"
  const std::string* robot = nullptr;   // the robot's id
  uint64_t tick = 0;

 private:
  // The column of value `name`, added while not frozen; checks that it may
  // be given.
  size_t Slot(std::string_view name, bool label) {
    size_t c = next < columns.size() && columns[next].name == name ? next : columns.size();
    for (size_t i = 0; c == columns.size() && i < columns.size(); ++i) {
      if (columns[i].name == name) c = i;
    }
    if (c == columns.size()) Add(name, label);
    if (columns[c].label != label) {
      Fail(*source + " gives robot '" + *robot + "' the value '" + std::string(name) + "' as a " +
           (label ? "label" : "number") + "; the column is one of " +
           (columns[c].label ? "labels" : "numbers") +
           " (fixed where it first appeared): give it the same kind of value everywhere");
    }
    if (const std::string* before = row.given_by[c]) {
      Fail(*source + " gives robot '" + *robot + "' the value '" + std::string(name) + "' twice" +
           (before == source ? "" : " (" + *before + " gave it first)") +
           "; give each value once, under its own name");
    }
    row.given_by[c] = source;
    next = c + 1;
    return c;
  }

  void Add(std::string_view name, bool label) {
    const std::string text(name);
    if (frozen) {
      Fail(*source + " gives robot '" + *robot + "' the value '" + text +
           "', which is not a column of the trajectories table: its columns were fixed at its "
           "first record; give every value from the first record on (a NaN or an empty label "
           "where there is none yet)");
    }
    if (text.empty()) Fail(*source + " gives robot '" + *robot + "' a value with no name");
    const auto& own = OwnColumns();
    if (std::find(own.begin(), own.end(), text) != own.end()) {
      Fail(*source + " gives the value '" + text +
           "', the name of one of the trajectories table's own columns (" + Join(own) +
           "); rename it");
    }
    columns.push_back({text, label});
    row.numbers.push_back(0);
    row.labels.emplace_back();
    row.given_by.push_back(nullptr);
  }

  [[noreturn]] void Fail(const std::string& message) {
    if (!frozen) throw ValueError{message, true};
    throw ValueError{message + " (at tick " + std::to_string(tick) + ")", false};
  }

  size_t next = 0;  // the column the next value most likely goes to
};

std::string Trajectories::FileName(const OutputConfig& output) {
  if (output.trajectories_format == OutputConfig::Format::kHdf5) return "trajectories.h5";
  return output.trajectories_gzip ? "trajectories.csv.gz" : "trajectories.csv";
}

Trajectories::Trajectories(const std::string& dir, const Simulation& sim)
    : path_((std::filesystem::path(dir) / FileName(sim.output())).string()),
      output_(sim.output()),
      values_(std::make_unique<Values>()) {
  for (const auto& engine : sim.engines()) three_d_ = three_d_ || engine->Is3D();
}

Trajectories::~Trajectories() = default;

void Trajectories::Ask(Simulation& sim, uint32_t slot) {
  const Space& space = sim.space();
  const EntityHandle robot = space.HandleOf(slot);
  Values& values = *values_;
  values.Clear(space.id(slot));
  // Calls `give` (a plugin's hook), naming `who` and `hook` in what it throws.
  auto ask = [&](const std::string& who, const char* hook, auto&& give) {
    try {
      give();
    } catch (const ValueError& e) {
      if (e.at_load) throw ConfigError(e.message);
      throw RuntimeFailure(e.message);
    } catch (const std::exception& e) {
      throw RuntimeFailure(who + " failed in " + hook + " for robot '" + space.id(slot) +
                           "' at tick " + std::to_string(sim.tick()) + ": " + e.what());
    } catch (...) {
      throw RuntimeFailure(who + " failed in " + hook + " for robot '" + space.id(slot) +
                           "' at tick " + std::to_string(sim.tick()) +
                           ": it threw something that is not a std::exception");
    }
  };
  if (const Controller* controller = sim.ControllerOf(robot)) {
    const std::string& label = sim.ControllerLabelOf(robot);
    auto known = std::find_if(controller_sources_.begin(), controller_sources_.end(),
                              [&](const auto& s) { return s.first == &label; });
    if (known == controller_sources_.end()) {
      controller_sources_.emplace_back(&label, "controller '" + label + "'");
      known = controller_sources_.end() - 1;
    }
    values.source = &known->second;
    const RunningScope running({"controller", label.c_str(), sim.ControllerLibraryOf(robot),
                                space.id(slot).c_str(), sim.tick()});
    ask(known->second, "RecordValues", [&] { controller->RecordValues(values); });
  }
  for (size_t i = 0; i < sim.loop_functions_count(); ++i) {
    const PluginInfo& info = sim.loop_functions_info(i);
    if (loop_sources_.size() <= i) loop_sources_.push_back("loop functions '" + info.label + "'");
    values.source = &loop_sources_[i];
    const RunningScope running({"loop functions", info.label.c_str(),
                                info.library.empty() ? nullptr : info.library.c_str(),
                                space.id(slot).c_str(), sim.tick()});
    ask(loop_sources_[i], "RecordRobotValues",
        [&] { sim.loop_functions(i).RecordRobotValues(robot, values); });
  }
}

void Trajectories::Open(const Simulation& sim, size_t longest_id) {
  // HDF5 keeps ids and types in fixed-width strings (a third of the size
  // of variable-length ones, and read without a Python object per cell):
  // a type in that of the longest registered entity type, an id in the
  // longest id of the first record plus 8 bytes, for robots added later.
  if (output_.trajectories_format == OutputConfig::Format::kHdf5) {
    size_t longest_type = 1;
    for (const auto& label : Registry<EntityType>::Get().Labels())
      longest_type = std::max(longest_type, label.size());
    type_width_ = (longest_type + 7) / 8 * 8;
    id_width_ = (longest_id + 8 + 7) / 8 * 8;
  }
  std::vector<TableColumn> columns = {{"tick", ColumnType::kInteger},
                                      {"time", ColumnType::kNumber, 15},
                                      {"id", ColumnType::kText, 0, id_width_},
                                      {"type", ColumnType::kText, 0, type_width_}};
  for (const char* name : {"x", "y", "z", "yaw"}) columns.push_back({name, ColumnType::kNumber});
  if (three_d_) {
    for (const char* name : {"pitch", "roll"}) columns.push_back({name, ColumnType::kNumber});
  }
  if (output_.trajectories_leds) {
    for (const char* name : {"led_r", "led_g", "led_b"})
      columns.push_back({name, ColumnType::kNumber});
  }
  for (const auto& c : values_->columns)
    columns.push_back({c.name, c.label ? ColumnType::kText : ColumnType::kNumber});
  TableOptions options;
  options.compress =
      output_.trajectories_gzip && output_.trajectories_format == OutputConfig::Format::kHdf5;
  table_ = Table::Create(path_, std::move(columns), options);
  values_->frozen = true;
}

void Trajectories::WriteRow(const Simulation& sim, uint32_t slot) {
  const Space& space = sim.space();
  const Pose& pose = space.pose(slot);
  const Quat& q = pose.orientation;
  if (id_width_ > 0 && space.id(slot).size() > id_width_) {
    throw RuntimeFailure("robot '" + space.id(slot) + "' has an id of " +
                         std::to_string(space.id(slot).size()) + " bytes, more than the " +
                         std::to_string(id_width_) + " of " + path_ +
                         "'s id column (the longest id at its first record plus 8); give robots "
                         "added while running shorter ids, or write the trajectories as CSV");
  }
  table_.Integer(static_cast<int64_t>(sim.tick()))
      .Number(sim.time())
      .Text(space.id(slot))
      .Text(space.TypeLabel(space.type(slot)))
      .Number(pose.position.x())
      .Number(pose.position.y())
      .Number(pose.position.z())
      .Number(YawOf(q));
  if (three_d_) {
    // Z-Y-X Euler angles, as the experiment files give orientations.
    const double sin_pitch = 2.0 * (q.w() * q.y() - q.z() * q.x());
    table_.Number(std::asin(std::clamp(sin_pitch, -1.0, 1.0)))
        .Number(std::atan2(2.0 * (q.w() * q.x() + q.y() * q.z()),
                           1.0 - 2.0 * (q.x() * q.x() + q.y() * q.y())));
  }
  if (output_.trajectories_leds) {
    const auto leds = space.leds(slot);
    const Color c = leds.empty() ? space.color(slot) : leds[0];
    table_.Number(c.r).Number(c.g).Number(c.b);
  }
  const Values& values = *values_;
  for (size_t c = 0; c < values.columns.size(); ++c) {
    if (!values.row.given_by[c]) {
      table_.Missing();
    } else if (values.columns[c].label) {
      table_.Text(values.row.labels[c]);
    } else {
      table_.Number(values.row.numbers[c]);
    }
  }
  table_.EndRow();
}

void Trajectories::Record(Simulation& sim) {
  const Space& space = sim.space();
  values_->tick = sim.tick();
  auto is_robot = [&](uint32_t s) { return space.alive(s) && (space.flags(s) & kRobot); };
  if (values_->frozen) {
    for (uint32_t s = 0; s < space.slots(); ++s) {
      if (!is_robot(s)) continue;
      Ask(sim, s);
      WriteRow(sim, s);
    }
    return;
  }
  // The first record: every robot's values are gathered before the columns
  // they make are fixed and the rows written.
  std::vector<uint32_t> slots;
  std::vector<Values::Row> rows;
  size_t longest_id = 0;
  for (uint32_t s = 0; s < space.slots(); ++s) {
    if (!is_robot(s)) continue;
    Ask(sim, s);
    slots.push_back(s);
    rows.push_back(values_->row);
    longest_id = std::max(longest_id, space.id(s).size());
  }
  Open(sim, longest_id);
  const size_t width = values_->columns.size();
  for (size_t i = 0; i < slots.size(); ++i) {
    Values::Row& row = rows[i];
    row.numbers.resize(width, 0);
    row.labels.resize(width);
    row.given_by.resize(width, nullptr);
    values_->row = std::move(row);
    WriteRow(sim, slots[i]);
  }
  values_->row.given_by.assign(width, nullptr);
}

void Trajectories::Close() {
  if (!values_->frozen) return;  // never recorded
  table_.Close();
}

}  // namespace colony
