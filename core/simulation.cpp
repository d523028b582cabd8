#include "core/simulation.h"

#include <tinyxml2.h>

#include <algorithm>
#include <chrono>
#include <mutex>

#include "core/bus.h"
#include "core/crash_report.h"
#include "core/image_renderer.h"
#include "core/text.h"

namespace colony {

const std::vector<std::string>& Metrics::BuiltInColumns() {
  static const std::vector<std::string> columns = {"tick", "time"};
  return columns;
}

void Metrics::Set(const std::string& name, double value) {
  for (size_t i = 0; i < columns_.size(); ++i) {
    if (columns_[i] != name) continue;
    if (owners_[i] && owner_ && *owners_[i] != *owner_) {
      throw MetricNameError("metric '" + name + "' of loop functions '" + *owner_ +
                            "' is already a metric of loop functions '" + *owners_[i] +
                            "'; give each metric its own name");
    }
    values_[i] = value;
    return;
  }
  const std::string who = owner_ ? "of loop functions '" + *owner_ + "' " : "";
  for (const auto& column : BuiltInColumns()) {
    if (name == column) {
      throw MetricNameError("metric '" + name + "' " + who +
                            "has the name of one of metrics.csv's own columns (" +
                            Join(BuiltInColumns()) + "); rename the metric");
    }
  }
  if (frozen_) {
    throw std::logic_error("metric '" + name + "' " + who +
                           "was set for the first time after metrics.csv's header was written "
                           "(at tick 0, after Init); set every metric in Init too");
  }
  columns_.push_back(name);
  values_.push_back(value);
  owners_.push_back(owner_);
}

double Metrics::Value(std::string_view name) const {
  for (size_t i = 0; i < columns_.size(); ++i) {
    if (columns_[i] == name) return values_[i];
  }
  throw std::out_of_range("no metric '" + std::string(name) + "'; " +
                          (columns_.empty() ? "the loop functions set none"
                                            : "the loop functions set: " + Join(columns_)));
}

Simulation::Simulation() = default;

Simulation::~Simulation() {
  for (auto& lf : loop_functions_) lf->Destroy();
  for (auto& r : robots_) {
    if (r.alive && r.controller) r.controller->Destroy();
  }
}

EntityHandle Simulation::Instantiate(const EntityDesc& desc, uint16_t type,
                                     PhysicsModel* const* models, const std::vector<int>& engines,
                                     int line) {
  const EntityHandle h = space_.Add(desc.init, type);
  if (engine_of_.size() < space_.slots()) {
    engine_of_.resize(space_.slots(), -1);
    robot_of_.resize(space_.slots(), -1);
    line_of_.resize(space_.slots(), 0);
  }
  engine_of_[h.index] = -1;
  robot_of_[h.index] = -1;
  line_of_[h.index] = line;
  for (int e : engines) {
    engines_[e]->SetOwned(h.index, true);
    engines_[e]->AddEntity(h, *models[e]);
    if (engine_of_[h.index] < 0) engine_of_[h.index] = static_cast<int16_t>(e);
  }
  if (!desc.controller.empty()) {
    Robot& robot = robots_.emplace_back();
    robot.entity = h;
    robot_of_[h.index] = static_cast<int32_t>(robots_.size() - 1);
    for (auto& c : controller_configs_) {
      if (c->id == desc.controller) robot.config = c.get();
    }
    one_config_ = one_config_ && robot.config == robots_.front().config;
    AttachController(robot, line);
    ++robot_count_;
  }
  return h;
}

void Simulation::AttachController(Robot& robot, int line) {
  const std::string& id = space_.id(robot.entity.index);
  ControllerConfig& config = *robot.config;
  const auto* entry = static_cast<const Registry<Controller>::Entry*>(config.entry);
  config.library = entry->info.library.empty() ? nullptr : entry->info.library.c_str();
  robot.controller = entry->create();
  const size_t ns = config.sensors.size(), na = config.actuators.size();
  robot.sensors = sensor_tables_.Take(ns).data();
  robot.actuators = actuator_tables_.Take(na).data();
  const std::string& type = space_.TypeLabel(space_.type(robot.entity.index));
  bool attached = true;
  // What the devices need of the robot and its engine, checked here for
  // every device (and again in Migrate), unless robots like it passed.
  const bool fits = DevicesKnownToFit(robot);
  auto component_problem = [&](auto* system) -> std::string {
    if (fits) return {};
    return ComponentProblem(robot.entity.index, system->NeededComponents(), EngineOf(robot.entity),
                            true);
  };
  for (size_t i = 0; i < ns; ++i) {
    try {
      if (std::string problem = component_problem(config.sensors[i]); !problem.empty())
        throw AttachError(problem);
      robot.sensors[i] = config.sensors[i]->Attach(
          robot.entity, RandomStream::For(seed_, id, "sensor/", config.sensor_labels[i]));
    } catch (const AttachError& e) {
      config.sensor_nodes[i].ElementError("robot '" + id + "' (a " + type + ", line " +
                                          std::to_string(line) +
                                          ") cannot carry this sensor: " + e.what());
      attached = false;
    }
  }
  for (size_t i = 0; i < na; ++i) {
    try {
      if (std::string problem = component_problem(config.actuators[i]); !problem.empty())
        throw AttachError(problem);
      robot.actuators[i] = config.actuators[i]->Attach(
          robot.entity, RandomStream::For(seed_, id, "actuator/", config.actuator_labels[i]));
    } catch (const AttachError& e) {
      config.actuator_nodes[i].ElementError("robot '" + id + "' (a " + type + ", line " +
                                            std::to_string(line) +
                                            ") cannot carry this actuator: " + e.what());
      attached = false;
    }
  }
  if (!attached) {
    context_->diagnostics.ThrowIfAny();
  }
  if (!fits && attached) {
    if (config.needs.empty()) {
      auto add = [&](auto* system) {
        std::vector<ComponentType>& types = config.needs.emplace_back();
        for (const std::string& name : system->NeededComponents())
          types.push_back(ComponentTypeNamed(name));
      };
      for (size_t i = 0; i < ns; ++i) add(config.sensors[i]);
      for (size_t i = 0; i < na; ++i) add(config.actuators[i]);
    }
    config.needs_simulated.emplace_back(EngineOf(robot.entity), space_.type(robot.entity.index));
  }
  DeviceTable table;
  table.robot_id = &id;
  table.sensors = robot.sensors;
  table.actuators = robot.actuators;
  table.labels = &config.labels;
  robot.controller->Bind(table, RandomStream::SeedFor(seed_, id, "controller"));
  robot.timing.reset();
  if (config.step_period > 0 || config.any_bus) robot.timing = std::make_unique<Robot::Timing>();
  if (config.step_period > 0) {
    // A random phase comes from a stream of its own, so the controller's
    // stream is the same with and without it.
    const double phase =
        config.random_phase
            ? RandomStream::For(seed_, id, "controller_phase").Uniform() * config.step_period
            : config.step_phase;
    robot.timing->step = Schedule(config.step_period, phase);
  }
  for (size_t i = 0; i < ns && config.any_bus; ++i) {
    if (config.sensor_bus[i] && config.sensors[i]->BusValues(robot.sensors[i]) == 0) {
      config.sensor_nodes[i].Error(
          "bus", "true",
          "sensor '" + config.sensor_labels[i] +
              "' has no bus model (how many values a poll carries); sensors that have one: "
              "proximity");
      context_->diagnostics.ThrowIfAny();
    }
  }
  // Where a parameter's error points: <params>, else the controller's element
  // (looked up only for an error).
  auto params_node = [&config] {
    const ConfigNode params = config.node.Child("params");
    return params.valid() ? params : config.node;
  };
  try {
    robot.controller->Init(config.params);
  } catch (const ParamError& e) {
    params_node().Error(e.key(), e.value(), e.what());
    context_->diagnostics.ThrowIfAny();
  } catch (const std::exception& e) {
    config.node.ElementError("controller '" + config.label + "' failed to start on robot '" + id +
                             "': " + e.what());
    context_->diagnostics.ThrowIfAny();
  } catch (...) {
    config.node.ElementError("controller '" + config.label + "' failed to start on robot '" + id +
                             "': it threw something that is not a std::exception");
    context_->diagnostics.ThrowIfAny();
  }
  // What Init read is not a poll of a tick (bus accounting).
  for (size_t i = 0; i < ns; ++i) robot.sensors[i]->TakeRead();
  if (!config.params_checked) {
    config.params_checked = true;
    // A controller that declares its parameters read only those, with the
    // declared defaults: the declaration `colony query` prints is the code's.
    const auto& info = static_cast<const Registry<Controller>::Entry*>(config.entry)->info;
    for (const auto& problem : UndeclaredParamReads(info, config.params))
      config.node.ElementError(problem);
    context_->diagnostics.ThrowIfAny();
    // Parameters the controller never read are typos or leftovers.
    for (const auto& key : config.params.Unread()) {
      std::string message = "parameter not read by controller '" + config.label + "'";
      const std::string guess = DidYouMean(key, config.params.Asked());
      if (!guess.empty()) message += " (did you mean '" + guess + "'?)";
      const auto& asked = config.params.Asked();
      std::string list;
      for (size_t i = 0; i < asked.size(); ++i) list += (i ? ", " : "") + asked[i];
      if (!list.empty()) message += "; it reads: " + list;
      params_node().Error(key, config.params.GetString(key, ""), message);
    }
    context_->diagnostics.ThrowIfAny();
  }
  if (!config.batch_asked) {
    config.batch_asked = true;
    try {
      config.batch = robot.controller->NewBatch();
    } catch (const ParamError& e) {
      params_node().Error(e.key(), e.value(), e.what());
      context_->diagnostics.ThrowIfAny();
    } catch (const std::exception& e) {
      config.node.ElementError("controller '" + config.label + "' failed to start: " + e.what());
      context_->diagnostics.ThrowIfAny();
    }
    if (config.batch && config.step_period > 0) {
      config.batch.reset();
      config.node.Error("rate", config.node.GetString("rate", ""),
                        "controller '" + config.label +
                            "' steps its robots together (a batch), every tick; it takes no rate");
      context_->diagnostics.ThrowIfAny();
    }
  }
}

void Simulation::RemoveEntity(EntityHandle entity) {
  if (!space_.IsAlive(entity)) return;
  const uint32_t slot = entity.index;
  if (robot_of_[slot] >= 0) {
    Robot& robot = robots_[robot_of_[slot]];
    robot.controller->Destroy();
    for (size_t i = 0; i < robot.config->sensors.size(); ++i)
      robot.config->sensors[i]->Detach(robot.sensors[i]);
    for (size_t i = 0; i < robot.config->actuators.size(); ++i)
      robot.config->actuators[i]->Detach(robot.actuators[i]);
    robot.controller.reset();
    robot.alive = false;
    robot_of_[slot] = -1;
    --robot_count_;
  }
  for (auto& engine : engines_) {
    if (!engine->Owns(slot)) continue;
    engine->RemoveEntity(entity);
    engine->SetOwned(slot, false);
  }
  engine_of_[slot] = -1;
  space_.Remove(entity);
  space_.UpdateIndex();
}

std::string Simulation::MoveEntity(EntityHandle entity, const Pose& pose) {
  if (busy_) return "entities are moved between ticks, not during one";
  if (!space_.IsAlive(entity)) return "no such entity";
  const uint32_t s = entity.index;
  if (!space_.movable(s) || engine_of_[s] < 0) return "'" + space_.id(s) + "' is fixed";
  Space::EntityInit init;
  init.id = space_.id(s);
  init.type = space_.type(s);
  init.pose = pose;
  init.geometry = space_.geometry(s);
  init.flags = space_.flags(s);
  if (std::string problem = PlaceProblemNow(init, s); !problem.empty()) return problem;
  // The engine that takes it there: its own if that one takes its type or
  // holds the place, else the first whose region does (as Migrate chooses).
  const auto& models = models_[space_.type(s)];
  int to = engine_of_[s];
  PhysicsEngine& from = *engines_[to];
  if (!from.takes_types() && !from.Holds(pose.position)) {
    to = -1;
    for (size_t e = 0; e < engines_.size() && to < 0; ++e) {
      if (models[e] && !engines_[e]->takes_types() && engines_[e]->Holds(pose.position))
        to = static_cast<int>(e);
    }
    if (to < 0) return "no physics engine's region holds that place";
    try {
      CheckDevicesCanMigrate(s, from, *engines_[to]);
    } catch (const RuntimeFailure& e) {
      return e.what();
    }
  }
  from.RemoveEntity(entity);
  from.SetOwned(s, false);
  space_.pose(s) = pose;
  space_.twist(s) = Twist{};
  engines_[to]->SetOwned(s, true);
  engines_[to]->AddEntity(entity, *models[to]);
  engine_of_[s] = static_cast<int16_t>(to);
  space_.UpdateIndex();
  return "";
}

Controller* Simulation::ControllerOf(EntityHandle robot) const {
  if (!space_.IsAlive(robot) || robot_of_[robot.index] < 0) return nullptr;
  return robots_[robot_of_[robot.index]].controller.get();
}

const std::string& Simulation::ControllerLabelOf(EntityHandle robot) const {
  static const std::string none;
  if (!space_.IsAlive(robot) || robot_of_[robot.index] < 0) return none;
  return robots_[robot_of_[robot.index]].config->label;
}

const char* Simulation::ControllerLibraryOf(EntityHandle robot) const {
  if (!space_.IsAlive(robot) || robot_of_[robot.index] < 0) return nullptr;
  return robots_[robot_of_[robot.index]].config->library;
}

const DeviceMounts& Simulation::MountsOf(EntityHandle entity) const {
  return entity_types_[space_.type(entity.index)].first->mounts();
}

bool Simulation::Anchor(EntityHandle entity, std::string_view name, Pose& pose) const {
  if (!space_.IsAlive(entity) || engine_of_[entity.index] < 0) return false;
  const uint16_t type = space_.type(entity.index);
  if (type >= models_.size()) return false;
  const PhysicsModel* model = models_[type][engine_of_[entity.index]];
  return model && model->Anchor(space_, entity.index, name, pose);
}

PhysicsEngine* Simulation::EngineOf(EntityHandle entity) const {
  if (!space_.IsAlive(entity) || engine_of_[entity.index] < 0) return nullptr;
  return engines_[engine_of_[entity.index]].get();
}

void Simulation::Migrate() {
  // In slot order, so the engines receive migrants in the same order
  // whatever the thread count.
  for (uint32_t s = 0; s < space_.slots(); ++s) {
    if (!space_.alive(s) || !space_.movable(s) || engine_of_[s] < 0) continue;
    const Vec3& p = space_.pose(s).position;
    PhysicsEngine& from = *engines_[engine_of_[s]];
    // An engine that takes entity types covers the whole arena: its own
    // never leave it.
    if (from.takes_types() || from.Holds(p)) continue;
    const auto& models = models_[space_.type(s)];
    // Engines that take entity types take no other type's movables.
    for (size_t e = 0; e < engines_.size(); ++e) {
      if (!models[e] || engines_[e]->takes_types() || !engines_[e]->Holds(p)) continue;
      CheckDevicesCanMigrate(s, from, *engines_[e]);
      const EntityHandle h = space_.HandleOf(s);
      from.RemoveEntity(h);
      from.SetOwned(s, false);
      engines_[e]->SetOwned(s, true);
      engines_[e]->AddEntity(h, *models[e]);
      engine_of_[s] = static_cast<int16_t>(e);
      break;
    }
  }
}

void Simulation::CheckDevicesCanMigrate(uint32_t slot, const PhysicsEngine& from,
                                        const PhysicsEngine& to) const {
  if (robot_of_[slot] < 0) return;
  const Robot& robot = robots_[robot_of_[slot]];
  const ControllerConfig& config = *robot.config;
  auto check = [&](const char* kind, const std::string& label,
                   const std::vector<std::string>& needed) {
    const std::string problem = ComponentProblem(slot, needed, &to, false);
    if (problem.empty()) return;
    throw RuntimeFailure(
        "robot '" + space_.id(robot.entity.index) + "' crossed at tick " +
        std::to_string(tick_ + 1) + " from " + EngineName(&from) + " into the region of " +
        EngineName(&to) + ", which cannot simulate its " + kind + " '" + label + "': " + problem +
        "; keep such robots inside the regions of engines that simulate it (walls, or "
        "boundaries)");
  };
  for (size_t i = 0; i < config.sensors.size(); ++i) {
    check("sensor", config.sensor_labels[i], config.sensors[i]->NeededComponents());
  }
  for (size_t i = 0; i < config.actuators.size(); ++i) {
    check("actuator", config.actuator_labels[i], config.actuators[i]->NeededComponents());
  }
}

bool Simulation::DevicesKnownToFit(const Robot& robot) const {
  const ControllerConfig& config = *robot.config;
  const uint32_t slot = robot.entity.index;
  const std::pair<const PhysicsEngine*, uint16_t> key(EngineOf(robot.entity), space_.type(slot));
  if (std::find(config.needs_simulated.begin(), config.needs_simulated.end(), key) ==
      config.needs_simulated.end()) {
    return false;
  }
  for (const auto& types : config.needs) {
    for (ComponentType t : types) {
      if (!space_.Has(slot, t)) return false;
    }
  }
  return true;
}

std::string Simulation::ComponentProblem(uint32_t slot, const std::vector<std::string>& needed,
                                         const PhysicsEngine* engine, bool attaching) const {
  if (needed.empty()) return "";
  const uint16_t type = space_.type(slot);
  const std::string& type_label = space_.TypeLabel(type);
  const PluginInfo* model = nullptr;
  if (engine) {
    const auto key = std::make_pair(engine, type);
    auto it = model_info_.find(key);
    if (it == model_info_.end()) {
      const auto* entry = Registry<PhysicsModel>::Get().Find(engine->label() + ":" + type_label);
      it = model_info_.emplace(key, entry ? &entry->info : nullptr).first;
    }
    model = it->second;
  }
  for (const std::string& name : needed) {
    if (!space_.Has(slot, ComponentTypeNamed(name))) {
      const EntityType* entity_type =
          type < entity_types_.size() ? entity_types_[type].first : nullptr;
      const std::string hint = entity_type ? entity_type->ComponentHint(name) : "";
      return "it has no " + name + (hint.empty() ? "" : "; " + hint);
    }
    if (!engine || !model) continue;
    const auto& simulated = model->components;
    if (std::find(simulated.begin(), simulated.end(), name) != simulated.end()) continue;
    // Engines whose model of this entity type simulates it.
    const std::vector<std::string> others = EnginesAbleToSimulate(type_label, name);
    return (attaching ? "its physics engine (" + EngineName(engine) + ")" : EngineName(engine)) +
           " does not simulate the " + name + " of a " + type_label +
           (others.empty() ? "; no engine does" : "; use " + Join(others, " or "));
  }
  return "";
}

void Simulation::Act() {
  for (auto& a : actuator_systems_) {
    pool_->ParallelFor(a->size(), 256, [&](size_t b, size_t e) { a->Act(b, e); });
  }
}

// Whether sensor instance k of every sensor system belongs to robots_[k]:
// every robot runs the same controller configuration, so each of its sensor
// systems holds one instance per robot, attached in the same order.
bool Simulation::SensorsAlignWithRobots() const {
  if (robots_.empty() || !one_config_) return false;
  for (const SensorSystem* s : robots_.front().config->sensors) {
    if (s->size() != robots_.size()) return false;
  }
  return true;
}

void Simulation::SenseAndControl() {
  // A controller that throws fails the run; the lowest robot index is
  // reported so the message does not depend on scheduling.
  std::mutex error_mutex;
  size_t error_robot = SIZE_MAX;
  std::string error_message;
  auto fail = [&](size_t robot, const std::string& message) {
    std::lock_guard lock(error_mutex);
    if (robot < error_robot) {
      error_robot = robot;
      error_message = message;
    }
  };
  // The tick being computed: which sensors sample on it (period="..."),
  // which configurations have events to deliver.
  const uint64_t now = tick_ + 1;
  if (!sensors_every_tick_) {
    for (size_t k = 0; k < sensor_systems_.size(); ++k)
      sensor_due_[k] = sensor_schedules_[k].Due(now);
  }
  bool all_plain = true;
  for (auto& config : controller_configs_) {
    config->watching = false;
    for (SensorSystem* s : config->sensors) config->watching = config->watching || s->HasWatches();
    all_plain = all_plain && config->Plain();
  }
  auto control = [&](size_t b, size_t e) {
    RunningScope running({"controller", nullptr, nullptr, nullptr, now});
    RunningCode& code = running.code();
    // This thread's event list, kept from tick to tick (no allocation once warm).
    static thread_local std::vector<SensorEvent> events;
    for (size_t i = b; i < e; ++i) {
      Robot& r = robots_[i];
      if (!r.alive) continue;
      code.label = r.config->label.c_str();
      code.library = r.config->library;
      code.robot = space_.id(r.entity.index).c_str();
      try {
        if (all_plain || r.config->Plain()) {
          r.controller->ControlStep();
        } else {
          StepTimed(r, now, events);
        }
      } catch (const std::exception& ex) {
        fail(i, ex.what());
      } catch (...) {
        fail(i, "it threw something that is not a std::exception");
      }
    }
  };
  if (SensorsAlignWithRobots()) {
    // Each chunk of robots is sensed, then controlled while its readings are
    // still in cache. Sensors read only the space and the media, which
    // controllers do not change during this step, so the results are those
    // of sensing every robot first.
    const ControllerConfig& config = *robots_.front().config;
    const auto& sensors = config.sensors;
    pool_->ParallelFor(robots_.size(), 64, [&](size_t b, size_t e) {
      if (sensors_every_tick_) {
        for (SensorSystem* s : sensors) s->Update(b, e);
      } else {
        for (size_t k = 0; k < sensors.size(); ++k) {
          if (sensor_due_[config.sensor_slots[k]]) sensors[k]->Update(b, e);
        }
      }
      control(b, e);
    });
  } else {
    for (size_t k = 0; k < sensor_systems_.size(); ++k) {
      if (!sensor_due_[k] && !sensors_every_tick_) continue;
      SensorSystem& s = *sensor_systems_[k];
      pool_->ParallelFor(s.size(), 64, [&](size_t b, size_t e) { s.Update(b, e); });
    }
    pool_->ParallelFor(robots_.size(), 64, control);
  }
  if (any_bus_) {
    // In robot order, after the parallel part: the same sum whatever the
    // thread count.
    for (Robot& r : robots_) {
      if (!r.timing) continue;
      bus_bytes_ += r.timing->bus_bytes;
      r.timing->bus_bytes = 0;
    }
    metrics_.Set("bus_bytes", static_cast<double>(bus_bytes_));
  }
  if (error_robot != SIZE_MAX) {
    const Robot& r = robots_[error_robot];
    throw RuntimeFailure("controller '" + r.config->label + "' of robot '" +
                         space_.id(r.entity.index) + "' failed at tick " +
                         std::to_string(tick_ + 1) + ": " + error_message);
  }
  StepBatches();
}

void Simulation::StepTimed(Robot& r, uint64_t tick, std::vector<SensorEvent>& events) {
  ControllerConfig& config = *r.config;
  const size_t ns = config.sensors.size();
  // Events first, sensor by sensor, then the step when due.
  if (config.watching) {
    for (size_t k = 0; k < ns; ++k) {
      SensorSystem& system = *config.sensors[k];
      if (!system.HasWatches()) continue;
      events.clear();
      system.TakeEvents(r.sensors[k], events);
      if (config.any_bus && config.sensor_bus[k])
        r.timing->bus_bytes += events.size() * BusEventBytes();
      for (const SensorEvent& event : events) r.controller->OnEvent(event);
    }
  }
  if (config.step_period == 0 || r.timing->step.Due(tick)) r.controller->ControlStep();
  // A sensor the controller read (in OnEvent or ControlStep) was polled.
  if (!config.any_bus) return;
  for (size_t k = 0; k < ns; ++k) {
    if (config.sensor_bus[k] && r.sensors[k]->TakeRead())
      r.timing->bus_bytes += BusPollBytes(config.sensors[k]->BusValues(r.sensors[k]));
  }
}

void Simulation::StepBatches() {
  for (auto& config : controller_configs_) {
    if (!config->batch) continue;
    // In the order of the robots' slots in the space (sim.robots' order in
    // Python), which is the order they were added until a removed robot's
    // slot is reused.
    config->by_slot.clear();
    for (Robot& r : robots_) {
      if (r.alive && r.config == config.get())
        config->by_slot.emplace_back(r.entity.index, r.controller.get());
    }
    if (config->by_slot.empty()) continue;
    if (!std::is_sorted(config->by_slot.begin(), config->by_slot.end()))
      std::sort(config->by_slot.begin(), config->by_slot.end());
    config->members.clear();
    for (const auto& [slot, controller] : config->by_slot) config->members.push_back(controller);
    RunningScope running(
        {"controller", config->label.c_str(), config->library, nullptr, tick_ + 1});
    auto failed = [&](const std::string& message) {
      return RuntimeFailure(config->node.file() + ":" + std::to_string(config->node.line()) +
                            ": controller '" + config->label + "' (configuration '" + config->id +
                            "', stepping its " + std::to_string(config->members.size()) +
                            " robots together) failed at tick " + std::to_string(tick_ + 1) + ": " +
                            message);
    };
    try {
      config->batch->Step(config->members);
    } catch (const std::exception& e) {
      throw failed(e.what());
    } catch (...) {
      throw failed("it threw something that is not a std::exception");
    }
  }
}

template <typename Hook>
void Simulation::CallLoopFunctions(const char* hook, uint64_t tick, Hook&& call) {
  for (size_t i = 0; i < loop_functions_.size(); ++i) {
    const PluginInfo& info = *loop_function_info_[i];
    metrics_.SetOwner(&info.label);
    const RunningScope running({"loop functions", info.label.c_str(),
                                info.library.empty() ? nullptr : info.library.c_str(), nullptr,
                                tick});
    try {
      call(*loop_functions_[i]);
    } catch (const std::exception& e) {
      throw RuntimeFailure("loop functions '" + info.label + "' failed in " + hook + " at tick " +
                           std::to_string(tick) + ": " + e.what());
    } catch (...) {
      throw RuntimeFailure("loop functions '" + info.label + "' failed in " + hook + " at tick " +
                           std::to_string(tick) +
                           ": it threw something that is not a std::exception");
    }
  }
}

void Simulation::CallResetHooks() {
  {
    RunningScope running({"controller", nullptr, nullptr, nullptr, 0});
    RunningCode& code = running.code();
    for (Robot& r : robots_) {
      if (!r.alive) continue;
      code.label = r.config->label.c_str();
      code.library = r.config->library;
      code.robot = space_.id(r.entity.index).c_str();
      auto failed = [&](const std::string& message) {
        return RuntimeFailure("controller '" + r.config->label + "' of robot '" +
                              space_.id(r.entity.index) + "' failed in Reset: " + message);
      };
      try {
        r.controller->Reset();
      } catch (const std::exception& e) {
        throw failed(e.what());
      } catch (...) {
        throw failed("it threw something that is not a std::exception");
      }
    }
  }
  CallLoopFunctions("Reset", 0, [](LoopFunctions& lf) { lf.Reset(); });
}

void Simulation::Step() {
  if (!reset_failure_.empty()) {
    throw RuntimeFailure("the simulation is empty: its last Reset failed (" + reset_failure_ +
                         "); call Reset again");
  }
  if (busy_) {
    throw std::logic_error(
        "Simulation::Step was called during a tick or while the simulation was being built "
        "(from a controller or loop functions)");
  }
  const BusyScope busy(busy_);
  using Clock = std::chrono::steady_clock;
  Clock::time_point mark = Clock::now();
  // Adds the time since the last mark to `phase`.
  auto lap = [&mark](double& phase) {
    const Clock::time_point now = Clock::now();
    phase += std::chrono::duration<double>(now - mark).count();
    mark = now;
  };
  // Entities added or removed since the last tick.
  if (space_.index_dirty()) space_.UpdateIndex();
  // 1. act
  Act();
  lap(profile_.act);
  // 2. physics (engines in parallel with each other), migration between
  // engines, then the spatial index for sensors and the next tick
  if (engines_.size() == 1) {
    engines_.front()->Step(dt_);
  } else {
    pool_->ParallelFor(engines_.size(), 1, [&](size_t b, size_t e) {
      for (size_t i = b; i < e; ++i) engines_[i]->Step(dt_);
    });
    Migrate();
  }
  space_.UpdateIndex();
  lap(profile_.physics);
  // 3. media
  for (auto& m : media_) m->Update();
  lap(profile_.media);
  // 4. loop functions pre-step
  CallLoopFunctions("PreStep", tick_ + 1, [](LoopFunctions& lf) { lf.PreStep(); });
  if (space_.index_dirty()) space_.UpdateIndex();
  lap(profile_.loop_functions);
  // 5. sense + control
  SenseAndControl();
  ++tick_;
  lap(profile_.sense_control);
  // 6. loop functions post-step and stop conditions
  CallLoopFunctions("PostStep", tick_, [](LoopFunctions& lf) { lf.PostStep(); });
  if (space_.index_dirty()) space_.UpdateIndex();
  done_ = length_ticks_ > 0 && tick_ >= length_ticks_;
  CallLoopFunctions("IsExperimentFinished", tick_,
                    [this](LoopFunctions& lf) { done_ = lf.IsExperimentFinished() || done_; });
  lap(profile_.loop_functions);
  ++profile_.ticks;
}

Renderer& Simulation::AddRenderer(const std::string& xml) {
  renderers_.push_back(NewRenderer(xml));
  added_renderers_.push_back(xml);
  return *renderers_.back();
}

std::unique_ptr<Renderer> Simulation::NewRenderer(const std::string& xml) {
  tinyxml2::XMLDocument fragment;
  if (fragment.Parse(xml.c_str()) != tinyxml2::XML_SUCCESS || !fragment.RootElement()) {
    throw ConfigError("AddRenderer: not well-formed XML: " + std::string(fragment.ErrorStr()));
  }
  ConfigContext context{"<AddRenderer>", {}};
  const ConfigNode node(fragment.RootElement(), &context);
  if (!HaveImageRenderer())
    throw ConfigError(NoImageRendererMessage("the renderer <" + node.name() + ">"));
  const auto* entry = Registry<Renderer>::Get().Find(node.name());
  if (!entry) {
    throw ConfigError("no renderer '" + node.name() +
                      "' in this build; available: " + Join(Registry<Renderer>::Get().Labels()));
  }
  node.CheckAttributes(entry->info.AttributeNames());
  auto renderer = entry->create();
  renderer->Bind(this);
  renderer->Configure(node);
  context.diagnostics.ThrowIfAny();
  return renderer;
}

uint64_t Simulation::StateHash() const {
  StateHasher h;
  h.AddU64(tick_);
  space_.Hash(h);
  for (const auto& s : sensor_systems_) s->Hash(h);
  return h.value();
}

}  // namespace colony
