// Experiment files: XML -> validated, built Simulation.
#include <tinyxml2.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include "core/bounds.h"
#include "core/overrides.h"
#include "core/placement.h"
#include "core/plugin_loader.h"
#include "core/simulation.h"
#include "core/xml_errors.h"

namespace colony {

namespace {

const std::vector<std::string> kTopLevel = {"framework",       "controllers", "loop_functions",
                                            "arena",           "physics_engines", "media",
                                            "visualization",   "output"};

// Whether `parent` holds a misspelling of `name`, already reported as an
// unknown element (so "missing <name>" would only repeat it).
bool HasMisspelt(const ConfigNode& parent, const std::string& name) {
  for (const ConfigNode& child : parent.Children()) {
    if (child.name() != name && DidYouMean(child.name(), {name}) == name) return true;
  }
  return false;
}

// One stateless instance per registered entity type.
const EntityType& EntityTypeInstance(const Registry<EntityType>::Entry* entry) {
  static std::map<const void*, std::unique_ptr<EntityType>> types;
  auto& type = types[entry];
  if (!type) type = entry->create();
  return *type;
}

}  // namespace

class ExperimentLoader {
 public:
  ExperimentLoader(Simulation& sim, const ExperimentOptions& options) : sim_(sim), options_(options) {}

  void Load();
  // Builds one entity element (used at load and by Simulation::AddEntity).
  EntityHandle BuildEntity(const ConfigNode& node, const Pose* placed, bool check_placement);

 private:
  ConfigContext& ctx() { return *sim_.context_; }
  Diagnostics& diag() { return sim_.context_->diagnostics; }
  void Parse();
  void ReadFramework(const ConfigNode& root);
  void ReadControllers(const ConfigNode& root);
  void ReadEngines(const ConfigNode& root);
  void ReadMedia(const ConfigNode& root);
  void ReadOptionalSections(const ConfigNode& root);
  void ReadArena(const ConfigNode& root);
  void ReadDistribute(const ConfigNode& node);
  bool CheckMemory(const ConfigNode& arena);
  void ReadLoopFunctions(const ConfigNode& root);
  void ReadOutput(const ConfigNode& root);
  bool LoadLibraryAttribute(const ConfigNode& node);
  bool ReadEntityDesc(const ConfigNode& node, const EntityType& type, EntityDesc& desc, bool needs_body);
  std::string CheckPlacement(const EntityDesc& desc);
  std::vector<int> EnginesFor(const EntityDesc& desc, const std::vector<const PhysicsModel*>& models,
                              const ConfigNode& node);
  void ReadBoundaries(const ConfigNode& engine_node, PhysicsEngine& engine);
  template <class System>
  void ReadDevices(const ConfigNode& section, const std::string& what, std::vector<std::string>& labels,
                   std::vector<System*>& systems, std::vector<ConfigNode>& nodes,
                   std::vector<std::unique_ptr<System>>& owned);

  Simulation& sim_;
  const ExperimentOptions& options_;
  std::map<std::string, int> entity_lines_;
  std::vector<int> ids_line_;  // line of each engine's element
  std::unique_ptr<PlacementIndex> placement_;
  int generated_line_ = 0;  // the line of <walls> while its boxes are built
};

void ExperimentLoader::Parse() {
  auto& doc = *sim_.document_;
  const std::string& file = sim_.file_;
  const std::string text =
      options_.text.empty() && !options_.file.empty() ? ReadExperimentText(options_.file) : options_.text;
  ParseExperimentXml(text, file, doc);
  for (const auto& o : options_.overrides) ApplyOverride(doc, o, file);
}

void ExperimentLoader::ReadFramework(const ConfigNode& root) {
  const ConfigNode framework = root.Child("framework");
  if (!framework.valid()) {
    if (HasMisspelt(root, "framework")) return;
    root.ElementError("missing <framework> (it holds <experiment length ticks_per_second random_seed>)");
    return;
  }
  framework.CheckAttributes({});
  framework.CheckChildren({"system", "experiment", "profiling"});
  framework.CheckAtMostOne("system");
  framework.CheckAtMostOne("experiment");
  const ConfigNode system = framework.Child("system");
  int threads = 0;
  if (system.valid()) {
    system.CheckAttributes({"threads", "method"});
    threads = static_cast<int>(system.GetInt("threads", 0, 0, 256));
  }
  const ConfigNode experiment = framework.Child("experiment");
  if (!experiment.valid()) {
    if (HasMisspelt(framework, "experiment")) return;
    framework.ElementError("missing <experiment length=\"seconds\" ticks_per_second=\"10\" random_seed=\"1\"/>");
    return;
  }
  experiment.CheckAttributes({"length", "ticks_per_second", "random_seed", "real_time"});
  const double length = experiment.GetDouble("length", 0, Range::NonNegative());
  const double tps = experiment.GetDouble("ticks_per_second", 10, {0, 1e6, true});
  const int64_t seed = experiment.GetInt("random_seed", 0, 0, INT64_MAX);
  if (length * tps >= 9e18) {
    experiment.Error("length", experiment.GetString("length", ""),
                     "the experiment would last over 9e18 ticks; accepted: length * ticks_per_second < 9e18 (0: unlimited)");
  }
  sim_.dt_ = 1.0 / tps;
  sim_.length_ticks_ = static_cast<uint64_t>(std::llround(length * tps));
  if (length > 0 && sim_.length_ticks_ == 0) sim_.length_ticks_ = 1;
  sim_.seed_ = options_.seed ? *options_.seed : static_cast<uint64_t>(seed);
  // 0 and 1 both run everything on the calling thread: report 1.
  sim_.threads_ = std::max(1, options_.threads ? *options_.threads : threads);
}

bool ExperimentLoader::LoadLibraryAttribute(const ConfigNode& node) {
  if (!node.Has("library")) return true;
  const std::string spec = node.GetString("library", "");
  const std::string base = std::filesystem::path(sim_.file_).parent_path().string();
  const std::string error = LoadPluginLibrary(spec, base);
  if (error.empty()) return true;
  node.Error("library", spec, error);
  return false;
}

template <class Base>
static const typename Registry<Base>::Entry* FindPlugin(const ConfigNode& node, const std::string& what,
                                                        const std::string& label, const std::string& impl) {
  auto& registry = Registry<Base>::Get();
  if (const auto* entry = registry.Find(label, impl)) return entry;
  if (registry.Find(label)) {
    node.Error("implementation", impl, "no implementation '" + impl + "' of " + what + " '" + label +
                                           "'; accepted: " + Join(registry.Implementations(label)));
    return nullptr;
  }
  std::string message = "unknown " + what + " '" + label + "'";
  const std::string guess = DidYouMean(label, registry.Labels());
  if (!guess.empty()) message += " (did you mean '" + guess + "'?)";
  auto labels = registry.Labels();
  message += labels.empty() ? "; none is available in this build" : "; accepted: " + Join(labels);
  node.ElementError(message);
  return nullptr;
}

void ExperimentLoader::ReadControllers(const ConfigNode& root) {
  const ConfigNode controllers = root.Child("controllers");
  if (!controllers.valid()) return;
  controllers.CheckAttributes({});
  std::map<std::string, int> ids;
  for (const ConfigNode& node : controllers.Children()) {
    node.CheckAttributes({"id", "library"});
    node.CheckChildren({"sensors", "actuators", "params"});
    const std::string id = node.RequireString("id");
    if (!id.empty()) {
      if (ids.count(id)) {
        node.Error("id", id, "controller id '" + id + "' already defined at line " + std::to_string(ids[id]));
      }
      ids[id] = node.line();
    }
    if (!LoadLibraryAttribute(node)) continue;
    const auto* entry = FindPlugin<Controller>(node, "controller", node.name(), "default");
    if (!entry) {
      if (!node.Has("library")) {
        auto d = Diagnostic{ctx().file, node.line(), node.Label(), "library", "",
                            "hint: a controller built as a plugin is loaded with library=\"NAME or path\""};
        diag().Add(d);
      }
      continue;
    }
    auto config = std::make_unique<Simulation::ControllerConfig>();
    config->id = id;
    config->label = node.name();
    config->entry = entry;
    config->node = node;
    const ConfigNode params = node.Child("params");
    node.CheckAtMostOne("params");
    node.CheckAtMostOne("sensors");
    node.CheckAtMostOne("actuators");
    if (params.valid()) {
      params.CheckChildren({});
      config->params = params.ToParams();
    }
    ReadDevices(node.Child("sensors"), "sensor", config->sensor_labels, config->sensors, config->sensor_nodes,
                sim_.sensor_systems_);
    ReadDevices(node.Child("actuators"), "actuator", config->actuator_labels, config->actuators,
                config->actuator_nodes, sim_.actuator_systems_);
    sim_.controller_configs_.push_back(std::move(config));
  }
}

// Creates one system per device element of a controller's <sensors> or
// <actuators>, checking its attributes against the registered list.
template <class System>
void ExperimentLoader::ReadDevices(const ConfigNode& section, const std::string& what, std::vector<std::string>& labels,
                                   std::vector<System*>& systems, std::vector<ConfigNode>& nodes,
                                   std::vector<std::unique_ptr<System>>& owned) {
  for (const ConfigNode& d : section.Children()) {
    const std::string impl = d.GetString("implementation", "default");
    const auto* entry = FindPlugin<System>(d, what, d.name(), impl);
    if (!entry) continue;
    auto names = entry->info.AttributeNames();
    names.push_back("implementation");
    d.CheckAttributes(names);
    auto system = entry->create();
    system->Bind(&sim_);
    system->Configure(d);
    labels.push_back(d.name());
    systems.push_back(system.get());
    nodes.push_back(d);
    owned.push_back(std::move(system));
  }
}

void ExperimentLoader::ReadEngines(const ConfigNode& root) {
  const ConfigNode engines = root.Child("physics_engines");
  if (!engines.valid()) return;
  engines.CheckAttributes({});
  std::map<std::string, int> ids;
  for (const ConfigNode& node : engines.Children()) {
    const auto* entry = FindPlugin<PhysicsEngine>(node, "physics engine", node.name(), "default");
    if (!entry) continue;
    auto names = entry->info.AttributeNames();
    names.push_back("id");
    node.CheckAttributes(names);
    const std::string id = node.RequireString("id");
    if (ids.count(id)) node.Error("id", id, "engine id '" + id + "' already used at line " + std::to_string(ids[id]));
    ids[id] = node.line();
    node.CheckChildren({"boundaries"});
    node.CheckAtMostOne("boundaries");
    auto engine = entry->create();
    engine->Bind(&sim_, id, entry->info.label);
    engine->Configure(node);
    ReadBoundaries(node, *engine);
    // 3D engines (gravity, ditches, stacking) and 2D ones (bodies on the floor) do not mix.
    if (!sim_.engines_.empty() && engine->Is3D() != sim_.engines_.front()->Is3D()) {
      const PhysicsEngine& first = *sim_.engines_.front();
      const auto dims = [](const PhysicsEngine& e) { return e.Is3D() ? std::string("3D") : std::string("2D"); };
      node.ElementError(engine->label() + " '" + id + "' is a " + dims(*engine) + " engine and cannot share an experiment with " +
                        dims(first) + " engines (" + first.label() + " '" + first.id() + "', line " +
                        std::to_string(ids_line_.front()) + "); use only 3D engines or only 2D ones");
    }
    // Two engines of one kind must not simulate the same place.
    for (size_t k = 0; k < sim_.engines_.size(); ++k) {
      const PhysicsEngine& other = *sim_.engines_[k];
      if (other.label() != engine->label()) continue;
      const bool overlap = !engine->region() || !other.region() || engine->region()->Overlaps(*other.region());
      if (overlap) {
        node.ElementError("the region of " + engine->label() + " '" + id + "' overlaps that of " + other.label() +
                          " '" + other.id() + "' (line " + std::to_string(ids_line_[k]) + ")" +
                          (!engine->region() || !other.region() ? "; an engine without <boundaries> covers the whole arena" : ""));
      }
    }
    ids_line_.push_back(node.line());
    sim_.engines_.push_back(std::move(engine));
  }
}

void ExperimentLoader::ReadBoundaries(const ConfigNode& engine_node, PhysicsEngine& engine) {
  const ConfigNode b = engine_node.Child("boundaries");
  if (!b.valid()) return;
  b.CheckAttributes({});
  b.CheckChildren({"top", "bottom", "sides"});
  for (const char* part : {"top", "bottom", "sides"}) b.CheckAtMostOne(part);
  Region region;
  if (const ConfigNode top = b.Child("top"); top.valid()) {
    top.CheckAttributes({"height"});
    region.top = top.RequireDouble("height");
  }
  if (const ConfigNode bottom = b.Child("bottom"); bottom.valid()) {
    bottom.CheckAttributes({"height"});
    region.bottom = bottom.RequireDouble("height");
  }
  if (region.bottom >= region.top) {
    b.ElementError("the bottom height must be below the top height");
  }
  const ConfigNode sides = b.Child("sides");
  if (!sides.valid()) {
    b.ElementError("missing <sides> with at least three <vertex point=\"x,y\"/>, counter-clockwise");
    return;
  }
  sides.CheckAttributes({"size"});
  sides.CheckChildren({"vertex"});
  for (const ConfigNode& v : sides.Children("vertex")) {
    v.CheckAttributes({"point"});
    const std::string raw = v.RequireString("point");
    const auto parts = SplitList(raw);
    double x = 0, y = 0;
    if (parts.size() != 2 || !ParseFiniteDouble(parts[0], x) || !ParseFiniteDouble(parts[1], y)) {
      if (!raw.empty()) v.Error("point", raw, "'" + raw + "' is not two finite numbers; accepted: \"x,y\"");
      continue;
    }
    region.vertices.emplace_back(x, y);
  }
  const int64_t size = sides.GetInt("size", static_cast<int64_t>(region.vertices.size()), 3, 100000);
  if (size != static_cast<int64_t>(region.vertices.size())) {
    sides.Error("size", sides.GetString("size", ""), "says " + std::to_string(size) + " vertices but " +
                                                        std::to_string(region.vertices.size()) + " are given");
  }
  const std::string problem = region.Problem();
  if (!problem.empty()) {
    sides.ElementError(problem);
    return;
  }
  engine.SetRegion(std::move(region));
}

void ExperimentLoader::ReadMedia(const ConfigNode& root) {
  const ConfigNode node = root.Child("media");
  if (!node.valid()) return;
  node.CheckAttributes({});
  std::map<std::string, int> ids;
  for (const ConfigNode& child : node.Children()) {
    const auto* entry = FindPlugin<Medium>(child, "medium", child.name(), "default");
    if (!entry) continue;
    auto names = entry->info.AttributeNames();
    names.push_back("id");
    child.CheckAttributes(names);
    const std::string id = child.GetString("id", child.name());
    if (const auto [it, fresh] = ids.emplace(id, child.line()); !fresh) {
      child.Error("id", id, "duplicate medium id '" + id + "' (first at line " + std::to_string(it->second) +
                                "); give each medium its own id");
      continue;
    }
    auto medium = entry->create();
    medium->Bind(&sim_, id, entry->info.label);
    medium->Configure(child);
    sim_.media_.push_back(std::move(medium));
  }
}

void ExperimentLoader::ReadOptionalSections(const ConfigNode& root) {
  const ConfigNode node = root.Child("visualization");
  if (!node.valid()) return;
  node.CheckAttributes({});
  for (const ConfigNode& child : node.Children()) {
    if (const auto* entry = FindPlugin<Renderer>(child, "renderer", child.name(), "default")) {
      child.CheckAttributes(entry->info.AttributeNames());
      auto renderer = entry->create();
      renderer->Bind(&sim_);
      renderer->Configure(child);
      sim_.renderers_.push_back(std::move(renderer));
    }
  }
}

Medium* Simulation::MediumFor(const ConfigNode& device, const std::string& label) {
  auto& registry = Registry<Medium>::Get();
  if (device.Has("medium")) {
    const std::string id = device.GetString("medium", "");
    std::vector<std::string> same_kind;
    for (auto& m : media_) {
      if (m->id() == id) {
        if (m->label() == label) return m.get();
        device.Error("medium", id, "medium '" + id + "' is a <" + m->label() + ">, not a <" + label + ">");
        return nullptr;
      }
      if (m->label() == label) same_kind.push_back(m->id());
    }
    device.Error("medium", id, "no medium with id '" + id + "' in <media>; accepted: " +
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
    device.ElementError("<media> declares several <" + label + "> media; say which with medium=\"id\"");
    return nullptr;
  }
  // None declared: one with default settings, shared by every device that names none.
  const auto* entry = registry.Find(label, "default");
  if (!entry) {
    device.ElementError("needs a <" + label + "> medium, and none is available in this build");
    return nullptr;
  }
  auto* element = document_->NewElement(label.c_str());
  element->SetAttribute("id", label.c_str());
  auto medium = entry->create();
  medium->Bind(this, label, label);
  medium->Configure(ConfigNode(element, context_.get()));
  media_.push_back(std::move(medium));
  return media_.back().get();
}

bool ExperimentLoader::ReadEntityDesc(const ConfigNode& node, const EntityType& type, EntityDesc& desc,
                                      bool needs_body) {
  Diagnostics& diagnostics = node.context().diagnostics;
  const size_t before = diagnostics.size();
  desc.init.id = node.RequireString("id");
  type.Build(node, desc);
  if (type.has_body()) {
    node.CheckAtMostOne("body");
    const ConfigNode body = node.Child("body");
    if (body.valid()) {
      body.CheckAttributes({"position", "orientation"});
      body.CheckChildren({});
      const auto p = body.RequireTriple("position");
      const auto o = body.GetTriple("orientation", {0, 0, 0});
      desc.init.pose.position = Vec3(p[0], p[1], p[2]);
      desc.init.pose.orientation = FromEulerZYX(DegToRad(o[0]), DegToRad(o[1]), DegToRad(o[2]));
    } else if (needs_body) {
      node.ElementError("missing <body position=\"x,y,z\" orientation=\"yaw,pitch,roll\"/>");
    }
  }
  if (type.is_robot()) {
    node.CheckAtMostOne("controller");
    const ConfigNode c = node.Child("controller");
    if (!c.valid()) {
      node.ElementError("missing <controller config=\"ID\"/> naming one of the <controllers>");
    } else {
      c.CheckAttributes({"config"});
      c.CheckChildren({});
      desc.controller = c.RequireString("config");
      bool found = false;
      std::vector<std::string> ids;
      for (const auto& cfg : sim_.controller_configs_) {
        ids.push_back(cfg->id);
        found = found || cfg->id == desc.controller;
      }
      if (!found && !desc.controller.empty()) {
        std::string message = "no controller with id '" + desc.controller + "' is defined in <controllers>";
        const std::string guess = DidYouMean(desc.controller, ids);
        if (!guess.empty()) message += " (did you mean '" + guess + "'?)";
        message += ids.empty() ? "" : "; defined: " + Join(ids);
        c.Error("config", desc.controller, message);
      }
    }
  }
  std::vector<std::string> children;
  if (type.has_body()) children.push_back("body");
  if (type.is_robot()) children.push_back("controller");
  node.CheckChildren(children);
  return diagnostics.size() == before;
}

std::string ExperimentLoader::CheckPlacement(const EntityDesc& desc) {
  return PlacementProblem(desc.init, sim_.space_, *placement_);
}

EntityHandle ExperimentLoader::BuildEntity(const ConfigNode& node, const Pose* placed, bool check_placement) {
  const auto* entry = FindPlugin<EntityType>(node, "entity type", node.name(), "default");
  if (!entry) return {};
  const EntityType* type = &EntityTypeInstance(entry);
  auto names = entry->info.AttributeNames();
  names.push_back("id");
  node.CheckAttributes(names);
  EntityDesc desc;
  if (!ReadEntityDesc(node, *type, desc, placed == nullptr)) return {};
  if (placed) desc.init.pose = *placed;
  const std::string& id = desc.init.id;
  if (entity_lines_.count(id) || sim_.space_.Find(id).valid()) {
    node.Error("id", id, "duplicate entity id '" + id + "'" +
                             (entity_lines_.count(id) ? " (first defined at line " + std::to_string(entity_lines_[id]) + ")" : ""));
    return {};
  }
  if (check_placement && placement_) {
    const std::string problem = CheckPlacement(desc);
    if (!problem.empty()) {
      node.ElementError("entity '" + id + "' " + problem +
                        "; accepted: a body wholly inside the arena, not overlapping solid entities "
                            "(only fixed ones may overlap each other)");
      return {};
    }
  }
  desc.init.type = sim_.space_.TypeId(entry->info.label);
  if (sim_.entity_types_.size() <= desc.init.type) sim_.entity_types_.resize(desc.init.type + 1);
  sim_.entity_types_[desc.init.type] = {type, desc.init.type};
  // Physics models of this type, one per engine.
  if (sim_.models_.size() <= desc.init.type) sim_.models_.resize(desc.init.type + 1);
  auto& models = sim_.models_[desc.init.type];
  if (models.size() != sim_.engines_.size()) {
    models.assign(sim_.engines_.size(), nullptr);
    for (size_t e = 0; e < sim_.engines_.size(); ++e) {
      const std::string label = sim_.engines_[e]->label() + ":" + entry->info.label;
      if (const auto* m = Registry<PhysicsModel>::Get().Find(label)) {
        sim_.model_storage_.push_back(m->create());
        models[e] = sim_.model_storage_.back().get();
      }
    }
  }
  if (desc.init.geometry.shape != ShapeKind::kNone) {
    bool any = false;
    for (const auto* m : models) any = any || m;
    if (!any) {
      std::vector<std::string> engines;
      for (const auto& e : sim_.engines_) engines.push_back(e->label() + " '" + e->id() + "'");
      node.ElementError(engines.empty()
                            ? "entity '" + id + "' needs a physics engine, but <physics_engines> declares none; add e.g. <kinematics2d id=\"k2d\"/>"
                            : "no physics engine of this experiment can simulate a '" + entry->info.label +
                                  "' (engines: " + Join(engines) + "; no model registered for " +
                                  sim_.engines_.front()->label() + ":" + entry->info.label + ")");
      return {};
    }
  }
  const std::vector<int> engines = EnginesFor(desc, models, node);
  if (desc.init.geometry.shape != ShapeKind::kNone && engines.empty()) return {};
  // Entities made by the loader (walls) have no line of their own.
  const int line = node.line() > 0 ? node.line() : generated_line_;
  entity_lines_[id] = line;
  if (check_placement && placement_ && (desc.init.flags & kSolid)) {
    placement_->Insert(desc.init.pose, desc.init.geometry, id, line, desc.init.flags & kMovable);
  }
  return sim_.Instantiate(desc, models.data(), engines, node);
}

std::vector<int> ExperimentLoader::EnginesFor(const EntityDesc& desc, const std::vector<const PhysicsModel*>& models,
                                              const ConfigNode& node) {
  std::vector<int> chosen;
  const auto& init = desc.init;
  if (init.geometry.shape == ShapeKind::kNone) return chosen;
  const Vec3& p = init.pose.position;
  const Vec2 half = FootprintHalfExtents(init.geometry, init.pose.orientation);
  const bool movable = init.flags & kMovable;
  // A movable entity goes to the first engine (in file order) whose region
  // holds it; a fixed one to every engine whose region it touches.
  for (size_t e = 0; e < sim_.engines_.size(); ++e) {
    if (!models[e]) continue;
    const PhysicsEngine& engine = *sim_.engines_[e];
    if (movable && engine.Holds(p)) {
      chosen.push_back(static_cast<int>(e));
      break;
    }
    if (!movable && (!engine.region() || engine.region()->Touches(p.head<2>(), half, p.z(), p.z() + init.geometry.height()))) {
      chosen.push_back(static_cast<int>(e));
    }
  }
  if (chosen.empty()) {
    std::vector<std::string> names;
    for (size_t e = 0; e < sim_.engines_.size(); ++e)
      if (models[e]) names.push_back(sim_.engines_[e]->label() + " '" + sim_.engines_[e]->id() + "'");
    std::ostringstream s;
    s << "entity '" << init.id << "' at (" << p.x() << ", " << p.y() << ", " << p.z() << ") is "
      << (movable ? "inside" : "touching") << " no engine's <boundaries> (engines that can simulate it: "
      << Join(names) << ")";
    node.ElementError(s.str());
  }
  return chosen;
}

void ExperimentLoader::ReadDistribute(const ConfigNode& node) {
  // Problems found elsewhere do not stop this block from being checked.
  const size_t errors_before = diag().size();
  node.CheckAttributes({});
  node.CheckChildren({"position", "orientation", "entity"});
  for (const char* part : {"position", "orientation", "entity"}) {
    node.CheckAtMostOne(part);
    if (!node.Child(part).valid()) node.ElementError(std::string("missing <") + part + ">");
  }
  if (diag().size() != errors_before) return;
  struct Generator {
    std::string method;
    std::array<double, 3> a{}, b{};
    std::vector<std::array<double, 3>> values;
  };
  auto read_generator = [&](const ConfigNode& g, Generator& out, bool degrees) {
    const std::vector<std::string> methods = {"uniform", "gaussian", "constant", "grid"};
    out.method = g.GetChoice("method", methods, "");
    if (!g.Has("method")) g.Error("method", "", "required attribute is missing; accepted: uniform, gaussian, constant, grid");
    if (out.method == "uniform") {
      g.CheckAttributes({"method", "min", "max"});
      out.a = g.RequireTriple("min");
      out.b = g.RequireTriple("max");
      for (int k = 0; k < 3; ++k)
        if (out.a[k] > out.b[k]) g.Error("max", g.GetString("max", ""), "each component of max must be >= the same component of min");
    } else if (out.method == "gaussian") {
      g.CheckAttributes({"method", "mean", "std_dev"});
      out.a = g.RequireTriple("mean");
      out.b = g.RequireTriple("std_dev", Range::NonNegative());
    } else if (out.method == "constant") {
      g.CheckAttributes({"method", "values"});
      out.a = g.RequireTriple("values");
    } else if (out.method == "grid") {
      g.CheckAttributes({"method", "center", "distances", "layout"});
      out.a = g.RequireTriple("center");
      out.b = g.RequireTriple("distances", Range::NonNegative());
      const auto layout = g.RequireTriple("layout", Range::Between(1, 1e7));
      const double places = layout[0] * layout[1] * layout[2];
      bool whole = true;
      for (double v : layout) whole = whole && v == std::floor(v);
      if (!whole || places > 1e7) {
        g.Error("layout", g.GetString("layout", ""),
                "'" + g.GetString("layout", "") + "' is not a usable grid; accepted: three whole numbers >= 1 (places along x, y, z) "
                "whose product is at most 10000000");
        return;
      }
      // Grid cells, filled x fastest, then y, then z.
      const int nx = static_cast<int>(layout[0]), ny = static_cast<int>(layout[1]), nz = static_cast<int>(layout[2]);
      for (int z = 0; z < nz; ++z)
        for (int y = 0; y < ny; ++y)
          for (int x = 0; x < nx; ++x)
            out.values.push_back({out.a[0] + (x - (nx - 1) / 2.0) * out.b[0], out.a[1] + (y - (ny - 1) / 2.0) * out.b[1],
                                  out.a[2] + (z - (nz - 1) / 2.0) * out.b[2]});
    }
    if (degrees) {
      for (auto* v : {&out.a, &out.b})
        for (double& c : *v) c = DegToRad(c);
      for (auto& v : out.values)
        for (double& c : v) c = DegToRad(c);
    }
  };
  const ConfigNode pos_node = node.Child("position"), ori_node = node.Child("orientation"), ent_node = node.Child("entity");
  Generator pos, ori;
  read_generator(pos_node, pos, false);
  read_generator(ori_node, ori, true);
  ent_node.CheckAttributes({"quantity", "max_trials", "base_num"});
  const int64_t quantity = ent_node.RequireInt("quantity", 1, kMaxDistributeQuantity);
  const int64_t max_trials = ent_node.GetInt("max_trials", 100, 1, 1'000'000);
  const int64_t base_num = ent_node.GetInt("base_num", 0, 0, INT64_MAX);
  const auto templates = ent_node.Children();
  if (templates.size() != 1) ent_node.ElementError("must hold exactly one entity element (e.g. <marxbot id=\"mb\">), found " + std::to_string(templates.size()));
  if (diag().size() != errors_before) return;
  if (pos.method == "grid" && static_cast<int64_t>(pos.values.size()) < quantity) {
    pos_node.Error("layout", pos_node.GetString("layout", ""), "the grid has " + std::to_string(pos.values.size()) +
                                                                    " places, fewer than quantity=" + std::to_string(quantity));
    return;
  }
  const ConfigNode tmpl = templates.front();
  const std::string base_id = tmpl.GetString("id", "");
  RandomStream rng = RandomStream::For(sim_.seed_, "distribute", std::to_string(node.line()));
  auto draw = [&](Generator& g, size_t index) -> Vec3 {
    if (g.method == "uniform") return Vec3(rng.Uniform(g.a[0], g.b[0]), rng.Uniform(g.a[1], g.b[1]), rng.Uniform(g.a[2], g.b[2]));
    if (g.method == "gaussian") return Vec3(rng.Gaussian(g.a[0], g.b[0]), rng.Gaussian(g.a[1], g.b[1]), rng.Gaussian(g.a[2], g.b[2]));
    if (g.method == "grid") return Vec3(g.values[index][0], g.values[index][1], g.values[index][2]);
    return Vec3(g.a[0], g.a[1], g.a[2]);
  };
  const auto* entry = FindPlugin<EntityType>(tmpl, "entity type", tmpl.name(), "default");
  if (!entry) return;
  const EntityType& type = EntityTypeInstance(entry);
  // The template element is built once per entity under its numbered id.
  auto* element = const_cast<tinyxml2::XMLElement*>(tmpl.element());
  for (int64_t i = 0; i < quantity; ++i) {
    const std::string id = base_id + std::to_string(base_num + i);
    element->SetAttribute("id", id.c_str());
    bool placed = false;
    std::string last_problem;
    for (int64_t trial = 0; trial < max_trials && !placed; ++trial) {
      Pose pose;
      pose.position = draw(pos, static_cast<size_t>(i));
      const Vec3 o = draw(ori, static_cast<size_t>(i));
      pose.orientation = FromEulerZYX(o[0], o[1], o[2]);
      // Probe the footprint quietly; the real build below reports problems.
      EntityDesc probe;
      ConfigContext scratch{ctx().file, {}};
      type.Build(ConfigNode(element, &scratch), probe);
      probe.init.id = id;
      probe.init.pose = pose;
      last_problem = CheckPlacement(probe);
      if (!last_problem.empty()) continue;
      placed = true;
      if (!BuildEntity(tmpl, &pose, true).valid()) {
        element->SetAttribute("id", base_id.c_str());
        return;
      }
    }
    if (!placed) {
      ent_node.Error("max_trials", std::to_string(max_trials),
                     "could place only " + std::to_string(i) + " of " + std::to_string(quantity) + " entities: '" + id +
                         "' found no free place in " + std::to_string(max_trials) + " trials (last try: it " +
                         last_problem + "); enlarge the <position> range or the arena, lower quantity, or raise max_trials");
      break;
    }
  }
  element->SetAttribute("id", base_id.c_str());
}

// Refuses the arena's entities, before any is built, when together they
// would need more memory than the machine has: a rough estimate per entity
// (core/bounds.h) times the quantity of every <distribute> block, plus the
// entities listed one by one. Problems with the blocks themselves are
// reported when they are read.
bool ExperimentLoader::CheckMemory(const ConfigNode& arena) {
  const uint64_t available = AvailableMemoryBytes();
  double needed = 0;
  for (const ConfigNode& child : arena.Children()) {
    if (const auto* entry = Registry<EntityType>::Get().Find(child.name())) {
      needed += EntityTypeInstance(entry).is_robot() ? kEstimatedBytesPerRobot : kEstimatedBytesPerEntity;
      continue;
    }
    if (child.name() != "distribute") continue;
    const ConfigNode entity = child.Child("entity");
    const auto templates = entity.Children();
    ConfigContext scratch{ctx().file, {}};
    const int64_t quantity = ConfigNode(entity.element(), &scratch).GetInt("quantity", 0, 1, kMaxDistributeQuantity);
    if (templates.size() != 1 || !scratch.diagnostics.empty()) continue;
    const ConfigNode& tmpl = templates.front();
    const auto* entry = Registry<EntityType>::Get().Find(tmpl.name());
    if (!entry) continue;
    uint64_t each = EntityTypeInstance(entry).is_robot() ? kEstimatedBytesPerRobot : kEstimatedBytesPerEntity;
    const std::string config = tmpl.Child("controller").GetString("config", "");
    for (const auto& c : sim_.controller_configs_) {
      if (c->id != config) continue;
      for (const SensorSystem* sensor : c->sensors) each += sensor->BytesPerRobot();
      for (const ActuatorSystem* actuator : c->actuators) each += actuator->BytesPerRobot();
    }
    const double before = needed;
    needed += static_cast<double>(each) * static_cast<double>(quantity);
    if (needed <= static_cast<double>(available)) continue;
    const double room = std::max(0.0, (static_cast<double>(available) - before) / static_cast<double>(each));
    entity.Error("quantity", std::to_string(quantity),
                 std::to_string(quantity) + " " + tmpl.name() + " entities would need about " + FormatBytes(needed) +
                     " of memory (about " + FormatBytes(static_cast<double>(each)) + " each" +
                     (before > 0 ? ", with the entities before them" : "") + "), more than the " +
                     FormatBytes(static_cast<double>(available)) + " this machine has; accepted: at most " +
                     std::to_string(static_cast<uint64_t>(room)) + " of them here");
    return false;
  }
  return true;
}

void ExperimentLoader::ReadArena(const ConfigNode& root) {
  const ConfigNode arena = root.Child("arena");
  if (!arena.valid()) {
    if (HasMisspelt(root, "arena")) return;
    root.ElementError("missing <arena size=\"x,y,z\"> holding the robots and objects");
    return;
  }
  std::vector<std::string> children = {"floor", "walls", "distribute"};
  for (const auto& l : Registry<EntityType>::Get().Labels()) children.push_back(l);
  arena.CheckAttributes({"size", "center", "positional_grid_size"});
  arena.CheckChildren(children);
  arena.CheckAtMostOne("floor");
  arena.CheckAtMostOne("walls");
  // Without a size nothing can be placed; other problems do not stop the
  // entities from being checked, so all are reported together.
  const size_t errors_before = diag().size();
  const auto size = arena.RequireTriple("size", {0, kMaxArenaExtent, true});
  const auto s = Vec3(size[0], size[1], size[2]);
  const auto c = arena.GetTriple("center", {0, 0, size[2] / 2}, Range::Between(-kMaxArenaExtent, kMaxArenaExtent));
  const Vec3 center(c[0], c[1], c[2]);
  if (diag().size() != errors_before || !CheckMemory(arena)) return;
  sim_.space_.SetArena(center, s);
  placement_ = std::make_unique<PlacementIndex>(0.5);
  const Vec3 lo = center - 0.5 * s, hi = center + 0.5 * s;

  if (const ConfigNode floor = arena.Child("floor"); floor.valid()) {
    floor.CheckAttributes({"id", "color", "source", "path"});
    floor.CheckChildren({"ditch"});
    const auto ditches = floor.Children("ditch");
    const bool too_many = static_cast<int64_t>(ditches.size()) > kMaxDitches;
    if (too_many) {
      ditches[kMaxDitches].ElementError("the floor has " + std::to_string(ditches.size()) + " ditches; accepted: at most " +
                                        std::to_string(kMaxDitches) + " <ditch> elements (join neighbouring ones)");
    }
    for (const ConfigNode& d : too_many ? std::vector<ConfigNode>{} : floor.Children()) {
      d.CheckAttributes({"center", "size", "depth"});
      d.CheckChildren({});
      const size_t before = diag().size();
      const auto dc = d.RequirePair("center");
      const auto ds = d.RequirePair("size", Range::Positive());
      const double depth = d.GetDouble("depth", 0.06, Range::Positive());
      if (diag().size() != before) continue;
      Ditch ditch{dc[0] - ds[0] / 2, dc[1] - ds[1] / 2, dc[0] + ds[0] / 2, dc[1] + ds[1] / 2, depth};
      if (ditch.min_x < lo.x() || ditch.max_x > hi.x() || ditch.min_y < lo.y() || ditch.max_y > hi.y()) {
        d.Error("center", d.GetString("center", ""), "the ditch reaches outside the arena; accepted: a centre and size "
                                                     "keeping it within the arena's floor");
        continue;
      }
      if (depth >= s.z()) {
        d.Error("depth", d.GetString("depth", ""), "the ditch is deeper than the arena is high; accepted: a depth > 0 and < " +
                                                     FormatNumber(s.z()));
        continue;
      }
      sim_.space_.floor().AddDitch(ditch);
    }
    const std::string source = floor.GetChoice("source", {"color", "image"}, floor.Has("path") ? "image" : "color");
    sim_.space_.floor().SetColor(floor.GetColor("color", Color::White()));
    if (source == "image") {
      std::string path = floor.RequireString("path");
      if (!path.empty()) {
        std::filesystem::path p(path);
        if (p.is_relative() && !sim_.file_.empty()) {
          const auto rel = std::filesystem::path(sim_.file_).parent_path() / p;
          std::error_code ec;
          if (std::filesystem::exists(rel, ec)) p = rel;
        }
        const std::string error = sim_.space_.floor().LoadImage(p.string(), lo.x(), lo.y(), hi.x(), hi.y());
        if (!error.empty()) floor.Error("path", path, error);
      }
    }
  }
  if (const ConfigNode walls = arena.Child("walls"); walls.valid()) {
    walls.CheckAttributes({"thickness", "height", "color"});
    walls.CheckChildren({});
    const size_t wall_errors = diag().size();
    const double t = walls.GetDouble("thickness", 0.1, Range::Positive());
    const double h = walls.GetDouble("height", 0.5, Range::Positive());
    const std::string color = walls.GetString("color", "gray50");
    if (!ParseColor(color)) walls.Error("color", color, "'" + color + "' is not a colour; accepted: " + kColorAccepted);
    if (2 * t >= std::min(s.x(), s.y())) {
      const std::string raw = walls.GetString("thickness", "");
      walls.Error("thickness", raw, "walls " + raw + " m thick leave no room inside the arena; accepted: a number > 0 and < " +
                                        FormatNumber(std::min(s.x(), s.y()) / 2) + " (half the arena's smaller side)");
    }
    if (h > s.z()) {
      const std::string raw = walls.GetString("height", "");
      walls.Error("height", raw, "walls are taller than the arena; accepted: a number > 0 and <= " + FormatNumber(s.z()) +
                                     " (the arena's height)");
    }
    // Bad walls are reported; the entities are still checked.
    if (diag().size() == wall_errors) {
      // Four boxes lining the inside of the arena's edges.
      struct Side {
        const char* id;
        double x, y, sx, sy;
      } sides[] = {
          {"wall_north", center.x(), hi.y() - t / 2, s.x(), t},
          {"wall_south", center.x(), lo.y() + t / 2, s.x(), t},
          {"wall_east", hi.x() - t / 2, center.y(), t, s.y() - 2 * t},
          {"wall_west", lo.x() + t / 2, center.y(), t, s.y() - 2 * t},
      };
      generated_line_ = walls.line();
      for (const auto& side : sides) {
        auto* e = sim_.document_->NewElement("box");
        e->SetAttribute("id", side.id);
        // Every digit: rounded figures could put a wall a hair outside the arena.
        auto exact = [](double v) {
          char buffer[32];
          std::snprintf(buffer, sizeof buffer, "%.17g", v);
          return std::string(buffer);
        };
        const std::string sz = exact(side.sx) + "," + exact(side.sy) + "," + exact(h);
        e->SetAttribute("size", sz.c_str());
        e->SetAttribute("movable", "false");
        e->SetAttribute("color", color.c_str());
        auto* body = e->InsertNewChildElement("body");
        const std::string pos = exact(side.x) + "," + exact(side.y) + "," + exact(lo.z());
        body->SetAttribute("position", pos.c_str());
        // Keep the walls' line for messages: parse it as if written there.
        ConfigContext& context = ctx();
        tinyxml2::XMLElement* parent = const_cast<tinyxml2::XMLElement*>(walls.element());
        parent->InsertEndChild(e);
        BuildEntity(ConfigNode(e, &context), nullptr, true);
        parent->DeleteChild(e);
      }
      generated_line_ = 0;
    }
  }
  for (const ConfigNode& child : arena.Children()) {
    const std::string n = child.name();
    if (n == "floor" || n == "walls") continue;
    if (n == "distribute") {
      ReadDistribute(child);
      continue;
    }
    if (Registry<EntityType>::Get().Find(n)) BuildEntity(child, nullptr, true);
  }
}

void ExperimentLoader::ReadLoopFunctions(const ConfigNode& root) {
  root.CheckAtMostOne("loop_functions");
  const ConfigNode node = root.Child("loop_functions");
  if (!node.valid()) return;
  node.CheckChildren({"params"});
  if (!LoadLibraryAttribute(node)) return;
  const std::string label = node.RequireString("label");
  if (label.empty()) return;
  const auto* entry = Registry<LoopFunctions>::Get().Find(label);
  if (!entry) {
    std::string message = "unknown loop functions '" + label + "'";
    const std::string guess = DidYouMean(label, Registry<LoopFunctions>::Get().Labels());
    if (!guess.empty()) message += " (did you mean '" + guess + "'?)";
    const auto labels = Registry<LoopFunctions>::Get().Labels();
    message += labels.empty() ? "; none is loaded (give library=\"...\")" : "; accepted: " + Join(labels);
    node.Error("label", label, message);
    return;
  }
  node.CheckAttributes({"library", "label"});
  const ConfigNode params_node = node.Child("params");
  Params params;
  if (params_node.valid()) {
    auto names = entry->info.AttributeNames();
    params_node.CheckAttributes(names);
    params = params_node.ToParams();
  }
  diag().ThrowIfAny();
  auto lf = entry->create();
  lf->Bind(&sim_);
  try {
    lf->Init(params);
  } catch (const ParamError& e) {
    params_node.Error(e.key(), e.value(), e.what());
  }
  sim_.loop_functions_.push_back(std::move(lf));
  sim_.loop_function_info_.push_back(&entry->info);
}

void ExperimentLoader::ReadOutput(const ConfigNode& root) {
  root.CheckAtMostOne("output");
  const ConfigNode node = root.Child("output");
  if (!node.valid()) return;
  node.CheckAttributes({"metrics_every", "hash_every"});
  node.CheckChildren({});
  sim_.output_.metrics_every = static_cast<uint64_t>(node.GetInt("metrics_every", 1, 0, INT64_MAX));
  sim_.output_.hash_every = static_cast<uint64_t>(node.GetInt("hash_every", 0, 0, INT64_MAX));
}

void ExperimentLoader::Load() {
  Parse();
  const ConfigNode root(sim_.document_->RootElement(), &ctx());
  root.CheckChildren(kTopLevel);
  for (const auto& section : kTopLevel) root.CheckAtMostOne(section);
  ReadFramework(root);
  ReadOutput(root);
  diag().ThrowIfAny();
  // Media first: sensors and actuators look theirs up when configured.
  ReadMedia(root);
  ReadControllers(root);
  ReadEngines(root);
  ReadOptionalSections(root);
  diag().ThrowIfAny();
  sim_.pool_ = std::make_unique<ThreadPool>(sim_.threads_);
  sim_.rng_ = RandomStream::For(sim_.seed_, "loop_functions", "");
  ReadArena(root);
  diag().ThrowIfAny();
  ReadLoopFunctions(root);
  if (sim_.length_ticks_ == 0 && sim_.loop_functions_.empty()) {
    // Nothing could ever end the run.
    const ConfigNode experiment = root.Child("framework").Child("experiment");
    experiment.Error("length", experiment.GetString("length", "0"),
                     "length 0 runs until the loop functions end the experiment, but none are "
                     "declared; accepted: a length > 0 (seconds), or <loop_functions> that stop the run");
  }
  diag().ThrowIfAny();
  sim_.space_.UpdateIndex();
  placement_.reset();
}

std::unique_ptr<Simulation> Simulation::Load(const ExperimentOptions& options) {
  std::unique_ptr<Simulation> sim(new Simulation());
  sim->file_ = options.file.empty() ? std::string("<string>") : options.file;
  sim->context_ = std::make_unique<ConfigContext>();
  sim->context_->file = sim->file_;
  sim->document_ = std::make_unique<tinyxml2::XMLDocument>();
  ExperimentLoader loader(*sim, options);
  loader.Load();
  return sim;
}

EntityHandle Simulation::AddEntity(const std::string& xml) {
  tinyxml2::XMLDocument fragment;
  if (fragment.Parse(xml.c_str()) != tinyxml2::XML_SUCCESS || !fragment.RootElement()) {
    throw ConfigError("AddEntity: not well-formed XML: " + std::string(fragment.ErrorStr()));
  }
  auto* copy = fragment.RootElement()->DeepClone(document_.get())->ToElement();
  document_->RootElement()->InsertEndChild(copy);
  ConfigContext context{"<AddEntity>", {}};
  ExperimentOptions none;
  ExperimentLoader loader(*this, none);
  const EntityHandle h = loader.BuildEntity(ConfigNode(copy, &context), nullptr, false);
  document_->RootElement()->DeleteChild(copy);
  context.diagnostics.ThrowIfAny();
  space_.UpdateIndex();
  return h;
}

std::string Simulation::ResolvedXml() const {
  tinyxml2::XMLPrinter printer;
  document_->Print(&printer);
  return printer.CStr();
}

}  // namespace colony
