// The control interface: everything a robot's program sees. It includes
// nothing from the simulator, so a controller written against it can be
// compiled for a real robot with another implementation of the same sensor
// and actuator classes.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "core/random.h"

namespace colony {

class Sensor;

// Events (docs/events.md): a controller asks a sensor to tell it when a
// reading crosses a threshold, instead of reading it every step.

// Which way a reading must cross the threshold to emit an event.
enum class Crossing {
  kRising,   // from below the threshold to at or above it
  kFalling,  // from at or above it to below threshold - hysteresis
  kBoth,
};

// What Sensor::Watch is asked to watch.
struct ThresholdWatch {
  int reading = -1;      // which reading (its index in the sensor's list); -1: each of them
  double threshold = 0;  // in the readings' units
  Crossing crossing = Crossing::kBoth;
  // A reading that rose to the threshold counts as below again only once it
  // fell below threshold - hysteresis (>= 0), so noise around the threshold
  // does not emit an event every sample.
  double hysteresis = 0;
};

// One crossing, handed to Controller::OnEvent.
struct SensorEvent {
  const Sensor* sensor = nullptr;  // the sensor that emitted it
  int watch = 0;                   // what Sensor::Watch returned
  int reading = 0;                 // which reading crossed
  double value = 0;                // its value on the sample that crossed
  bool rising = true;              // it rose to the threshold (false: it fell below)
};

// Base of every sensor's control interface (sensors/<name>/<name>.h).
class Sensor {
 public:
  virtual ~Sensor() = default;
  // Asks for an event (Controller::OnEvent) on every sample on which a
  // reading crosses `watch`'s threshold the way it says, and only then: a
  // reading that stays above the threshold emits nothing more. Whether a
  // reading starts above or below is taken from its value now (0 before the
  // first sample). Returns the watch's number (0, 1, ...), carried by its
  // events. Throws std::invalid_argument when this sensor emits no events
  // (so far: the proximity ring does) or `watch` is not one it can honour.
  virtual int Watch(const ThresholdWatch& watch) {
    (void)watch;
    throw std::invalid_argument("this sensor emits no events (Watch); sensors that do: proximity");
  }
  // For the host's bus accounting (docs/events.md): whether the controller
  // read this sensor's readings since the last call. Only sensors with a
  // bus model (SensorSystem::BusValues) keep track; the others say false
  // and keep nothing (no byte per instance for a feature few runs use).
  virtual bool TakeRead() { return false; }
};

// Base of every actuator's control interface (actuators/<name>/<name>.h).
class Actuator {
 public:
  virtual ~Actuator() = default;
};

// A parameter that was missing or could not be read; the host turns it into
// a message naming the file, line and element.
class ParamError : public std::runtime_error {
 public:
  ParamError(std::string key, std::string value, const std::string& message)
      : std::runtime_error(message), key_(std::move(key)), value_(std::move(value)) {}
  const std::string& key() const { return key_; }
  const std::string& value() const { return value_; }

 private:
  std::string key_;
  std::string value_;
};

// Parameters of a controller or loop functions: the attributes of its
// <params> element. Getters throw ParamError on a malformed value, so a typo
// in an experiment file is reported instead of silently replaced.
class Params {
 public:
  void Set(std::string key, std::string value);
  bool Has(std::string_view key) const;
  std::string GetString(std::string_view key, std::string_view fallback) const;
  std::string GetString(std::string_view key) const;  // required
  // A finite number in [min, max].
  double GetDouble(std::string_view key, double fallback, double min = -1e300,
                   double max = 1e300) const;
  double GetDouble(std::string_view key) const;  // required
  int64_t GetInt(std::string_view key, int64_t fallback, int64_t min = INT64_MIN,
                 int64_t max = INT64_MAX) const;
  bool GetBool(std::string_view key, bool fallback) const;
  // Finite numbers separated by commas ("25,50,75"), each in [min, max];
  // exactly `count` of them unless count is 0 (then at least one).
  std::vector<double> GetNumbers(std::string_view key, std::string_view fallback, size_t count = 0,
                                 double min = -1e300, double max = 1e300) const;
  // Keys present but never read: the host reports them as unknown parameters.
  std::vector<std::string> Unread() const;
  // The folder of the experiment file these parameters came from (empty when
  // they were not read from a file): relative file names in parameters (a Lua
  // script, a data file) resolve against it.
  const std::string& base_directory() const { return base_directory_; }
  void SetBaseDirectory(std::string dir) { base_directory_ = std::move(dir); }
  // Every key a getter asked for, present or not (to suggest a correction).
  const std::vector<std::string>& Asked() const { return asked_; }
  // The default each getter was given, the first time it asked for its key
  // (Has asks without one): the host checks them against a controller's
  // declared parameters.
  struct Default {
    enum Kind { kRequired, kNumber, kText };
    std::string key;
    std::string text;  // the number (shortest round-trip), or the text ("true"/"false" for a bool)
    Kind kind = kRequired;
  };
  const std::vector<Default>& Defaults() const { return defaults_; }

 private:
  struct Entry {
    std::string key;
    std::string value;
    mutable bool read = false;
    mutable std::optional<double> number;  // the value as a finite number, once parsed
  };
  const Entry* Find(std::string_view key) const;
  // Notes the default of `key` the first time it is asked for; text() makes
  // its text only then (every robot of a controller asks).
  template <class Text>
  void NoteDefault(std::string_view key, Default::Kind kind, Text&& text) const;
  std::vector<Entry> entries_;
  mutable std::vector<std::string> asked_;
  mutable std::vector<Default> defaults_;
  std::string base_directory_;
};

// The labels and names of the devices declared for a controller in the
// experiment file, shared by every robot of that controller (one per
// <controllers> entry). A device's label is its element's name as written
// (`footbot_proximity`); its name is the registered device it stands for
// (`proximity`), the same unless the file used an alias. A controller finds
// a device by either.
struct DeviceLabels {
  const std::vector<std::string>* sensor_labels = nullptr;
  const std::vector<std::string>* sensor_names = nullptr;  // null: the labels
  const std::vector<std::string>* actuator_labels = nullptr;
  const std::vector<std::string>* actuator_names = nullptr;  // null: the labels
  // The folder this run's files go to (null or "": none), for a controller
  // that reads something a loop function or an earlier tick put there.
  const std::string* run_folder = nullptr;

  // The index of the device declared with label or registered name `name`.
  std::optional<size_t> SensorIndex(std::string_view name) const {
    return IndexOf(*sensor_labels, sensor_names, name);
  }
  std::optional<size_t> ActuatorIndex(std::string_view name) const {
    return IndexOf(*actuator_labels, actuator_names, name);
  }
  // The registered name of device i.
  const std::string& SensorName(size_t i) const {
    return sensor_names ? (*sensor_names)[i] : (*sensor_labels)[i];
  }
  const std::string& ActuatorName(size_t i) const {
    return actuator_names ? (*actuator_names)[i] : (*actuator_labels)[i];
  }

 private:
  static std::optional<size_t> IndexOf(const std::vector<std::string>& labels,
                                       const std::vector<std::string>* names,
                                       std::string_view name) {
    for (size_t i = 0; i < labels.size(); ++i) {
      if (labels[i] == name || (names && (*names)[i] == name)) return i;
    }
    return std::nullopt;
  }
};

// What the host hands a controller: its robot's id and the devices declared
// for it, in the order of `labels`. Filled by the simulator (or by a real
// robot's runtime) before Init. Per robot only what differs from robot to
// robot (32 bytes; the labels are its controller's, shared).
struct DeviceTable {
  const std::string* robot_id = nullptr;
  Sensor* const* sensors = nullptr;
  Actuator* const* actuators = nullptr;
  const DeviceLabels* labels = nullptr;
};

// Where a controller (Controller::RecordValues) or loop functions
// (LoopFunctions::RecordRobotValues) put a few named values of one robot:
// numbers (counters, a battery level) and short labels (a state name). They
// become columns of the per-robot table (<output trajectories_every>, see
// docs/data-output.md), fixed at its first record: a robot without a value
// in a column gets an empty cell. A name must not be one of the table's own
// columns (tick, time, id, type, x, y, z, yaw, pitch, roll), be given twice
// for one robot, or change from number to label; such a name ends the run
// with a message naming it and who gave it.
class RobotValues {
 public:
  virtual void Set(std::string_view name, double value) = 0;
  virtual void SetLabel(std::string_view name, std::string_view label) = 0;

 protected:
  ~RobotValues() = default;
};

class Controller;

// The controllers of one configuration stepped together, once per tick, by
// one object: a host of controllers written over arrays in another language
// (Python's batched numpy controllers, docs/python.md). A controller asks
// for one by returning it from Controller::NewBatch.
class ControllerBatch {
 public:
  virtual ~ControllerBatch() = default;
  // Called once per tick in phase 5 (sense + control), after every robot's
  // sensors were read and every ControlStep ran, before the loop functions'
  // post-step (so the commands it sets are those the next act phase
  // applies). It runs on the thread that called Simulation::Step, never in
  // parallel with anything else of the simulation, and batches are called
  // in the order of their configurations in <controllers>, so it may do
  // what ControlStep may not (take a language's global lock) and stays
  // deterministic. `members`: the configuration's controllers alive now, in
  // robot order (the order of their slots in the space). What it throws
  // fails the run, as a throwing ControlStep does.
  virtual void Step(const std::vector<Controller*>& members) = 0;
};

// Base of every robot controller. Subclass it, register it with
// COLONY_REGISTER_CONTROLLER (core/registry.h), build it as a shared library.
class Controller {
 public:
  virtual ~Controller() = default;
  // Called once with the <params> of the controller's configuration.
  virtual void Init(const Params& params) { (void)params; }
  // Called once per tick, after the sensors were read; with a rate
  // (<controllers><x rate="25">) only on the ticks of that rate (core/schedule.h).
  virtual void ControlStep() = 0;
  // Called for each event a sensor emitted (Sensor::Watch), on the tick the
  // sensor sampled the crossing, whether or not the controller steps on that
  // tick, and before that tick's ControlStep: in the order of the sensors
  // in <sensors>, then of the readings. Wheel commands set here are applied
  // in the next tick's act phase, as ControlStep's are.
  virtual void OnEvent(const SensorEvent& event) { (void)event; }
  // Called by Simulation::Reset (docs/embedding.md) on the new controller it
  // built, bound and Init'ed for the robot, before the loop functions'
  // Reset; never during a plain run. As in ARGoS, it must leave the
  // controller as Init did (set its state, draw no random numbers), so that
  // a reset run is the run a fresh load with that seed gives.
  virtual void Reset() {}
  virtual void Destroy() {}
  // Called by the host once per configuration, on the first of its
  // controllers it starts (after that one's Init): a batch to step every
  // controller of the configuration together (see ControllerBatch), or null
  // (the default) for controllers stepped one by one. The host owns the
  // batch; it lives until the simulation is deleted or Reset. A ParamError
  // it throws is reported as Init's are (the <params> attribute's line).
  virtual std::unique_ptr<ControllerBatch> NewBatch() { return nullptr; }
  // This robot's named values for the per-robot table (see RobotValues):
  // called on the ticks the table records (tick 0 after Init, then after
  // ControlStep), never when no table is recorded. It must not change the
  // controller's state.
  virtual void RecordValues(RobotValues& values) const { (void)values; }

  const std::string& id() const { return *devices_.robot_id; }
  // The folder this run's files go to, to read from ("" when the run writes
  // none). Controllers run in parallel: write files from loop functions.
  const std::string& run_folder() const {
    static const std::string none;
    return devices_.labels && devices_.labels->run_folder ? *devices_.labels->run_folder : none;
  }
  // This robot's own random stream (deterministic whatever the thread count).
  // Made on the first call: most controllers never draw, and a stream is 32
  // bytes of every robot.
  RandomStream& rng() {
    if (!rng_) rng_ = std::make_unique<RandomStream>(rng_seed_);
    return *rng_;
  }

  // The sensor declared with element name `label` in <sensors>. Throws
  // std::logic_error when it is not declared or is not a T.
  template <class T>
  T& GetSensor(std::string_view label) const {
    return Lookup<T>(label, devices_.labels->SensorIndex(label), devices_.sensors, "sensor",
                     "<sensors>");
  }
  template <class T>
  T& GetActuator(std::string_view label) const {
    return Lookup<T>(label, devices_.labels->ActuatorIndex(label), devices_.actuators, "actuator",
                     "<actuators>");
  }
  // Every declared device, for hosts of controllers in other languages (Lua,
  // the ARGoS compatibility layer) that enumerate them.
  const DeviceTable& devices() const { return devices_; }

  // For the host: binds the devices and the random stream before Init.
  void Bind(const DeviceTable& devices, const RandomStream& rng) {
    devices_ = devices;
    rng_ = std::make_unique<RandomStream>(rng);
  }
  // The same, with the seed of the stream (RandomStream::SeedFor): the
  // stream is made when the controller first draws.
  void Bind(const DeviceTable& devices, uint64_t rng_seed) {
    devices_ = devices;
    rng_seed_ = rng_seed;
    rng_.reset();
  }

 private:
  template <class T, class D>
  static T& Lookup(std::string_view label, std::optional<size_t> index, D* const* items,
                   const char* what, const char* section) {
    if (!index) {
      throw std::logic_error("the controller asked for " + std::string(what) + " '" +
                             std::string(label) + "', which is not declared in its " + section);
    }
    if (auto* typed = dynamic_cast<T*>(items[*index])) return *typed;
    throw std::logic_error(std::string(what) + " '" + std::string(label) +
                           "' is not of the type the controller asked for");
  }

  DeviceTable devices_;
  uint64_t rng_seed_ = 0;
  std::unique_ptr<RandomStream> rng_;  // null until the first draw (rng())
};

}  // namespace colony
