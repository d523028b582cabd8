// A simulation: an experiment spec (core/experiment_spec.h) built once into
// a space, engines, sensor and actuator systems, controllers and loop
// functions, and stepped tick by tick in the fixed order of DESIGN.md:
//   1 act  2 physics (+ spatial index)  3 media  4 loop pre-step
//   5 sense + control (then the controller batches, ControllerBatch)
//   6 loop post-step, metrics, stop conditions.
// Building it (Create, AddEntity) is in core/simulation_create.cpp; the tick
// in core/simulation.cpp.
#pragma once

#include <algorithm>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/config.h"
#include "core/control_interface.h"
#include "core/device.h"
#include "core/engine.h"
#include "core/entity_type.h"
#include "core/experiment_spec.h"
#include "core/loop_functions.h"
#include "core/medium.h"
#include "core/renderer.h"
#include "core/schedule.h"
#include "core/space.h"
#include "core/thread_pool.h"

namespace tinyxml2 {
class XMLDocument;
}

namespace colony {

class PlacementIndex;

// Named values recorded by loop functions; one row of metrics.csv every
// `metrics_every` ticks, the first at tick 0 (after the loop functions'
// Init). Columns are fixed by the names set before the first row is written:
// set every metric in Init too.
class Metrics {
 public:
  // Sets metric `name`, a new column the first time. A name that is one of
  // metrics.csv's own columns (tick, time), or another loop functions'
  // metric, throws MetricNameError; a new name after the header was written
  // throws std::logic_error.
  void Set(const std::string& name, double value);
  const std::vector<std::string>& columns() const { return columns_; }
  const std::vector<double>& values() const { return values_; }
  // The value of metric `name` as last set (e.g. a fitness read after a
  // run). Throws std::out_of_range naming it and the metrics there are.
  double Value(std::string_view name) const;
  void Freeze() { frozen_ = true; }
  // For the host: who sets metrics from now on (a loop functions' label),
  // named in messages.
  void SetOwner(const std::string* label) { owner_ = label; }
  // metrics.csv's own columns, which no metric may be named.
  static const std::vector<std::string>& BuiltInColumns();

 private:
  std::vector<std::string> columns_;
  std::vector<double> values_;
  std::vector<const std::string*> owners_;  // who set each column first
  const std::string* owner_ = nullptr;
  bool frozen_ = false;
};

// A metric name that collides with a built-in column or another loop
// functions' metric (a load-time error when set in Init).
class MetricNameError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// Wall time spent in each phase of Simulation::Step, summed over the ticks
// since the load or the last Reset or ResetProfile (seconds), as Box2D's and
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

// What AddEntity checks of where an entity stands, besides being in an
// engine's region.
enum class PlacementCheck {
  kNone,   // nothing more: the caller knows there is room
  kClear,  // wholly inside the arena and clear of solid entities (fixed ones may touch each other),
           // as the entities of an experiment file must be
};

class Simulation {
 public:
  // Builds a simulation from a spec. Throws ConfigError listing every
  // problem found.
  static std::unique_ptr<Simulation> Create(const ExperimentSpec& spec);
  // Reads, checks and builds an experiment: Create(ReadExperimentSpec(options)).
  static std::unique_ptr<Simulation> Load(const ExperimentOptions& options);
  ~Simulation();

  // Puts the simulation back to its start, for evaluating many controller
  // parameter sets (or seeds) in one process (docs/embedding.md). What it
  // builds is what a fresh Load of the same experiment with `seed` (none:
  // the seed it has now) builds — the same state hash at tick 0 and at
  // every tick after — but nothing is read from the file and no plugin
  // library is loaded again. In order:
  //   1. the loop functions' and every controller's Destroy is called, and
  //      everything the experiment built is deleted: entities (those added
  //      while running too), engines, media, sensors, actuators and their
  //      random streams, controllers, loop functions, renderers, metrics;
  //   2. all of it is built again from the experiment as loaded, as Load
  //      does: entities of <distribute> placed with the new seed, tick 0;
  //      each controller a new object, Init'ed with its <params> (as changed
  //      by SetControllerParam), the loop functions a new object, Init'ed;
  //   3. each controller's Reset(), in robot order, then the loop
  //      functions' Reset(), as ARGoS calls them on reset.
  // So a controller or loop functions keep nothing across a Reset: the
  // program keeps what must last (a genome, the best fitness) and passes it
  // through SetControllerParam, or sets it on the new objects after Reset.
  // Their Reset() must leave them as Init did (ARGoS's contract: restore,
  // draw nothing), or the run differs from a fresh load's. Pointers and
  // references to controllers, loop functions, devices, engines, media and
  // renderers from before a Reset are invalid after it; entity handles
  // also (find entities again by id). Kept: this object, the thread pool,
  // renderers added with AddRenderer (added again), the spec with its
  // parameter changes.
  // Throws std::logic_error, changing nothing, when called during a tick
  // or a build (from a controller or loop functions). Throws ConfigError
  // when building fails as a load would (a parameter out of range,
  // <distribute> cannot place its entities with this seed), RuntimeFailure
  // when a Destroy or Reset hook throws; the simulation is then left empty,
  // and Step throws RuntimeFailure saying why until a Reset succeeds.
  void Reset(std::optional<uint64_t> seed = std::nullopt);
  // Sets parameter `key` of the controller configuration with id
  // `controller_id` (<controllers><diffusion id="dc"><params key="...">)
  // to `value`, for the controllers the next Reset builds; the running ones
  // keep what they read. Throws std::invalid_argument when no controller
  // configuration has that id (naming those there are); a key the
  // controller does not read is reported by the next Reset, as at load.
  void SetControllerParam(const std::string& controller_id, const std::string& key,
                          const std::string& value);

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
  // Where this run's files go ("" when it writes none): loop functions put
  // their own output there, so that runs of a sweep never share a file.
  const std::string& run_folder() const { return run_folder_; }
  // The experiment file as resolved (overrides applied), as XML text ("" for
  // a spec without a document). Changes a program made to the spec after
  // reading it are not in it.
  std::string ResolvedXml() const;
  // The parsed experiment file behind ResolvedXml (its elements keep their
  // line numbers), or null.
  const tinyxml2::XMLDocument* document() const {
    return document_ ? document_->xml.get() : nullptr;
  }
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
  // The label of the controller `robot` runs ("" if none) and the library
  // it came from (null: built in), for messages and crash reports.
  const std::string& ControllerLabelOf(EntityHandle robot) const;
  const char* ControllerLibraryOf(EntityHandle robot) const;
  // The loop functions and their registrations (label, library), for output
  // that asks them about every robot (core/trajectories.h).
  size_t loop_functions_count() const { return loop_functions_.size(); }
  LoopFunctions& loop_functions(size_t i) const { return *loop_functions_[i]; }
  const PluginInfo& loop_functions_info(size_t i) const { return *loop_function_info_[i]; }
  // Where the entity's type carries its devices (sensor rings, LEDs...).
  const DeviceMounts& MountsOf(EntityHandle entity) const;

  // Adds an entity while running (for loop functions), checked as the
  // entities of an experiment file are: a registered type, a new id, a robot's
  // controller among the <controllers> (it is attached and started), an engine
  // that can simulate it and whose region holds it, and with kClear its place.
  // Throws ConfigError naming the entity; nothing is added then.
  EntityHandle AddEntity(const EntityDesc& desc, PlacementCheck check = PlacementCheck::kNone);
  // The same from an XML element, as in <arena> (e.g. "<box id='b'
  // size='1,1,1'><body position='0,0,0'/></box>"): ReadEntityDesc, then
  // AddEntity. To add many alike, read one and copy it.
  EntityHandle AddEntity(const std::string& xml);
  void RemoveEntity(EntityHandle entity);
  // Puts a movable entity (a robot, a movable object) at `pose` between
  // ticks, at rest (the live viewer's drag): its engine drops it and takes it
  // again from there, as when it migrates, and the engine whose region holds
  // the new place takes it if that is another. Refused, with the reason
  // (nothing changes then), for a dead or fixed entity, a place outside the
  // arena or overlapping a solid entity, or an engine there that cannot
  // simulate it or its devices. Returns "" when moved.
  std::string MoveEntity(EntityHandle entity, const Pose& pose);

  // Per-engine ownership of an entity (for tests and tools).
  PhysicsEngine* EngineOf(EntityHandle entity) const;
  // Sets `pose` to anchor `name` of `entity` (a named frame on one of its
  // moving parts, world frame, as its engine's model put it after the last
  // step: PhysicsModel::Anchor) and returns true; false if the entity's
  // model has no such anchor. Devices call it from their parallel chunks.
  bool Anchor(EntityHandle entity, std::string_view name, Pose& pose) const;
  const std::vector<std::unique_ptr<PhysicsEngine>>& engines() const { return engines_; }

  // The medium of kind `label` (e.g. "range_and_bearing") a device element
  // uses: the one its medium="id" attribute names, else the only one of that
  // kind in <media>, else (none declared) one with default settings, shared
  // by every device that names none. On a problem records a diagnostic on
  // `device` and returns nullptr. For sensor and actuator Configure, which
  // Create calls after building the media.
  Medium* MediumFor(const ConfigNode& device, const std::string& label);
  const std::vector<std::unique_ptr<Medium>>& media() const { return media_; }

  // Renderers from <visualization>, in file order; the host calls them
  // between ticks (see core/renderer.h).
  const std::vector<std::unique_ptr<Renderer>>& renderers() const { return renderers_; }
  // Adds a renderer described by an XML element, as in <visualization>
  // (e.g. "<osmesa/>", for `colony run --frames`). Throws ConfigError.
  Renderer& AddRenderer(const std::string& xml);

 private:
  Simulation();

  struct ControllerConfig {
    std::string id;
    std::string label;
    const void* entry = nullptr;  // Registry<Controller>::Entry
    const char* library =
        nullptr;  // the entry's shared library, or null (built in), for crash reports
    ConfigNode node;
    Params params;
    std::vector<std::string> sensor_labels, actuator_labels;  // element names as written
    std::vector<std::string> sensor_names, actuator_names;    // the registered devices'
    DeviceLabels labels;  // the above and the run folder, for every robot's DeviceTable
    std::vector<SensorSystem*> sensors;
    std::vector<ActuatorSystem*> actuators;
    std::vector<ConfigNode> sensor_nodes, actuator_nodes;
    bool params_checked = false;
    // What its devices need (NeededComponents, sensors then actuators, as
    // component types), filled when a robot first passed ComponentProblem
    // for all of them, and the (engine, entity type) pairs whose model
    // simulated all of that: a robot of such a pair that carries those
    // components needs no other check (AttachController).
    std::vector<std::vector<ComponentType>> needs;
    std::vector<std::pair<const PhysicsEngine*, uint16_t>> needs_simulated;
    // Controller::NewBatch of its first controller (null: none, or not
    // asked yet), stepped by SenseAndControl with `members`, its controllers
    // alive now in the order of their slots (kept to step without allocating).
    bool batch_asked = false;
    std::unique_ptr<ControllerBatch> batch;
    std::vector<Controller*> members;
    std::vector<std::pair<uint32_t, Controller*>> by_slot;
    // Rates and events (docs/events.md). `sensor_slots`: each sensor's index
    // in sensor_systems_; `sensor_bus`: whether it has bus accounting.
    std::vector<size_t> sensor_slots;
    std::vector<uint8_t> sensor_bus;
    bool any_bus = false;
    // rate="...": the controller's period in ticks (0: every tick) and its
    // phase in ticks, or a random phase per robot.
    double step_period = 0, step_phase = 0;
    bool random_phase = false;
    // Set each tick: some sensor of it has watches (events to deliver).
    bool watching = false;
    // Whether its robots are stepped as without rates, events and bus (the
    // plain path, which this tick's flags decide).
    bool Plain() const { return step_period == 0 && !any_bus && !watching; }
  };
  struct Robot {
    EntityHandle entity;  // its id is the space's (a reference that stays valid)
    std::unique_ptr<Controller> controller;
    ControllerConfig* config = nullptr;
    Sensor** sensors = nullptr;      // in sensor_tables_
    Actuator** actuators = nullptr;  // in actuator_tables_
    bool alive = true;
    // Only for a controller with a rate or a sensor with bus accounting
    // (null otherwise: 8 bytes per robot rather than 40 for what few runs use).
    struct Timing {
      Schedule step;           // the ticks its controller steps on (rate="...")
      uint64_t bus_bytes = 0;  // bytes on its bus this tick (bus accounting)
    };
    std::unique_ptr<Timing> timing;
  };

  // Building (core/simulation_create.cpp), in the order Create calls them.
  // Problems are recorded in context_->diagnostics, thrown together after
  // the plugins, after the arena and after the loop functions.
  void Build(const ExperimentSpec& spec);
  void CreateMedia(const std::vector<PluginSpec>& media);
  void CreateControllers(const std::vector<ControllerSpec>& controllers);
  template <class System>
  void CreateDevices(const std::vector<PluginSpec>& devices, const char* what,
                     std::vector<std::string>& labels, std::vector<std::string>& names,
                     std::vector<System*>& systems, std::vector<ConfigNode>& nodes,
                     std::vector<std::unique_ptr<System>>& owned);
  void CreateEngines(const std::vector<EngineSpec>& engines);
  void CreateRenderers(const std::vector<PluginSpec>& renderers);
  bool CheckMemory(const ArenaSpec& arena);
  void BuildArena(const ArenaSpec& arena);
  void CreateLoopFunctions(const std::optional<PluginSpec>& loop_functions, const ArenaSpec& arena);
  // A plugin element of the spec, reporting to this simulation's diagnostics.
  ConfigNode Node(const ConfigNode& element) const {
    return ConfigNode(element.element(), context_.get());
  }
  // Checks `desc` (see AddEntity) and adds it. `check` says whether its
  // place is checked: against `placed` while building (the footprints placed
  // so far, which it joins), otherwise against the space.
  // Records problems and returns an invalid handle.
  EntityHandle Add(const EntityDesc& desc, PlacementCheck check, PlacementIndex* placed);
  // Why `init` cannot stand where it is among the entities now in the space, or "".
  // Why `init` cannot be placed now ("" if it can); the entity in slot
  // `self` (one being moved) is not in its own way.
  std::string PlaceProblemNow(const Space::EntityInit& init, uint32_t self = UINT32_MAX);
  // The physics model of each engine for entity type `label` (nullptr: none).
  std::vector<PhysicsModel*>& ModelsFor(uint16_t type, const std::string& label);
  // The engines `desc` goes into (one if movable); none: records why.
  std::vector<int> EnginesFor(const EntityDesc& desc, uint16_t type,
                              const std::vector<PhysicsModel*>& models);
  // Engines with a model registered for entity type `type` ("pointmass3d"),
  // and, if `component` is given, whose model simulates that component.
  static std::vector<std::string> EnginesAbleToSimulate(const std::string& type,
                                                        const std::string& component = "");
  // Takes out again an entity whose robot failed to start while running.
  void Withdraw(const std::string& id);
  // Records a problem with `desc` (its line and element, when from the file).
  void EntityError(const EntityDesc& desc, const std::string& attribute, const std::string& value,
                   const std::string& message);

  // Adds a described entity to the space, an engine and (robots) a controller.
  // `engines`: the engines it goes into (one if movable); `line`: its line in
  // the file, for messages.
  EntityHandle Instantiate(const EntityDesc& desc, uint16_t type, PhysicsModel* const* models,
                           const std::vector<int>& engines, int line);
  // Hands movable entities that left their engine's region to the engine
  // whose region now holds them.
  void Migrate();
  // Throws RuntimeFailure when a device of the robot in `slot` cannot work
  // in `to` (ComponentProblem).
  void CheckDevicesCanMigrate(uint32_t slot, const PhysicsEngine& from,
                              const PhysicsEngine& to) const;
  // The one check of what a device needs (SensorSystem::NeededComponents):
  // why the entity in `slot` cannot use a device needing the components
  // `needed` while `engine` simulates it (null: not checked against an
  // engine): a component it does not carry, or one the engine's model of
  // its type does not simulate; "" if it can. The engine is named "its
  // physics engine (...)" when `attaching`, plainly otherwise.
  std::string ComponentProblem(uint32_t slot, const std::vector<std::string>& needed,
                               const PhysicsEngine* engine, bool attaching) const;
  void AttachController(Robot& robot, int line);
  // Whether the robot's devices are known to work on it (ControllerConfig::
  // needs); false means "check them".
  bool DevicesKnownToFit(const Robot& robot) const;
  // The sampling periods and bus flags of a configuration's sensors and its
  // rate (docs/events.md), read from their elements.
  void ReadTiming(ControllerConfig& config);
  double ReadPhase(const ConfigNode& node, double period, const std::string& owner);
  void Act();
  void SenseAndControl();
  // One robot's events, step (when due) and bus bytes, for configurations
  // with rates, events or bus accounting (ControllerConfig::Plain false).
  void StepTimed(Robot& robot, uint64_t tick, std::vector<SensorEvent>& events);
  // Steps the configurations' batches (ControllerBatch), serially, in the
  // order of <controllers>. Throws RuntimeFailure naming the one that threw.
  void StepBatches();
  bool SensorsAlignWithRobots() const;
  // Calls `call` on every loop functions, naming them (and `tick`, the tick
  // being computed) in what they throw and in a crash report.
  template <typename Hook>
  void CallLoopFunctions(const char* hook, uint64_t tick, Hook&& call);
  // A renderer described by an XML element (AddRenderer). Throws ConfigError.
  std::unique_ptr<Renderer> NewRenderer(const std::string& xml);
  // Reset (core/simulation_create.cpp): deletes what Build built, as the
  // destructor does (Destroy hooks first, then the members in reverse order
  // of declaration), leaving them as a new Simulation has them, except the
  // thread pool and what Reset keeps. Returns what the first Destroy hook
  // that threw said ("" if none did). A member added below must be cleared
  // there too.
  std::string TearDown();
  // Calls every controller's Reset, then the loop functions' (step 3 of
  // Reset). Throws RuntimeFailure naming the one that threw.
  void CallResetHooks();
  // Marks the simulation busy (a tick, a build, a reset) while it lives:
  // Reset and Step refuse to run then.
  class BusyScope {
   public:
    explicit BusyScope(bool& busy) : busy_(busy), was_(busy) { busy_ = true; }
    ~BusyScope() { busy_ = was_; }
    BusyScope(const BusyScope&) = delete;
    BusyScope& operator=(const BusyScope&) = delete;

   private:
    bool& busy_;
    bool was_;
  };

  // File and parsed document (the plugins' elements; ResolvedXml), and the
  // problems found building.
  std::string run_folder_;
  std::string file_;
  std::shared_ptr<const SpecDocument> document_;
  std::unique_ptr<ConfigContext> context_;
  std::unique_ptr<tinyxml2::XMLDocument> generated_;  // elements made here (default media)
  // The experiment as loaded, which Reset builds again: its seed is the
  // last Reset's, its controllers' params as SetControllerParam left them.
  ExperimentSpec spec_;
  std::vector<std::string> added_renderers_;  // AddRenderer's elements, added again by Reset
  bool busy_ = false;                         // in a tick, a build or a reset (BusyScope)
  std::string reset_failure_;                 // why the last Reset failed ("" if it did not)

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
  // Per entity type: the engine that takes it (entities="..."), or -1.
  std::vector<int> taken_by_;
  std::vector<std::unique_ptr<PhysicsModel>> model_storage_;
  std::vector<int16_t> engine_of_;  // per space slot
  std::vector<int> line_of_;        // per space slot: the entity's line in the file (0: none)
  std::vector<std::unique_ptr<SensorSystem>> sensor_systems_;
  // Per sensor system: when it samples (period="..."), and whether it does
  // on the tick being computed; all every tick when sensors_every_tick_.
  std::vector<Schedule> sensor_schedules_;
  std::vector<uint8_t> sensor_due_;
  bool sensors_every_tick_ = true;
  bool any_bus_ = false;    // some sensor has bus accounting: the bus_bytes metric
  uint64_t bus_bytes_ = 0;  // every robot's bus bytes since the start
  std::vector<std::unique_ptr<ActuatorSystem>> actuator_systems_;
  std::vector<std::unique_ptr<ControllerConfig>> controller_configs_;
  std::deque<Robot> robots_;  // stable addresses: controllers point at their tables
  // Whether every robot runs the configuration of the first (kept as robots
  // are added: a robot's configuration never changes, and reading every
  // robot for it each tick was a serial pass over them).
  bool one_config_ = true;
  // Robots' device tables (the pointers to each robot's sensor and actuator
  // instances), carved from shared blocks: a heap array per robot and table
  // cost 32 bytes each, for one or two pointers.
  ArrayBlocks<Sensor*> sensor_tables_;
  ArrayBlocks<Actuator*> actuator_tables_;
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
