// Building a simulation from an ExperimentSpec (core/experiment_spec.h), and
// adding entities to it while it runs.
#include <malloc.h>
#include <tinyxml2.h>

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <variant>

#include "core/bounds.h"
#include "core/placement.h"
#include "core/simulation.h"

namespace colony {

namespace {

// "a" or "an" before an entity type's name, as spoken ("an eyebot").
std::string Article(const std::string& word) {
  return !word.empty() && std::string("aeiou").find(word[0]) != std::string::npos ? "an" : "a";
}

// The registered plugin a spec names. A spec the reader made names only
// registered ones; a program may have changed it.
template <class Base>
const typename Registry<Base>::Entry* FindEntry(const PluginSpec& plugin, const ConfigNode& node,
                                                const char* what) {
  if (const auto* entry = Registry<Base>::Get().Find(plugin.label, plugin.implementation))
    return entry;
  node.ElementError(std::string("no ") + what + " '" + plugin.label + "' (implementation '" +
                    plugin.implementation +
                    "') is registered; accepted: " + Join(Registry<Base>::Get().Labels()));
  return nullptr;
}

// The entity as messages name it: `box id="b"`.
std::string EntityLabel(const EntityDesc& desc) {
  return desc.type + (desc.init.id.empty() ? "" : " id=\"" + desc.init.id + "\"");
}

}  // namespace

std::unique_ptr<Simulation> Simulation::Create(const ExperimentSpec& spec) {
  std::unique_ptr<Simulation> sim(new Simulation());
  sim->spec_ = spec;
  sim->Build(sim->spec_);
  return sim;
}

std::unique_ptr<Simulation> Simulation::Load(const ExperimentOptions& options) {
  return Create(ReadExperimentSpec(options));
}

void Simulation::Build(const ExperimentSpec& spec) {
  const BusyScope busy(busy_);
  file_ = spec.file;
  run_folder_ = spec.run_folder;
  document_ = spec.document;
  context_ = std::make_unique<ConfigContext>();
  context_->file = file_;
  dt_ = spec.dt;
  length_ticks_ = spec.length_ticks;
  seed_ = spec.seed;
  threads_ = std::max(1, spec.threads);
  output_ = spec.output;
  Diagnostics& diagnostics = context_->diagnostics;
  // Media first: sensors and actuators look theirs up when configured.
  CreateMedia(spec.media);
  CreateControllers(spec.controllers);
  if (any_bus_) metrics_.Set("bus_bytes", 0);
  CreateEngines(spec.engines);
  CreateRenderers(spec.renderers);
  diagnostics.ThrowIfAny();
  if (!pool_ || pool_->threads() != threads_) pool_ = std::make_unique<ThreadPool>(threads_);
  space_.set_pool(pool_.get());
  rng_ = RandomStream::For(seed_, "loop_functions", "");
  BuildArena(spec.arena);
  // The placement's scratch (its index, the poses of blocks numbered by
  // place) is freed among the robots' memory: its pages go back to the
  // system rather than stay resident until reused.
  malloc_trim(0);
  diagnostics.ThrowIfAny();
  for (const auto& [type, id] : entity_types_) {
    if (type) type->Placed(space_);
  }
  CreateLoopFunctions(spec.loop_functions, spec.arena);
  diagnostics.ThrowIfAny();
  space_.UpdateIndex();
}

void Simulation::Reset(std::optional<uint64_t> seed) {
  if (busy_) {
    throw std::logic_error(
        "Simulation::Reset was called during a tick or while the simulation was being built "
        "(from a controller or loop functions); call it between ticks");
  }
  const BusyScope busy(busy_);
  if (seed) spec_.seed = *seed;
  reset_failure_.clear();
  try {
    if (std::string failure = TearDown(); !failure.empty()) throw RuntimeFailure(failure);
    Build(spec_);
    for (const std::string& xml : added_renderers_) renderers_.push_back(NewRenderer(xml));
    CallResetHooks();
  } catch (const std::exception& e) {
    reset_failure_ = e.what();
    TearDown();
    throw;
  } catch (...) {
    reset_failure_ = "it threw something that is not a std::exception";
    TearDown();
    throw;
  }
}

std::string Simulation::TearDown() {
  // The Destroy hooks, as the destructor calls them; the first failure is
  // reported once everything is deleted.
  std::string failure;
  auto guarded = [&failure](auto&& call, auto&& name) {
    try {
      call();
    } catch (const std::exception& e) {
      if (failure.empty()) failure = name() + " failed in Destroy: " + e.what();
    } catch (...) {
      if (failure.empty())
        failure = name() + " failed in Destroy: it threw something that is not a std::exception";
    }
  };
  for (size_t i = 0; i < loop_functions_.size(); ++i) {
    guarded([&] { loop_functions_[i]->Destroy(); },
            [&] { return "loop functions '" + loop_function_info_[i]->label + "'"; });
  }
  for (Robot& r : robots_) {
    if (!r.alive || !r.controller) continue;
    guarded([&] { r.controller->Destroy(); },
            [&] {
              return "controller '" + r.config->label + "' of robot '" + space_.id(r.entity.index) +
                     "'";
            });
  }
  // In the reverse order of the members' declaration, as the destructor.
  model_info_.clear();
  entity_types_.clear();
  rng_ = RandomStream();
  profile_ = {};
  metrics_ = Metrics();
  media_.clear();
  renderers_.clear();
  loop_function_info_.clear();
  loop_functions_.clear();
  robot_count_ = 0;
  robot_of_.clear();
  actuator_tables_ = {};
  sensor_tables_ = {};
  robots_.clear();
  one_config_ = true;
  controller_configs_.clear();
  actuator_systems_.clear();
  sensor_systems_.clear();
  sensor_schedules_.clear();
  sensor_due_.clear();
  sensors_every_tick_ = true;
  any_bus_ = false;
  bus_bytes_ = 0;
  line_of_.clear();
  engine_of_.clear();
  model_storage_.clear();
  taken_by_.clear();
  models_.clear();
  engines_.clear();
  space_ = Space();
  tick_ = 0;
  done_ = false;
  generated_.reset();
  // A context for what the empty simulation may still be asked (AddEntity).
  context_ = std::make_unique<ConfigContext>();
  context_->file = file_;
  return failure;
}

void Simulation::SetControllerParam(const std::string& controller_id, const std::string& key,
                                    const std::string& value) {
  std::vector<std::string> ids;
  for (ControllerSpec& c : spec_.controllers) {
    if (c.plugin.id == controller_id) {
      c.params.Set(key, value);
      return;
    }
    ids.push_back(c.plugin.id);
  }
  throw std::invalid_argument("SetControllerParam: no controller configuration with id '" +
                              controller_id + "' in <controllers>; " +
                              (ids.empty() ? "there is none" : "there are: " + Join(ids)));
}

void Simulation::CreateMedia(const std::vector<PluginSpec>& media) {
  for (const PluginSpec& m : media) {
    const ConfigNode node = Node(m.node);
    const auto* entry = FindEntry<Medium>(m, node, "medium");
    if (!entry) continue;
    auto medium = entry->create();
    medium->Bind(this, m.id, entry->info.label);
    medium->Configure(node);
    media_.push_back(std::move(medium));
  }
}

void Simulation::CreateControllers(const std::vector<ControllerSpec>& controllers) {
  for (const ControllerSpec& c : controllers) {
    const ConfigNode node = Node(c.plugin.node);
    const auto* entry = FindEntry<Controller>(c.plugin, node, "controller");
    if (!entry) continue;
    auto config = std::make_unique<ControllerConfig>();
    config->id = c.plugin.id;
    config->label = c.plugin.label;
    config->entry = entry;
    config->node = node;
    config->params = c.params;
    CreateDevices(c.sensors, "sensor", config->sensor_labels, config->sensor_names, config->sensors,
                  config->sensor_nodes, sensor_systems_);
    for (size_t i = 0; i < config->sensors.size(); ++i)
      config->sensor_slots.push_back(sensor_systems_.size() - config->sensors.size() + i);
    ReadTiming(*config);
    CreateDevices(c.actuators, "actuator", config->actuator_labels, config->actuator_names,
                  config->actuators, config->actuator_nodes, actuator_systems_);
    config->labels = {&config->sensor_labels, &config->sensor_names, &config->actuator_labels,
                      &config->actuator_names, &run_folder_};
    controller_configs_.push_back(std::move(config));
  }
}

// The phase="..." of a device with a period of `period` seconds, in ticks:
// seconds in [0, period), or "random" (drawn from a stream named after
// `owner`). 0 when absent or bad (a bad one is recorded).
double Simulation::ReadPhase(const ConfigNode& node, double period, const std::string& owner) {
  if (!node.Has("phase")) return 0;
  const std::string text = node.GetString("phase", "");
  const double ticks = Schedule::Snap(period / dt_);
  if (text == "random") return RandomStream::For(seed_, owner, "phase").Uniform() * ticks;
  const double phase = node.GetDouble("phase", 0, Range::NonNegative());
  if (phase >= period) {
    node.Error("phase", text,
               "the phase '" + text + "' must be shorter than the period (" + FormatNumber(period) +
                   " s); accepted: a number of seconds in [0, " + FormatNumber(period) +
                   "), or \"random\"");
    return 0;
  }
  return Schedule::Snap(phase / dt_);
}

void Simulation::ReadTiming(ControllerConfig& config) {
  const double tps = 1.0 / dt_;
  const std::string per_tick =
      FormatNumber(dt_) + " s at " + FormatNumber(tps) + " ticks per second";
  for (size_t i = 0; i < config.sensors.size(); ++i) {
    const ConfigNode& node = config.sensor_nodes[i];
    Schedule schedule;
    if (node.Has("period")) {
      const double period = node.GetDouble("period", dt_, Range::Positive());
      if (period > 0 && Schedule::Snap(period / dt_) < 1) {
        node.Error("period", node.GetString("period", ""),
                   "a sensor samples at most once per tick: the period '" +
                       node.GetString("period", "") + "' is shorter than one tick (" + per_tick +
                       "); give a period >= " + FormatNumber(dt_) + " s, or more ticks_per_second");
      } else if (period > 0) {
        schedule = Schedule(period / dt_,
                            ReadPhase(node, period, config.id + "/" + config.sensor_labels[i]));
      }
    } else if (node.Has("phase")) {
      node.Error("phase", node.GetString("phase", ""),
                 "phase is the offset of a period's samples: give period=\"...\" too");
    }
    sensors_every_tick_ = sensors_every_tick_ && schedule.every_tick();
    sensor_schedules_.push_back(schedule);
    sensor_due_.push_back(1);
    const bool bus = node.GetBool("bus", false);
    config.sensor_bus.push_back(bus);
    config.any_bus = config.any_bus || bus;
  }
  any_bus_ = any_bus_ || config.any_bus;
  const ConfigNode& node = config.node;
  if (node.Has("rate")) {
    const double rate = node.GetDouble("rate", tps, Range::Positive());
    if (rate > 0 && Schedule::Snap(tps / rate) < 1) {
      node.Error("rate", node.GetString("rate", ""),
                 "a controller steps at most once per tick: the rate '" +
                     node.GetString("rate", "") + "' is above the simulation's " +
                     FormatNumber(tps) + " ticks per second; give a rate <= " + FormatNumber(tps) +
                     ", or more ticks_per_second");
    } else if (rate > 0) {
      config.step_period = Schedule::Snap(tps / rate);
    }
  }
  if (node.Has("phase")) {
    const std::string text = node.GetString("phase", "");
    if (!node.Has("rate")) {
      node.Error("phase", text, "phase is the offset of a rate's steps: give rate=\"...\" too");
    } else if (text == "random") {
      config.random_phase = true;
    } else if (config.step_period > 0) {
      config.step_phase = ReadPhase(node, config.step_period * dt_, "");
    }
  }
}

// One system per device element of a controller's <sensors> or <actuators>.
template <class System>
void Simulation::CreateDevices(const std::vector<PluginSpec>& devices, const char* what,
                               std::vector<std::string>& labels, std::vector<std::string>& names,
                               std::vector<System*>& systems, std::vector<ConfigNode>& nodes,
                               std::vector<std::unique_ptr<System>>& owned) {
  for (const PluginSpec& d : devices) {
    const ConfigNode node = Node(d.node);
    const auto* entry = FindEntry<System>(d, node, what);
    if (!entry) continue;
    auto system = entry->create();
    system->Bind(this);
    system->Configure(node);
    labels.push_back(d.label);
    names.push_back(entry->info.label);
    systems.push_back(system.get());
    nodes.push_back(node);
    owned.push_back(std::move(system));
  }
}

void Simulation::CreateEngines(const std::vector<EngineSpec>& engines) {
  std::vector<int> lines;  // of each engine's element
  for (const EngineSpec& spec : engines) {
    const ConfigNode node = Node(spec.plugin.node);
    const auto* entry = FindEntry<PhysicsEngine>(spec.plugin, node, "physics engine");
    if (!entry) continue;
    const std::string& id = spec.plugin.id;
    auto engine = entry->create();
    engine->Bind(this, id, entry->info.label);
    engine->Configure(node);
    if (spec.region) engine->SetRegion(*spec.region);
    engine->SetEntityTypes(spec.entity_types);
    // entities="...": each type simulated by this engine, and taken by no other.
    for (const std::string& type : spec.entity_types) {
      if (!Registry<PhysicsModel>::Get().Find(engine->label() + ":" + type)) {
        const std::vector<std::string> able = EnginesAbleToSimulate(type);
        node.Error("entities", Join(spec.entity_types),
                   engine->label() + " '" + id + "' cannot simulate " + Article(type) + " '" +
                       type + "' (no model " + engine->label() + ":" + type + " in this build)" +
                       (able.empty() ? "" : "; engines that can: " + Join(able)));
      }
      for (size_t k = 0; k < engines_.size(); ++k) {
        const auto& taken = engines_[k]->entity_types();
        if (std::find(taken.begin(), taken.end(), type) == taken.end()) continue;
        node.Error("entities", Join(spec.entity_types),
                   "entity type '" + type + "' is already taken by " +
                       EngineName(engines_[k].get()) + " (line " + std::to_string(lines[k]) +
                       "); an entity type may be taken by one engine only");
      }
    }
    // 3D engines (gravity, ditches, stacking) and 2D ones (bodies on the
    // floor) do not share movable entities: among engines that take what
    // their regions hold, all are 2D or all 3D. An engine that takes entity
    // types (eye-bots in pointmass3d) may be of either kind.
    if (!engine->takes_types()) {
      for (size_t k = 0; k < engines_.size(); ++k) {
        const PhysicsEngine& first = *engines_[k];
        if (first.takes_types()) continue;
        if (engine->Is3D() == first.Is3D()) break;
        const auto dims = [](const PhysicsEngine& e) {
          return e.Is3D() ? std::string("3D") : std::string("2D");
        };
        node.ElementError(engine->label() + " '" + id + "' is a " + dims(*engine) +
                          " engine and cannot share an experiment's regions with " + dims(first) +
                          " engines (" + first.label() + " '" + first.id() + "', line " +
                          std::to_string(lines[k]) +
                          "); use only 3D engines or only 2D ones, or let one take entity types "
                          "wherever they are (e.g. entities=\"eyebot\")");
        break;
      }
    }
    // Two engines of one kind that take what their regions hold must not
    // simulate the same place.
    for (size_t k = 0; k < engines_.size(); ++k) {
      const PhysicsEngine& other = *engines_[k];
      if (other.label() != engine->label() || other.takes_types() || engine->takes_types())
        continue;
      const bool overlap =
          !engine->region() || !other.region() || engine->region()->Overlaps(*other.region());
      if (overlap) {
        node.ElementError("the region of " + engine->label() + " '" + id + "' overlaps that of " +
                          other.label() + " '" + other.id() + "' (line " +
                          std::to_string(lines[k]) + ")" +
                          (!engine->region() || !other.region()
                               ? "; an engine without <boundaries> covers the whole arena"
                               : ""));
      }
    }
    lines.push_back(node.line());
    engines_.push_back(std::move(engine));
  }
}

void Simulation::CreateRenderers(const std::vector<PluginSpec>& renderers) {
  for (const PluginSpec& r : renderers) {
    const ConfigNode node = Node(r.node);
    const auto* entry = FindEntry<Renderer>(r, node, "renderer");
    if (!entry) continue;
    auto renderer = entry->create();
    renderer->Bind(this);
    renderer->Configure(node);
    renderers_.push_back(std::move(renderer));
  }
}

// Refuses the arena's entities, before any is built, when together they
// would need more memory than the machine has: a rough estimate per entity
// (core/bounds.h) times the quantity of every <distribute> block, plus the
// entities listed one by one.
bool Simulation::CheckMemory(const ArenaSpec& arena) {
  const uint64_t available = AvailableMemoryBytes();
  auto bytes_of = [](const EntityDesc& desc) -> uint64_t {
    const auto* entry = Registry<EntityType>::Get().Find(desc.type);
    return entry && EntityTypeInstance(*entry).is_robot() ? kEstimatedBytesPerRobot
                                                          : kEstimatedBytesPerEntity;
  };
  double needed = 0;
  for (const auto& item : arena.contents) {
    if (const auto* desc = std::get_if<EntityDesc>(&item)) {
      needed += static_cast<double>(bytes_of(*desc));
      continue;
    }
    const DistributeSpec& block = std::get<DistributeSpec>(item);
    uint64_t each = bytes_of(block.entity);
    for (const auto& c : controller_configs_) {
      if (c->id != block.entity.controller) continue;
      for (const SensorSystem* sensor : c->sensors) each += sensor->BytesPerRobot();
      for (const ActuatorSystem* actuator : c->actuators) each += actuator->BytesPerRobot();
    }
    const double before = needed;
    needed += static_cast<double>(each) * static_cast<double>(block.quantity);
    if (needed <= static_cast<double>(available)) continue;
    const double room =
        std::max(0.0, (static_cast<double>(available) - before) / static_cast<double>(each));
    const std::string quantity = std::to_string(block.quantity);
    context_->diagnostics.Add(Diagnostic{
        file_, block.entity_line, "entity", "quantity", quantity,
        quantity + " " + block.entity.type + " entities would need about " + FormatBytes(needed) +
            " of memory (about " + FormatBytes(static_cast<double>(each)) + " each" +
            (before > 0 ? ", with the entities before them" : "") + "), more than the " +
            FormatBytes(static_cast<double>(available)) + " this machine has; accepted: at most " +
            std::to_string(static_cast<uint64_t>(room)) + " of them here"});
    return false;
  }
  return true;
}

void Simulation::BuildArena(const ArenaSpec& arena) {
  if (!CheckMemory(arena)) return;
  space_.SetArena(arena.center, arena.size);
  const Vec3 lo = arena.center - 0.5 * arena.size, hi = arena.center + 0.5 * arena.size;
  if (arena.ceiling.present)
    space_.SetCeiling(Space::Ceiling{lo.z() + arena.ceiling.height, arena.ceiling.ferromagnetic});
  Floor& floor = space_.floor();
  for (const Ditch& ditch : arena.floor.ditches) floor.AddDitch(ditch);
  floor.SetColor(arena.floor.color);
  if (!arena.floor.image.empty()) {
    std::filesystem::path p(arena.floor.image);
    if (p.is_relative() && !file_.empty()) {
      const auto rel = std::filesystem::path(file_).parent_path() / p;
      std::error_code ec;
      if (std::filesystem::exists(rel, ec)) p = rel;
    }
    const std::string error = floor.LoadImage(p.string(), lo.x(), lo.y(), hi.x(), hi.y());
    if (!error.empty()) {
      context_->diagnostics.Add(
          Diagnostic{file_, arena.floor.line, "floor", "path", arena.floor.image, error});
    }
  }
  size_t expected = arena.walls.size();
  for (const auto& item : arena.contents) {
    const auto* block = std::get_if<DistributeSpec>(&item);
    expected += block ? static_cast<size_t>(block->quantity) : 1;
  }
  PlacementIndex placed(0.5, space_, expected);
  for (const EntityDesc& wall : arena.walls) Add(wall, PlacementCheck::kClear, &placed);
  // A <distribute> block adds what it found room for (and files it in
  // `placed` itself): checking again would cast the same footprint against
  // the same neighbours.
  auto add = [&](const EntityDesc& desc) { return Add(desc, PlacementCheck::kNone, nullptr); };
  for (const auto& item : arena.contents) {
    if (const auto* desc = std::get_if<EntityDesc>(&item)) {
      Add(*desc, PlacementCheck::kClear, &placed);
    } else {
      const DistributeSpec& block = std::get<DistributeSpec>(item);
      // Room for the whole block up front: arrays grown by doubling would
      // leave up to half of them unused, and copying them sets the peak.
      const size_t more = static_cast<size_t>(block.quantity);
      space_.Reserve(more, block.entity.init);
      const size_t slots = space_.slots() + more;
      engine_of_.reserve(slots);
      robot_of_.reserve(slots);
      line_of_.reserve(slots);
      PlaceDistributed(block, seed_, file_, space_, placed, add, context_->diagnostics);
    }
  }
}

void Simulation::CreateLoopFunctions(const std::optional<PluginSpec>& loop_functions,
                                     const ArenaSpec& arena) {
  if (!loop_functions) return;
  const ConfigNode node = Node(loop_functions->node);
  const auto* entry = FindEntry<LoopFunctions>(*loop_functions, node, "loop functions");
  if (!entry) return;
  const ConfigNode params_node = node.Child("params");
  const Params params = params_node.valid() ? params_node.ToParams() : Params();
  auto lf = entry->create();
  lf->Bind(this);
  metrics_.SetOwner(&entry->info.label);
  try {
    lf->Init(params);
  } catch (const ParamError& e) {
    params_node.Error(e.key(), e.value(), e.what());
  } catch (const MetricNameError& e) {
    node.ElementError(e.what());
  }
  if (const double ppm = arena.floor.loop_functions_pixels_per_meter; ppm > 0) {
    if (!lf->DrawsFloor()) {
      context_->diagnostics.Add(Diagnostic{
          file_, arena.floor.line, "floor", "source", "loop_functions",
          "the loop functions '" + entry->info.label +
              "' do not colour the floor (they do not override DrawsFloor and FloorColor); "
              "accepted: loop functions that do, or source=\"color\" or \"image\""});
    } else {
      const Vec3 lo = arena.center - 0.5 * arena.size, hi = arena.center + 0.5 * arena.size;
      const int w = std::max(1, static_cast<int>(std::ceil(arena.size.x() * ppm)));
      const int h = std::max(1, static_cast<int>(std::ceil(arena.size.y() * ppm)));
      std::vector<Color> pixels(static_cast<size_t>(w) * h);
      for (int py = 0; py < h; ++py) {
        const double y = hi.y() - (py + 0.5) * arena.size.y() / h;
        for (int px = 0; px < w; ++px) {
          const double x = lo.x() + (px + 0.5) * arena.size.x() / w;
          pixels[static_cast<size_t>(py) * w + px] = lf->FloorColor(x, y);
        }
      }
      space_.floor().SetImage(w, h, std::move(pixels),
                              "the loop functions '" + entry->info.label + "'", lo.x(), lo.y(),
                              hi.x(), hi.y());
    }
  }
  loop_functions_.push_back(std::move(lf));
  loop_function_info_.push_back(&entry->info);
}

void Simulation::EntityError(const EntityDesc& desc, const std::string& attribute,
                             const std::string& value, const std::string& message) {
  context_->diagnostics.Add(Diagnostic{desc.line > 0 ? file_ : "", desc.line, EntityLabel(desc),
                                       attribute, value, message});
}

EntityHandle Simulation::Add(const EntityDesc& desc, PlacementCheck check, PlacementIndex* placed) {
  const auto& registry = Registry<EntityType>::Get();
  const auto* entry = registry.Find(desc.type);
  if (!entry) {
    std::string message = "unknown entity type '" + desc.type + "'";
    const std::string guess = DidYouMean(desc.type, registry.Labels());
    if (!guess.empty()) message += " (did you mean '" + guess + "'?)";
    EntityError(desc, "", "", message + "; accepted: " + Join(registry.Labels()));
    return {};
  }
  const EntityType& type = EntityTypeInstance(*entry);
  const std::string& id = desc.init.id;
  if (id.empty()) {
    EntityError(desc, "id", "", "an entity needs an id, unique in the experiment");
    return {};
  }
  auto has_controller = [&] {
    return std::any_of(controller_configs_.begin(), controller_configs_.end(),
                       [&](const auto& c) { return c->id == desc.controller; });
  };
  if (type.is_robot()) {
    if (!has_controller()) {
      std::vector<std::string> ids;
      for (const auto& c : controller_configs_) ids.push_back(c->id);
      std::string message =
          desc.controller.empty()
              ? "a " + entry->info.label + " needs a controller: the id of one of the <controllers>"
              : "no controller with id '" + desc.controller + "' is defined in <controllers>";
      const std::string guess = desc.controller.empty() ? "" : DidYouMean(desc.controller, ids);
      if (!guess.empty()) message += " (did you mean '" + guess + "'?)";
      EntityError(desc, "", "",
                  message + (ids.empty() ? "; none is defined" : "; defined: " + Join(ids)));
      return {};
    }
  } else if (!desc.controller.empty()) {
    EntityError(
        desc, "", "",
        "a " + entry->info.label + " carries no controller (only robots do); accepted: none");
    return {};
  }
  if (const EntityHandle existing = space_.Find(id); existing.valid()) {
    const int first = line_of_[existing.index];
    const std::string where =
        first > 0 ? " (first defined at line " + std::to_string(first) + ")" : "";
    EntityError(desc, "id", id, "duplicate entity id '" + id + "'" + where);
    return {};
  }
  if (check == PlacementCheck::kClear) {
    const std::string problem =
        placed ? PlacementProblem(desc.init, space_, *placed) : PlaceProblemNow(desc.init);
    if (!problem.empty()) {
      EntityError(desc, "", "",
                  "entity '" + id + "' " + problem +
                      "; accepted: a body wholly inside the arena, not overlapping solid entities "
                      "(only fixed ones may overlap each other)");
      return {};
    }
  }
  const Space::EntityInit& init = desc.init;
  const uint16_t type_id = space_.TypeId(entry->info.label);
  if (entity_types_.size() <= type_id) entity_types_.resize(type_id + 1);
  entity_types_[type_id] = {&type, type_id};
  const std::vector<PhysicsModel*>& models = ModelsFor(type_id, entry->info.label);
  const bool simulated =
      std::any_of(models.begin(), models.end(), [](PhysicsModel* m) { return m; });
  if (init.geometry.shape != ShapeKind::kNone && !simulated) {
    std::vector<std::string> engines;
    for (const auto& e : engines_) engines.push_back(e->label() + " '" + e->id() + "'");
    const std::string& label = entry->info.label;
    const std::vector<std::string> able = EnginesAbleToSimulate(label);
    const int taker = taken_by_[type_id];
    EntityError(
        desc, "", "",
        engines.empty()
            ? "entity '" + id +
                  "' needs a physics engine, but <physics_engines> declares none; add e.g. "
                  "<kinematics2d id=\"k2d\"/>"
            : "no physics engine of this experiment can simulate " + Article(label) + " '" + label +
                  "' (engines: " + Join(engines) + "; no model registered for " +
                  (taker >= 0 ? engines_[taker]->label() : engines_.front()->label()) + ":" +
                  label + ")" +
                  (able.empty() ? "; no engine in this build can"
                                : "; engines that can: " + Join(able) + ", e.g. <" + able.front() +
                                      " id=\"" + able.front() + "\" entities=\"" + label + "\"/>"));
    return {};
  }
  const std::vector<int> engines = EnginesFor(desc, type_id, models);
  if (init.geometry.shape != ShapeKind::kNone && engines.empty()) return {};
  const EntityHandle h = Instantiate(desc, type_id, models.data(), engines, desc.line);
  if (placed && (init.flags & kSolid)) placed->Insert(h.index, desc.line);
  return h;
}

std::string Simulation::PlaceProblemNow(const Space::EntityInit& init, uint32_t self) {
  if (init.geometry.shape == ShapeKind::kNone) return "";
  if (std::string outside = OutsideArenaProblem(init, space_); !outside.empty()) return outside;
  if (!(init.flags & kSolid)) return "";
  if (space_.index_dirty()) space_.UpdateIndex();
  const Vec2 half = FootprintHalfExtents(init.geometry, init.pose.orientation);
  const Vec3& p = init.pose.position;
  std::vector<uint32_t> near;
  space_.Gather(p.x() - half.x(), p.y() - half.y(), p.x() + half.x(), p.y() + half.y(), near);
  std::sort(near.begin(), near.end());
  // As at load: fixed entities may touch each other.
  const bool movable = init.flags & kMovable;
  for (uint32_t s : near) {
    if (s == self || (!movable && !space_.movable(s))) continue;
    if (!FootprintsOverlap(init.pose, init.geometry, space_.pose(s), space_.geometry(s))) continue;
    return "overlaps '" + space_.id(s) + "'" +
           (line_of_[s] > 0 ? " (line " + std::to_string(line_of_[s]) + ")" : "");
  }
  return "";
}

std::vector<std::string> Simulation::EnginesAbleToSimulate(const std::string& type,
                                                           const std::string& component) {
  std::vector<std::string> able;
  const std::string suffix = ":" + type;
  for (const PluginInfo* info : AllPlugins()) {
    if (info->kind != PluginKind::kPhysicsModel || !info->label.ends_with(suffix)) continue;
    const auto& simulated = info->components;
    if (!component.empty() &&
        std::find(simulated.begin(), simulated.end(), component) == simulated.end())
      continue;
    able.push_back(info->label.substr(0, info->label.size() - suffix.size()));
  }
  return able;
}

std::vector<PhysicsModel*>& Simulation::ModelsFor(uint16_t type, const std::string& label) {
  if (models_.size() <= type) models_.resize(type + 1);
  if (taken_by_.size() <= type) taken_by_.resize(type + 1, -1);
  auto& models = models_[type];
  if (models.size() != engines_.size()) {
    models.assign(engines_.size(), nullptr);
    // A type an engine takes (entities="...") is that engine's alone, for
    // its movable entities (EnginesFor); fixed ones are in every engine.
    taken_by_[type] = -1;
    for (size_t e = 0; e < engines_.size(); ++e) {
      const auto& taken = engines_[e]->entity_types();
      if (std::find(taken.begin(), taken.end(), label) != taken.end())
        taken_by_[type] = static_cast<int>(e);
    }
    for (size_t e = 0; e < engines_.size(); ++e) {
      if (const auto* m = Registry<PhysicsModel>::Get().Find(engines_[e]->label() + ":" + label)) {
        model_storage_.push_back(m->create());
        models[e] = model_storage_.back().get();
      }
    }
  }
  return models;
}

std::vector<int> Simulation::EnginesFor(const EntityDesc& desc, uint16_t type,
                                        const std::vector<PhysicsModel*>& models) {
  std::vector<int> chosen;
  const auto& init = desc.init;
  if (init.geometry.shape == ShapeKind::kNone) return chosen;
  const Vec3& p = init.pose.position;
  const Vec2 half = FootprintHalfExtents(init.geometry, init.pose.orientation);
  const bool movable = init.flags & kMovable;
  // A movable entity goes to the engine that takes its type or, if none
  // does, to the first engine (in file order) that takes no types and whose
  // region holds it; a fixed one to every engine whose region it touches.
  const int taker = taken_by_[type];
  bool only_takers = movable && taker < 0;  // every engine with a model takes other types
  for (size_t e = 0; e < engines_.size(); ++e) {
    if (!models[e]) continue;
    const PhysicsEngine& engine = *engines_[e];
    if (movable && taker >= 0) {
      if (static_cast<int>(e) != taker) continue;
    } else if (movable && engine.takes_types()) {
      continue;
    }
    only_takers = false;
    if (movable && engine.Holds(p)) {
      chosen.push_back(static_cast<int>(e));
      break;
    }
    if (!movable &&
        (!engine.region() ||
         engine.region()->Touches(p.head<2>(), half, p.z(), p.z() + init.geometry.height()))) {
      chosen.push_back(static_cast<int>(e));
    }
  }
  if (chosen.empty() && only_takers) {
    std::vector<std::string> takers;
    for (size_t e = 0; e < engines_.size(); ++e) {
      if (models[e])
        takers.push_back(EngineName(engines_[e].get()) + ": " + Join(engines_[e]->entity_types()));
    }
    const std::string& label = space_.TypeLabel(type);
    EntityError(desc, "", "",
                "entity '" + init.id + "' is a movable " + label +
                    ", and every engine that can simulate " + Article(label) + " " + label +
                    " takes only the entity types it lists (" + Join(takers, "; ") +
                    "); add an engine without entities=\"...\", or list " + label + " in one");
  } else if (chosen.empty()) {
    std::vector<std::string> names;
    for (size_t e = 0; e < engines_.size(); ++e)
      if (models[e]) names.push_back(engines_[e]->label() + " '" + engines_[e]->id() + "'");
    std::ostringstream s;
    s << "entity '" << init.id << "' at (" << p.x() << ", " << p.y() << ", " << p.z() << ") is "
      << (movable ? "inside" : "touching")
      << " no engine's <boundaries> (engines that can simulate it: " << Join(names) << ")";
    EntityError(desc, "", "", s.str());
  }
  return chosen;
}

EntityHandle Simulation::AddEntity(const EntityDesc& desc, PlacementCheck check) {
  const bool id_was_free = !space_.Find(desc.init.id).valid();
  EntityHandle h;
  try {
    h = Add(desc, check, nullptr);
    context_->diagnostics.ThrowIfAny();
    if (h.valid()) entity_types_[space_.type(h.index)].first->Placed(space_);
  } catch (const ConfigError&) {
    // A robot whose devices or controller failed to start is taken out again.
    if (id_was_free) Withdraw(desc.init.id);
    throw;
  }
  space_.UpdateIndex();
  return h;
}

EntityHandle Simulation::AddEntity(const std::string& xml) {
  return AddEntity(ReadEntityDesc(xml, "<AddEntity>"));
}

void Simulation::Withdraw(const std::string& id) {
  const EntityHandle h = space_.Find(id);
  if (!h.valid() || robot_of_[h.index] < 0) return;
  // Its devices are detached and its controller deleted (not Destroyed: it
  // did not start).
  Robot& robot = robots_[robot_of_[h.index]];
  ControllerConfig& config = *robot.config;
  for (size_t i = 0; i < config.sensors.size(); ++i) {
    if (robot.sensors[i]) config.sensors[i]->Detach(robot.sensors[i]);
  }
  for (size_t i = 0; i < config.actuators.size(); ++i) {
    if (robot.actuators[i]) config.actuators[i]->Detach(robot.actuators[i]);
  }
  robot.controller.reset();
  robot.alive = false;
  robot_of_[h.index] = -1;
  for (auto& engine : engines_) {
    if (!engine->Owns(h.index)) continue;
    engine->RemoveEntity(h);
    engine->SetOwned(h.index, false);
  }
  engine_of_[h.index] = -1;
  space_.Remove(h);
  space_.UpdateIndex();
}

Medium* Simulation::MediumFor(const ConfigNode& device, const std::string& label) {
  auto& registry = Registry<Medium>::Get();
  if (device.Has("medium")) {
    const std::string id = device.GetString("medium", "");
    std::vector<std::string> same_kind;
    for (auto& m : media_) {
      if (m->id() == id) {
        if (m->label() == label) return m.get();
        device.Error("medium", id,
                     "medium '" + id + "' is a <" + m->label() + ">, not a <" + label + ">");
        return nullptr;
      }
      if (m->label() == label) same_kind.push_back(m->id());
    }
    device.Error("medium", id,
                 "no medium with id '" + id + "' in <media>; accepted: " +
                     (same_kind.empty() ? "the id of a <" + label + "> declared in <media>"
                                        : Join(same_kind)));
    return nullptr;
  }
  Medium* found = nullptr;
  int count = 0;
  for (auto& m : media_) {
    if (m->label() == label) {
      found = m.get();
      ++count;
    }
  }
  if (count == 1) return found;
  if (count > 1) {
    device.ElementError("<media> declares several <" + label +
                        "> media; say which with medium=\"id\"");
    return nullptr;
  }
  // None declared: one with default settings, shared by every device that names none.
  const auto* entry = registry.Find(label, "default");
  if (!entry) {
    device.ElementError("needs a <" + label + "> medium, and none is available in this build");
    return nullptr;
  }
  if (!generated_) generated_ = std::make_unique<tinyxml2::XMLDocument>();
  auto* element = generated_->NewElement(label.c_str());
  element->SetAttribute("id", label.c_str());
  auto medium = entry->create();
  medium->Bind(this, label, label);
  medium->Configure(ConfigNode(element, context_.get()));
  media_.push_back(std::move(medium));
  return media_.back().get();
}

std::string Simulation::ResolvedXml() const {
  if (!document_) return "";
  tinyxml2::XMLPrinter printer;
  document_->xml->Print(&printer);
  return printer.CStr();
}

}  // namespace colony
