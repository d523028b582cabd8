// The Python module's native part, colony._colony (pybind11): a Simulation
// driven from Python, its robots' state and sensor readings as numpy arrays,
// and the simulator's errors as Python exceptions. The package colony
// (python/colony/__init__.py) re-exports it; docs/python.md is the user
// guide.
//
// Arrays are copies made when they are asked for (one pass over the robots,
// no Python object per robot), so they stay valid after the simulation moves
// on or is reset. Stepping releases the GIL and checks for Ctrl-C after each
// tick.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/math.h"
#include "core/simulation.h"
#include "core/state_hash.h"
#include "python/device_arrays.h"

namespace py = pybind11;

namespace {

using Array = py::array_t<double>;

// The robots alive now (entities carrying a controller), in slot order: the
// order of sim.robots and of the trajectories table.
std::vector<uint32_t> RobotSlots(const colony::Space& space) {
  std::vector<uint32_t> slots;
  for (uint32_t s = 0; s < space.slots(); ++s) {
    if (space.alive(s) && (space.flags(s) & colony::kRobot)) slots.push_back(s);
  }
  return slots;
}

// The sensor of the robot in `slot` declared with label or registered name
// `name` in its controller's <sensors>, or null.
colony::Sensor* SensorOf(const colony::Simulation& sim, uint32_t slot, const std::string& name) {
  const colony::Controller* controller = sim.ControllerOf(sim.space().HandleOf(slot));
  if (!controller || !controller->devices().labels) return nullptr;
  const colony::DeviceTable& devices = controller->devices();
  const auto i = devices.labels->SensorIndex(name);
  return i ? devices.sensors[*i] : nullptr;
}

// The registered names of every sensor some robot's controller declares, in
// the order first met.
std::vector<std::string> SensorNames(const colony::Simulation& sim) {
  std::vector<std::string> names;
  const colony::Space& space = sim.space();
  for (uint32_t slot : RobotSlots(space)) {
    const colony::Controller* controller = sim.ControllerOf(space.HandleOf(slot));
    if (!controller || !controller->devices().labels) continue;
    const colony::DeviceLabels& devices = *controller->devices().labels;
    for (size_t i = 0; i < devices.sensor_labels->size(); ++i) {
      const std::string& name = devices.SensorName(i);
      if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
    }
  }
  return names;
}

// The label of the controller kind whose robots Python drives (sim.actuators).
constexpr const char* kExternal = "external_controller";

// The actuator of the robot in `slot` declared with label or registered
// name `name` in its controller's <actuators>, or null.
colony::Actuator* ActuatorOf(const colony::Simulation& sim, uint32_t slot,
                             const std::string& name) {
  const colony::Controller* controller = sim.ControllerOf(sim.space().HandleOf(slot));
  if (!controller || !controller->devices().labels) return nullptr;
  const colony::DeviceTable& devices = controller->devices();
  const auto i = devices.labels->ActuatorIndex(name);
  return i ? devices.actuators[*i] : nullptr;
}

bool IsExternal(const colony::Simulation& sim, uint32_t slot) {
  return sim.ControllerLabelOf(sim.space().HandleOf(slot)) == kExternal;
}

// The registered names of every actuator a robot with an external controller
// declares, in the order first met.
std::vector<std::string> ActuatorNames(const colony::Simulation& sim) {
  std::vector<std::string> names;
  const colony::Space& space = sim.space();
  for (uint32_t slot : RobotSlots(space)) {
    if (!IsExternal(sim, slot)) continue;
    const colony::DeviceLabels& devices = *sim.ControllerOf(space.HandleOf(slot))->devices().labels;
    for (size_t i = 0; i < devices.actuator_labels->size(); ++i) {
      const std::string& name = devices.ActuatorName(i);
      if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
    }
  }
  return names;
}

// Actuator `name` of every robot with an external controller that carries
// it, in sim.robots order: the instances, the robots' ids and rows.
struct ExternalActuators {
  std::vector<colony::Actuator*> actuators;
  std::vector<std::string> ids;
  std::vector<int64_t> robot_index;
};

ExternalActuators FindActuators(const colony::Simulation& sim, const std::string& name) {
  ExternalActuators out;
  const colony::Space& space = sim.space();
  const std::vector<uint32_t> slots = RobotSlots(space);
  std::string driven_by;  // a robot carrying it whose own controller sets it
  for (size_t i = 0; i < slots.size(); ++i) {
    colony::Actuator* a = ActuatorOf(sim, slots[i], name);
    if (!a) continue;
    if (!IsExternal(sim, slots[i])) {
      if (driven_by.empty()) {
        driven_by = "robot '" + space.id(slots[i]) + "' runs <" +
                    sim.ControllerLabelOf(space.HandleOf(slots[i])) + ">";
      }
      continue;
    }
    out.actuators.push_back(a);
    out.ids.push_back(space.id(slots[i]));
    out.robot_index.push_back(static_cast<int64_t>(i));
  }
  if (!out.actuators.empty()) return out;
  if (!driven_by.empty()) {
    throw py::key_error("actuator '" + name +
                        "' is carried only by robots whose controllers set it themselves (" +
                        driven_by +
                        "); Python sets the actuators of robots whose controller is "
                        "an <external_controller> (docs/python.md)");
  }
  std::string there;
  for (const auto& n : ActuatorNames(sim)) there += (there.empty() ? "" : ", ") + n;
  throw py::key_error(
      "no robot with an <external_controller> carries an actuator '" + name +
      "' (actuators Python can set: " + (there.empty() ? std::string("none") : there) + ")");
}

// The readings of one sensor for every robot that carries it, as arrays:
// what the Python SensorReadings object holds.
struct SensorReadings {
  std::string name;
  std::vector<std::string> ids;
  std::vector<int64_t> robot_index;  // row in sim.robots
  py::object values;
  py::object angles = py::none();  // ring sensors: each reading's direction (rad)
  std::vector<std::string> columns;
};

SensorReadings ReadSensor(const colony::Simulation& sim, const std::string& name) {
  SensorReadings out;
  out.name = name;
  const colony::Space& space = sim.space();
  const std::vector<uint32_t> slots = RobotSlots(space);
  std::vector<colony::Sensor*> sensors;
  for (size_t i = 0; i < slots.size(); ++i) {
    colony::Sensor* s = SensorOf(sim, slots[i], name);
    if (!s) continue;
    sensors.push_back(s);
    out.ids.push_back(space.id(slots[i]));
    out.robot_index.push_back(static_cast<int64_t>(i));
  }
  if (sensors.empty()) {
    std::string there;
    for (const auto& n : SensorNames(sim)) there += (there.empty() ? "" : ", ") + n;
    throw py::key_error("no robot carries a sensor '" + name + "' (sensors carried: " +
                        (there.empty() ? std::string("none") : there) + ")");
  }
  colony::python::SensorArrays arrays;
  if (!colony::python::ReadSensorArrays(sensors, true, arrays)) {
    throw py::key_error("sensor '" + name + "' has no array form in Python yet; those that have: " +
                        colony::python::kArraySensors);
  }
  out.values = arrays.values;
  out.angles = arrays.angles;
  out.columns = std::move(arrays.columns);
  return out;
}

// Python's colony.Simulation: owns a colony::Simulation. One call at a time:
// a call from a second Python thread while one steps (the GIL released) is
// refused rather than racing.
class PySimulation {
 public:
  PySimulation(const std::string& file, std::optional<uint64_t> seed, std::optional<int> threads,
               const std::optional<py::dict>& overrides) {
    colony::ExperimentOptions options;
    options.file = file;
    options.seed = seed;
    if (threads && (*threads < 0 || *threads > 256)) {
      throw py::value_error("threads must be from 0 to 256 (0: the calling thread only), not " +
                            std::to_string(*threads));
    }
    options.threads = threads;
    if (overrides) {
      for (const auto& [key, value] : *overrides) {
        if (!py::isinstance<py::str>(key)) {
          throw py::type_error("set: keys must be str paths such as 'framework.experiment.length'");
        }
        options.overrides.push_back(key.cast<std::string>() + "=" + OverrideText(value));
      }
    }
    const Guard guard(*this);
    py::gil_scoped_release release;
    sim_ = colony::Simulation::Load(options);
  }

  void Step() {
    const Guard guard(*this);
    py::gil_scoped_release release;
    sim_->Step();
  }

  // Steps `ticks` ticks, or until the end (None), stopping early when the
  // run is done; returns the ticks stepped.
  uint64_t Run(std::optional<int64_t> ticks) {
    if (ticks && *ticks < 0) {
      throw py::value_error("run: ticks must be >= 0, not " + std::to_string(*ticks));
    }
    if (!ticks && sim_->length_ticks() == 0) {
      throw py::value_error(
          "run() with no ticks runs to the experiment's end, and this experiment has no length "
          "(<experiment length=\"0\">): give run(ticks)");
    }
    const Guard guard(*this);
    uint64_t stepped = 0;
    const uint64_t limit = ticks ? static_cast<uint64_t>(*ticks) : UINT64_MAX;
    while (stepped < limit && !sim_->Done()) {
      {
        py::gil_scoped_release release;
        sim_->Step();
      }
      ++stepped;
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    }
    return stepped;
  }

  void Reset(std::optional<uint64_t> seed) {
    const Guard guard(*this);
    py::gil_scoped_release release;
    sim_->Reset(seed);
  }

  void SetControllerParam(const std::string& id, const std::string& key, py::handle value) {
    const Guard guard(*this);
    sim_->SetControllerParam(id, key, OverrideText(value));
  }

  std::string StateHash() const {
    const Guard guard(*this);
    return colony::StateHasher::Hex(sim_->StateHash());
  }

  py::dict Metrics() const {
    const Guard guard(*this);
    py::dict out;
    const auto& columns = sim_->metrics().columns();
    const auto& values = sim_->metrics().values();
    for (size_t i = 0; i < columns.size(); ++i) out[py::str(columns[i])] = values[i];
    return out;
  }

  std::vector<std::string> RobotIds() const {
    const Guard guard(*this);
    const colony::Space& space = sim_->space();
    std::vector<std::string> ids;
    for (uint32_t s : RobotSlots(space)) ids.push_back(space.id(s));
    return ids;
  }

  std::vector<std::string> RobotTypes() const {
    const Guard guard(*this);
    const colony::Space& space = sim_->space();
    std::vector<std::string> types;
    for (uint32_t s : RobotSlots(space)) types.push_back(space.TypeLabel(space.type(s)));
    return types;
  }

  // N x 3 positions (m).
  Array Positions() const {
    return PoseArray(3, [](const colony::Pose& p, double* row) {
      for (int k = 0; k < 3; ++k) row[k] = p.position[k];
    });
  }
  // N x 4 orientations as quaternions (w, x, y, z).
  Array Orientations() const {
    return PoseArray(4, [](const colony::Pose& p, double* row) {
      row[0] = p.orientation.w();
      row[1] = p.orientation.x();
      row[2] = p.orientation.y();
      row[3] = p.orientation.z();
    });
  }
  // N yaws (rad, in (-pi, pi]).
  Array Yaw() const {
    Array a = PoseArray(
        1, [](const colony::Pose& p, double* row) { row[0] = colony::YawOf(p.orientation); });
    return a.reshape({a.shape(0)});
  }

  SensorReadings Sensor(const std::string& name) const {
    const Guard guard(*this);
    return ReadSensor(*sim_, name);
  }
  std::vector<std::string> Sensors() const {
    const Guard guard(*this);
    return SensorNames(*sim_);
  }

  // Actuator `name` of the robots with an external controller: their ids
  // and rows in sim.robots.
  std::pair<std::vector<std::string>, py::array_t<int64_t>> ActuatorRobots(
      const std::string& name) const {
    const Guard guard(*this);
    ExternalActuators found = FindActuators(*sim_, name);
    return {found.ids, py::array_t<int64_t>(static_cast<py::ssize_t>(found.robot_index.size()),
                                            found.robot_index.data())};
  }
  // Writes `command` into actuator `name` of every robot with an external
  // controller carrying it; the next tick's act phase applies it.
  void SetActuator(const std::string& name, py::handle command) {
    const Guard guard(*this);
    ExternalActuators found = FindActuators(*sim_, name);
    if (!colony::python::WriteActuatorArrays(found.actuators, found.ids, name, command)) {
      throw py::key_error(
          "actuator '" + name +
          "' takes no arrays from Python yet; those that do: " + colony::python::kArrayActuators);
    }
  }
  py::object GetActuator(const std::string& name) const {
    const Guard guard(*this);
    ExternalActuators found = FindActuators(*sim_, name);
    py::object out = colony::python::ReadActuatorArrays(found.actuators);
    if (out.is_none()) {
      throw py::key_error(
          "actuator '" + name +
          "' takes no arrays from Python yet; those that do: " + colony::python::kArrayActuators);
    }
    return out;
  }
  std::vector<std::string> Actuators() const {
    const Guard guard(*this);
    return ActuatorNames(*sim_);
  }

  const colony::Simulation& sim() const { return *sim_; }

 private:
  // Marks the simulation in use for the length of one call.
  class Guard {
   public:
    explicit Guard(const PySimulation& owner) : owner_(owner) {
      if (owner_.in_use_.exchange(true)) {
        throw std::runtime_error(
            "the simulation is in use by another Python thread (stepping, loading or resetting); "
            "call it from one thread at a time");
      }
    }
    ~Guard() { owner_.in_use_ = false; }
    Guard(const Guard&) = delete;
    Guard& operator=(const Guard&) = delete;

   private:
    const PySimulation& owner_;
  };

  // A --set or <params> value as text: str as it is, bool as true/false,
  // int and float as Python prints them. Anything else is a TypeError.
  static std::string OverrideText(py::handle value) {
    if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "true" : "false";
    if (py::isinstance<py::str>(value) || py::isinstance<py::int_>(value) ||
        py::isinstance<py::float_>(value)) {
      return py::str(value).cast<std::string>();
    }
    throw py::type_error("a value must be a str, int, float or bool, not " +
                         py::str(py::type::of(value).attr("__name__")).cast<std::string>() + " (" +
                         py::repr(value).cast<std::string>() + ")");
  }

  template <class Fill>
  Array PoseArray(size_t cols, Fill fill) const {
    const Guard guard(*this);
    const colony::Space& space = sim_->space();
    const std::vector<uint32_t> slots = RobotSlots(space);
    Array a({slots.size(), cols});
    double* data = a.mutable_data();
    for (size_t i = 0; i < slots.size(); ++i) fill(space.pose(slots[i]), data + i * cols);
    return a;
  }

  std::unique_ptr<colony::Simulation> sim_;
  mutable std::atomic<bool> in_use_{false};
};

}  // namespace

PYBIND11_MODULE(_colony, m) {
  m.doc() = "Colony's native part; use the package colony (docs/python.md).";

  // colony.Error, and below it ConfigError (bad experiment file, --set path
  // or parameter: the message names file, line, element, attribute) and
  // RuntimeFailure (a controller or loop functions failed while running).
  static py::exception<std::runtime_error> error_base(m, "Error", PyExc_RuntimeError);
  static py::exception<colony::ConfigError> config_error(m, "ConfigError", error_base.ptr());
  static py::exception<colony::RuntimeFailure> runtime_failure(m, "RuntimeFailure",
                                                               error_base.ptr());
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const colony::ConfigError& e) {
      PyErr_SetString(config_error.ptr(), e.what());
    } catch (const colony::RuntimeFailure& e) {
      PyErr_SetString(runtime_failure.ptr(), e.what());
    }
  });

  py::class_<SensorReadings>(m, "SensorReadings",
                             "The readings of one sensor for every robot carrying it, copied when "
                             "asked for (sim.sensors[name]).")
      .def_readonly("name", &SensorReadings::name)
      .def_readonly("ids", &SensorReadings::ids,
                    "ids of the robots carrying it, in sim.robots order")
      .def_property_readonly(
          "robot_index",
          [](const SensorReadings& s) {
            return py::array_t<int64_t>(s.robot_index.size(), s.robot_index.data());
          },
          "each row's index in sim.robots")
      .def_readonly("values", &SensorReadings::values,
                    "float64 array, one row per robot carrying the sensor")
      .def_readonly("angles", &SensorReadings::angles,
                    "ring sensors: each reading's direction in the robot's frame (rad), N x K; "
                    "else None")
      .def_readonly("columns", &SensorReadings::columns,
                    "what each column of values holds, for sensors that are not rings")
      .def("__len__", [](const SensorReadings& s) { return s.ids.size(); })
      .def("__repr__", [](const SensorReadings& s) {
        return "<colony.SensorReadings '" + s.name + "' of " + std::to_string(s.ids.size()) +
               " robots>";
      });

  py::class_<PySimulation>(m, "Simulation")
      .def(py::init<const std::string&, std::optional<uint64_t>, std::optional<int>,
                    const std::optional<py::dict>&>(),
           py::arg("file"), py::kw_only(), py::arg("seed") = py::none(),
           py::arg("threads") = py::none(), py::arg("set") = py::none())
      .def("step", &PySimulation::Step, "One tick (the GIL is released while it runs).")
      .def("run", &PySimulation::Run, py::arg("ticks") = py::none(),
           "Steps `ticks` ticks, or to the end (None), stopping early when done; returns the "
           "ticks stepped.")
      .def("reset", &PySimulation::Reset, py::arg("seed") = py::none(),
           "Back to tick 0 as a fresh load with `seed` (None: the seed it has) gives, without "
           "reading the file or loading plugins again.")
      .def("set_controller_param", &PySimulation::SetControllerParam, py::arg("controller_id"),
           py::arg("key"), py::arg("value"),
           "Sets a <params> value of controller configuration `controller_id` for the "
           "controllers the next reset() builds.")
      .def("state_hash", &PySimulation::StateHash,
           "The state hash as `colony run` prints it (16 hex digits).")
      .def_property_readonly("tick", [](const PySimulation& s) { return s.sim().tick(); })
      .def_property_readonly("done", [](const PySimulation& s) { return s.sim().Done(); })
      .def_property_readonly("time", [](const PySimulation& s) { return s.sim().time(); })
      .def_property_readonly("dt", [](const PySimulation& s) { return s.sim().dt(); })
      .def_property_readonly("length", [](const PySimulation& s) { return s.sim().length_ticks(); })
      .def_property_readonly("seed", [](const PySimulation& s) { return s.sim().seed(); })
      .def_property_readonly("threads", [](const PySimulation& s) { return s.sim().threads(); })
      .def_property_readonly("file", [](const PySimulation& s) { return s.sim().file(); })
      .def_property_readonly("robot_count",
                             [](const PySimulation& s) { return s.sim().robot_count(); })
      .def_property_readonly("metrics", &PySimulation::Metrics)
      .def("_robot_ids", &PySimulation::RobotIds)
      .def("_robot_types", &PySimulation::RobotTypes)
      .def("_positions", &PySimulation::Positions)
      .def("_orientations", &PySimulation::Orientations)
      .def("_yaw", &PySimulation::Yaw)
      .def("_sensor", &PySimulation::Sensor, py::arg("name"))
      .def("_sensor_names", &PySimulation::Sensors)
      .def("_actuator_robots", &PySimulation::ActuatorRobots, py::arg("name"))
      .def("_set_actuator", &PySimulation::SetActuator, py::arg("name"), py::arg("command"))
      .def("_get_actuator", &PySimulation::GetActuator, py::arg("name"))
      .def("_actuator_names", &PySimulation::Actuators);
}
