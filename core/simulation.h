// A simulation: an experiment file compiled once into a space, engines,
// sensor and actuator systems, controllers and loop functions, and stepped
// tick by tick in the fixed order of DESIGN.md:
//   1 act  2 physics (+ spatial index)  3 media  4 loop pre-step
//   5 sense + control  6 loop post-step, metrics, stop conditions.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/config.h"
#include "core/control_interface.h"
#include "core/device.h"
#include "core/engine.h"
#include "core/entity_type.h"
#include "core/loop_functions.h"
#include "core/medium.h"
#include "core/renderer.h"
#include "core/space.h"
#include "core/thread_pool.h"

namespace tinyxml2 {
class XMLDocument;
}

namespace colony {

// How to load an experiment (from the command line or a test).
struct ExperimentOptions {
  std::string file;                    // path of the XML file, or
  std::string text;                    // the XML itself (file then only names it in messages)
  std::vector<std::string> overrides;  // "path=value", see ApplyOverride
  std::optional<int> threads;          // replaces <system threads>
  std::optional<uint64_t> seed;        // replaces <experiment random_seed>
};

// Named values recorded by loop functions; one row of metrics.csv every
// `metrics_every` ticks. Columns are fixed by the names set before the first
// row is written.
class Metrics {
 public:
  void Set(const std::string& name, double value);
  const std::vector<std::string>& columns() const { return columns_; }
  const std::vector<double>& values() const { return values_; }
  void Freeze() { frozen_ = true; }

 private:
  std::vector<std::string> columns_;
  std::vector<double> values_;
  bool frozen_ = false;
};

// Wall time spent in each phase of Simulation::Step, summed over the ticks
// since the load or the last ResetProfile (seconds), as Box2D's and
// MuJoCo's per-stage timers: where a tick's time goes. Reading the clock
// costs a few tens of nanoseconds per phase and tick.
struct StepProfile {
  double act = 0;             // 1: actuators
  double physics = 0;         // 2: engines, migration, spatial index
  double media = 0;           // 3: media
  double loop_functions = 0;  // 4 and 6: pre-step, post-step, stop conditions
  double sense_control = 0;   // 5: sensors and controllers
  uint64_t ticks = 0;
  double total() const { return act + physics + media + loop_functions + sense_control; }
};

struct OutputConfig {
  uint64_t metrics_every = 1;  // ticks between rows of metrics.csv (0: none)
  uint64_t hash_every = 0;     // ticks between state hashes printed to hashes.csv (0: none)
};

class Simulation {
 public:
  // Reads, validates and builds an experiment. Throws ConfigError listing
  // every problem found.
  static std::unique_ptr<Simulation> Load(const ExperimentOptions& options);
  ~Simulation();

  // One tick.
  void Step();
  // The experiment length is reached or the loop functions ended it.
  bool Done() const { return done_; }

  uint64_t tick() const { return tick_; }
  uint64_t length_ticks() const { return length_ticks_; }  // 0: unlimited
  double dt() const { return dt_; }
  double time() const { return tick_ * dt_; }
  uint64_t seed() const { return seed_; }
  // Threads running the simulation, as resolved: 0 in the file or on the
  // command line means the calling thread only, so it reads 1.
  int threads() const { return threads_; }
  const std::string& file() const { return file_; }
  // The experiment as resolved (overrides applied), as XML text.
  std::string ResolvedXml() const;
  const OutputConfig& output() const { return output_; }

  Space& space() { return space_; }
  const Space& space() const { return space_; }
  ThreadPool& pool() { return *pool_; }
  Metrics& metrics() { return metrics_; }
  const Metrics& metrics() const { return metrics_; }
  // A random stream for loop functions (deterministic).
  RandomStream& rng() { return rng_; }
  uint64_t StateHash() const;
  const StepProfile& profile() const { return profile_; }
  void ResetProfile() { profile_ = {}; }

  // Robots carrying a controller, alive now.
  size_t robot_count() const { return robot_count_; }
  Controller* ControllerOf(EntityHandle robot) const;
  // Where the entity's type carries its devices (sensor rings, LEDs...).
  const DeviceMounts& MountsOf(EntityHandle entity) const;

  // Adds an entity described by an XML element, as in <arena> (e.g.
  // "<box id='b' size='1,1,1'><body position='0,0,0'/></box>"). For loop
  // functions; throws ConfigError.
  EntityHandle AddEntity(const std::string& xml);
  void RemoveEntity(EntityHandle entity);

  // Per-engine ownership of an entity (for tests and tools).
  PhysicsEngine* EngineOf(EntityHandle entity) const;
  const std::vector<std::unique_ptr<PhysicsEngine>>& engines() const { return engines_; }

  // The medium of kind `label` (e.g. "range_and_bearing") a device element
  // uses: the one its medium="id" attribute names, else the only one of that
  // kind in <media>, else (none declared) one with default settings, shared
  // by every device that names none. On a problem records a diagnostic on
  // `device` and returns nullptr. For sensor and actuator Configure.
  Medium* MediumFor(const ConfigNode& device, const std::string& label);
  const std::vector<std::unique_ptr<Medium>>& media() const { return media_; }

  // Renderers from <visualization>, in file order; the host calls them
  // between ticks (see core/renderer.h).
  const std::vector<std::unique_ptr<Renderer>>& renderers() const { return renderers_; }
  // Adds a renderer described by an XML element, as in <visualization>
  // (e.g. "<osmesa/>", for `colony run --frames`). Throws ConfigError.
  Renderer& AddRenderer(const std::string& xml);

 private:
  friend class ExperimentLoader;
  Simulation();

  struct ControllerConfig {
    std::string id;
    std::string label;
    const void* entry = nullptr;  // Registry<Controller>::Entry
    const char* library = nullptr;  // the entry's shared library, or null (built in), for crash reports
    ConfigNode node;
    Params params;
    std::vector<std::string> sensor_labels, actuator_labels;
    std::vector<SensorSystem*> sensors;
    std::vector<ActuatorSystem*> actuators;
    std::vector<ConfigNode> sensor_nodes, actuator_nodes;
    bool params_checked = false;
  };
  struct Robot {
    EntityHandle entity;
    std::string id;
    std::unique_ptr<Controller> controller;
    ControllerConfig* config = nullptr;
    std::unique_ptr<Sensor*[]> sensors;
    std::unique_ptr<Actuator*[]> actuators;
    bool alive = true;
  };

  // Adds a described entity to the space, an engine and (robots) a controller.
  // `engines`: the engines it goes into (one if movable).
  EntityHandle Instantiate(const EntityDesc& desc, PhysicsModel* const* models,
                           const std::vector<int>& engines, const ConfigNode& where);
  // Hands movable entities that left their engine's region to the engine
  // whose region now holds them.
  void Migrate();
  // Throws RuntimeFailure when a device of the robot in `slot` cannot work
  // in `to` (ComponentProblem).
  void CheckDevicesCanMigrate(uint32_t slot, const PhysicsEngine& from, const PhysicsEngine& to) const;
  // The one check of what a device needs (SensorSystem::NeededComponents):
  // why the entity in `slot` cannot use a device needing the components
  // `needed` while `engine` simulates it (null: not checked against an
  // engine): a component it does not carry, or one the engine's model of
  // its type does not simulate; "" if it can. The engine is named "its
  // physics engine (...)" when `attaching`, plainly otherwise.
  std::string ComponentProblem(uint32_t slot, const std::vector<std::string>& needed,
                               const PhysicsEngine* engine, bool attaching) const;
  void AttachController(Robot& robot, const ConfigNode& where);
  void Act();
  void SenseAndControl();
  bool SensorsAlignWithRobots() const;
  // Calls `call` on every loop functions, naming them (and `tick`, the tick
  // being computed) in what they throw and in a crash report.
  template <typename Hook>
  void CallLoopFunctions(const char* hook, uint64_t tick, Hook&& call);

  // File and parsed document (kept for messages, runtime additions and output).
  std::string file_;
  std::unique_ptr<tinyxml2::XMLDocument> document_;
  std::unique_ptr<ConfigContext> context_;

  uint64_t tick_ = 0, length_ticks_ = 0, seed_ = 0;
  double dt_ = 0.1;
  int threads_ = 1;
  bool done_ = false;
  OutputConfig output_;

  Space space_;
  std::unique_ptr<ThreadPool> pool_;
  std::vector<std::unique_ptr<PhysicsEngine>> engines_;
  // Per entity type: the model of each engine (nullptr: unsupported).
  std::vector<std::vector<PhysicsModel*>> models_;
  std::vector<std::unique_ptr<PhysicsModel>> model_storage_;
  std::vector<int16_t> engine_of_;  // per space slot
  std::vector<std::unique_ptr<SensorSystem>> sensor_systems_;
  std::vector<std::unique_ptr<ActuatorSystem>> actuator_systems_;
  std::vector<std::unique_ptr<ControllerConfig>> controller_configs_;
  std::deque<Robot> robots_;  // stable addresses: controllers point at their ids
  std::vector<int32_t> robot_of_;  // per space slot, -1 if none
  size_t robot_count_ = 0;
  std::vector<std::unique_ptr<LoopFunctions>> loop_functions_;
  std::vector<const PluginInfo*> loop_function_info_;  // label and library of each
  std::vector<std::unique_ptr<Renderer>> renderers_;
  std::vector<std::unique_ptr<Medium>> media_;
  Metrics metrics_;
  StepProfile profile_;
  RandomStream rng_;
  std::vector<std::pair<const EntityType*, uint16_t>> entity_types_;  // by space type id
  // The registration of each (engine, entity type) model, as looked up.
  mutable std::map<std::pair<const PhysicsEngine*, uint16_t>, const PluginInfo*> model_info_;
};

}  // namespace colony
