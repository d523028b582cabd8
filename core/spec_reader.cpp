// Reading an experiment file into an ExperimentSpec (see
// core/experiment_spec.h): one reader per section. Problems are recorded
// with their file, line, element and attribute and thrown together at three
// points: after <framework> and <output> (nothing else is worth reading
// without them), after the plugin sections (robots name controllers, so a
// bad controller would be reported again by every robot), and at the end.
#include <tinyxml2.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <mutex>

#include "core/argos_compat.h"
#include "core/bounds.h"
#include "core/device.h"
#include "core/engine.h"
#include "core/entity_type.h"
#include "core/error.h"
#include "core/experiment_spec.h"
#include "core/image_renderer.h"
#include "core/log.h"
#include "core/loop_functions.h"
#include "core/medium.h"
#include "core/overrides.h"
#include "core/plugin_loader.h"
#include "core/renderer.h"
#include "core/xml_errors.h"

namespace colony {

SpecDocument::SpecDocument() : xml(std::make_unique<tinyxml2::XMLDocument>()) {}
SpecDocument::~SpecDocument() = default;

const EntityType& EntityTypeInstance(const Registry<EntityType>::Entry& entry) {
  static std::mutex mutex;
  static std::map<const void*, std::unique_ptr<EntityType>> types;
  std::lock_guard lock(mutex);
  auto& type = types[&entry];
  if (!type) type = entry.create();
  return *type;
}

namespace {

const std::vector<std::string> kTopLevel = {"framework",     "controllers",     "loop_functions",
                                            "arena",         "physics_engines", "media",
                                            "visualization", "output"};

// Whether `parent` holds a misspelling of `name`, already reported as an
// unknown element (so "missing <name>" would only repeat it).
bool HasMisspelt(const ConfigNode& parent, const std::string& name) {
  for (const ConfigNode& child : parent.Children()) {
    if (child.name() != name && DidYouMean(child.name(), {name}) == name) return true;
  }
  return false;
}

template <class Base>
const typename Registry<Base>::Entry* FindPlugin(const ConfigNode& node, const std::string& what,
                                                 const std::string& label,
                                                 const std::string& impl) {
  auto& registry = Registry<Base>::Get();
  if (const auto* entry = registry.Find(label, impl)) return entry;
  if (registry.Find(label)) {
    node.Error("implementation", impl,
               "no implementation '" + impl + "' of " + what + " '" + label +
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

class SpecReader {
 public:
  SpecReader(ExperimentSpec& spec, ConfigContext& context) : spec_(spec), context_(context) {}

  void Read(const ConfigNode& root, const ExperimentOptions& options);
  // Reads an entity element into `desc`: false (problems recorded) if it
  // cannot be built. A <distribute> template's id is optional (the ids'
  // prefix) and its pose is drawn; `check_controllers`: whether a robot's
  // controller must be one of spec_.controllers.
  bool ReadEntity(const ConfigNode& node, bool is_template, bool check_controllers,
                  EntityDesc& desc);

 private:
  Diagnostics& diag() { return context_.diagnostics; }
  void ReadFramework(const ConfigNode& root, const ExperimentOptions& options);
  void ReadOutput(const ConfigNode& root);
  bool LoadLibraryAttribute(const ConfigNode& node);
  void ReadMedia(const ConfigNode& root);
  void ReadControllers(const ConfigNode& root);
  template <class System>
  void ReadDevices(const ConfigNode& section, const std::string& what,
                   std::vector<PluginSpec>& devices);
  void ReadEngines(const ConfigNode& root);
  std::optional<Region> ReadBoundaries(const ConfigNode& engine_node);
  std::vector<std::string> ReadEngineEntityTypes(const ConfigNode& engine_node);
  void ReadRenderers(const ConfigNode& root);
  void ReadLoopFunctions(const ConfigNode& root);
  void ReadArena(const ConfigNode& root);
  void ReadFloor(const ConfigNode& floor);
  void ReadCeiling(const ConfigNode& ceiling);
  void ReadWalls(const ConfigNode& walls);
  void ReadDistribute(const ConfigNode& node);
  void ReadDraw(const ConfigNode& node, bool degrees, DistributeDraw& out);

  ExperimentSpec& spec_;
  ConfigContext& context_;
};

void SpecReader::Read(const ConfigNode& root, const ExperimentOptions& options) {
  root.CheckChildren(kTopLevel);
  for (const auto& section : kTopLevel) root.CheckAtMostOne(section);
  ReadFramework(root, options);
  ReadOutput(root);
  diag().ThrowIfAny();
  ReadMedia(root);
  ReadControllers(root);
  ReadEngines(root);
  ReadRenderers(root);
  ReadLoopFunctions(root);
  if (spec_.length_ticks == 0 && !root.Child("loop_functions").valid()) {
    // Nothing could ever end the run.
    const ConfigNode experiment = root.Child("framework").Child("experiment");
    experiment.Error(
        "length", experiment.GetString("length", "0"),
        "length 0 runs until the loop functions end the experiment, but none are "
        "declared; accepted: a length > 0 (seconds), or <loop_functions> that stop the run");
  }
  diag().ThrowIfAny();
  ReadArena(root);
  diag().ThrowIfAny();
}

void SpecReader::ReadFramework(const ConfigNode& root, const ExperimentOptions& options) {
  const ConfigNode framework = root.Child("framework");
  if (!framework.valid()) {
    if (HasMisspelt(root, "framework")) return;
    root.ElementError(
        "missing <framework> (it holds <experiment length ticks_per_second random_seed>)");
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
    framework.ElementError(
        "missing <experiment length=\"seconds\" ticks_per_second=\"10\" random_seed=\"1\"/>");
    return;
  }
  experiment.CheckAttributes({"length", "ticks_per_second", "random_seed", "real_time"});
  const double length = experiment.GetDouble("length", 0, Range::NonNegative());
  const double tps = experiment.GetDouble("ticks_per_second", 10, {0, 1e6, true});
  const int64_t seed = experiment.GetInt("random_seed", 0, 0, INT64_MAX);
  if (length * tps >= 9e18) {
    experiment.Error("length", experiment.GetString("length", ""),
                     "the experiment would last over 9e18 ticks; accepted: length * "
                     "ticks_per_second < 9e18 (0: unlimited)");
  }
  spec_.dt = 1.0 / tps;
  spec_.length_ticks = static_cast<uint64_t>(std::llround(length * tps));
  if (length > 0 && spec_.length_ticks == 0) spec_.length_ticks = 1;
  spec_.seed = options.seed ? *options.seed : static_cast<uint64_t>(seed);
  // 0 and 1 both run everything on the calling thread: report 1.
  spec_.threads = std::max(1, options.threads ? *options.threads : threads);
}

void SpecReader::ReadOutput(const ConfigNode& root) {
  root.CheckAtMostOne("output");
  const ConfigNode node = root.Child("output");
  if (!node.valid()) return;
  node.CheckAttributes(
      {"metrics_every", "hash_every", "trajectories_every", "format", "compress", "leds"});
  node.CheckChildren({});
  OutputConfig& out = spec_.output;
  out.metrics_every = static_cast<uint64_t>(node.GetInt("metrics_every", 1, 0, INT64_MAX));
  out.hash_every = static_cast<uint64_t>(node.GetInt("hash_every", 0, 0, INT64_MAX));
  out.trajectories_every =
      static_cast<uint64_t>(node.GetInt("trajectories_every", 0, 0, INT64_MAX));
  out.trajectories_format = node.GetChoice("format", {"csv", "hdf5"}, "csv") == "hdf5"
                                ? OutputConfig::Format::kHdf5
                                : OutputConfig::Format::kCsv;
  out.trajectories_gzip = node.GetChoice("compress", {"none", "gzip"}, "none") == "gzip";
  out.trajectories_leds = node.GetBool("leds", false);
  if (out.trajectories_every == 0 &&
      (node.Has("format") || node.Has("compress") || node.Has("leds"))) {
    LogWarning(node.file() + ":" + std::to_string(node.line()) +
               ": <output>: format, compress and leds describe the trajectories table, which "
               "is not written: trajectories_every is 0");
  }
}

bool SpecReader::LoadLibraryAttribute(const ConfigNode& node) {
  if (!node.Has("library")) return true;
  const std::string spec = node.GetString("library", "");
  const std::string base = std::filesystem::path(spec_.file).parent_path().string();
  const std::string error = LoadPluginLibrary(spec, base);
  if (error.empty()) return true;
  node.Error("library", spec, error);
  return false;
}

void SpecReader::ReadMedia(const ConfigNode& root) {
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
      child.Error("id", id,
                  "duplicate medium id '" + id + "' (first at line " + std::to_string(it->second) +
                      "); give each medium its own id");
      continue;
    }
    spec_.media.push_back(PluginSpec{child.name(), "default", id, child});
  }
}

void SpecReader::ReadControllers(const ConfigNode& root) {
  const ConfigNode controllers = root.Child("controllers");
  if (!controllers.valid()) return;
  controllers.CheckAttributes({});
  std::map<std::string, int> ids;
  for (const ConfigNode& node : controllers.Children()) {
    node.CheckAttributes({"id", "library", "rate", "phase"});
    node.CheckChildren({"sensors", "actuators", "params"});
    const std::string id = node.RequireString("id");
    if (!id.empty()) {
      if (ids.count(id)) {
        node.Error("id", id,
                   "controller id '" + id + "' already defined at line " + std::to_string(ids[id]));
      }
      ids[id] = node.line();
    }
    if (!LoadLibraryAttribute(node)) continue;
    // A controller host shipped with Colony (<lua_controller>) is a plugin of
    // the same name, loaded on first use when no library= names another.
    if (!node.Has("library") && !Registry<Controller>::Get().Find(node.name())) {
      // The plugin of that name found but refused by the loader (a missing
      // symbol or dependency): that, not "unknown controller", is the news.
      const std::string error = LoadPluginLibrary(node.name(), "");
      std::string failures;
      for (size_t at = error.find("\n    "); at != std::string::npos;
           at = error.find("\n    ", at + 1)) {
        const size_t end = std::min(error.find('\n', at + 1), error.size());
        const std::string line = error.substr(at + 5, end - at - 5);
        if (line.find(" (") != std::string::npos &&
            line.find("(no such file)") == std::string::npos &&
            line.find("COLONY_PLUGIN_PATH") == std::string::npos)
          failures += "\n    " + line;
      }
      if (!failures.empty()) {
        diag().Add(Diagnostic{
            node.file(), node.line(), node.Label(), "", "",
            "the plugin '" + node.name() + "' was found but could not be loaded:" + failures});
        continue;
      }
    }
    const auto* entry = FindPlugin<Controller>(node, "controller", node.name(), "default");
    if (!entry) {
      if (!node.Has("library")) {
        diag().Add(Diagnostic{
            node.file(), node.line(), node.Label(), "library", "",
            "hint: a controller built as a plugin is loaded with library=\"NAME or path\""});
      }
      continue;
    }
    ControllerSpec controller;
    controller.plugin = PluginSpec{node.name(), "default", id, node};
    const ConfigNode params = node.Child("params");
    node.CheckAtMostOne("params");
    node.CheckAtMostOne("sensors");
    node.CheckAtMostOne("actuators");
    if (params.valid()) {
      params.CheckChildren({});
      controller.params = params.ToParams();
    }
    ReadDevices<SensorSystem>(node.Child("sensors"), "sensor", controller.sensors);
    ReadDevices<ActuatorSystem>(node.Child("actuators"), "actuator", controller.actuators);
    spec_.controllers.push_back(std::move(controller));
  }
}

// The device elements of a controller's <sensors> or <actuators>, their
// attributes checked against the registered list.
template <class System>
void SpecReader::ReadDevices(const ConfigNode& section, const std::string& what,
                             std::vector<PluginSpec>& devices) {
  for (const ConfigNode& d : section.Children()) {
    const std::string impl = d.GetString("implementation", "default");
    const auto* entry = FindPlugin<System>(d, what, d.name(), impl);
    if (!entry) continue;
    auto names = entry->info.AttributeNames();
    names.push_back("implementation");
    // Every sensor's sampling period and bus accounting (docs/events.md).
    if (what == "sensor") names.insert(names.end(), {"period", "phase", "bus"});
    d.CheckAttributes(names);
    devices.push_back(PluginSpec{d.name(), impl, "", d});
  }
}

void SpecReader::ReadEngines(const ConfigNode& root) {
  const ConfigNode engines = root.Child("physics_engines");
  if (!engines.valid()) return;
  engines.CheckAttributes({});
  std::map<std::string, int> ids;
  for (const ConfigNode& node : engines.Children()) {
    const auto* entry = FindPlugin<PhysicsEngine>(node, "physics engine", node.name(), "default");
    if (!entry) continue;
    auto names = entry->info.AttributeNames();
    names.push_back("id");
    names.push_back("entities");
    node.CheckAttributes(names);
    const std::string id = node.RequireString("id");
    if (ids.count(id))
      node.Error("id", id,
                 "engine id '" + id + "' already used at line " + std::to_string(ids[id]));
    ids[id] = node.line();
    node.CheckChildren({"boundaries"});
    node.CheckAtMostOne("boundaries");
    EngineSpec engine;
    engine.plugin = PluginSpec{node.name(), "default", id, node};
    engine.region = ReadBoundaries(node);
    engine.entity_types = ReadEngineEntityTypes(node);
    if (!engine.entity_types.empty() && engine.region) {
      node.Child("boundaries")
          .ElementError(
              "an engine that takes entity types (entities=\"" + Join(engine.entity_types) +
              "\") takes them wherever they are, in the whole arena; it cannot have <boundaries>");
    }
    spec_.engines.push_back(std::move(engine));
  }
}

// entities="eyebot, ...": entity types by label or alias, separated by
// commas or spaces; returned as labels, each once.
std::vector<std::string> SpecReader::ReadEngineEntityTypes(const ConfigNode& engine_node) {
  std::vector<std::string> types;
  if (!engine_node.Has("entities")) return types;
  const std::string text = engine_node.GetString("entities", "");
  std::string word;
  auto take = [&]() {
    if (word.empty()) return;
    const auto* entry = Registry<EntityType>::Get().Find(word);
    if (!entry) {
      const auto labels = Registry<EntityType>::Get().Labels();
      const std::string guess = DidYouMean(word, labels);
      engine_node.Error("entities", text,
                        "unknown entity type '" + word + "'" +
                            (guess.empty() ? "" : " (did you mean '" + guess + "'?)") +
                            "; accepted: entity types separated by commas (" + Join(labels) + ")");
    } else if (std::find(types.begin(), types.end(), entry->info.label) == types.end()) {
      types.push_back(entry->info.label);
    }
    word.clear();
  };
  for (char c : text) {
    if (c == ',' || c == ' ' || c == '\t') {
      take();
    } else {
      word += c;
    }
  }
  take();
  if (types.empty()) {
    engine_node.Error("entities", text,
                      "names no entity type; accepted: entity types separated by commas, e.g. "
                      "\"eyebot\"");
  }
  return types;
}

std::optional<Region> SpecReader::ReadBoundaries(const ConfigNode& engine_node) {
  const ConfigNode b = engine_node.Child("boundaries");
  if (!b.valid()) return std::nullopt;
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
    b.ElementError(
        "missing <sides> with at least three <vertex point=\"x,y\"/>, counter-clockwise");
    return std::nullopt;
  }
  sides.CheckAttributes({"size"});
  sides.CheckChildren({"vertex"});
  for (const ConfigNode& v : sides.Children("vertex")) {
    v.CheckAttributes({"point"});
    const std::string raw = v.RequireString("point");
    const auto parts = SplitList(raw);
    double x = 0, y = 0;
    if (parts.size() != 2 || !ParseFiniteDouble(parts[0], x) || !ParseFiniteDouble(parts[1], y)) {
      if (!raw.empty())
        v.Error("point", raw, "'" + raw + "' is not two finite numbers; accepted: \"x,y\"");
      continue;
    }
    region.vertices.emplace_back(x, y);
  }
  const int64_t size =
      sides.GetInt("size", static_cast<int64_t>(region.vertices.size()), 3, 100000);
  if (size != static_cast<int64_t>(region.vertices.size())) {
    sides.Error("size", sides.GetString("size", ""),
                "says " + std::to_string(size) + " vertices but " +
                    std::to_string(region.vertices.size()) + " are given");
  }
  const std::string problem = region.Problem();
  if (!problem.empty()) {
    sides.ElementError(problem);
    return std::nullopt;
  }
  return region;
}

void SpecReader::ReadRenderers(const ConfigNode& root) {
  const ConfigNode node = root.Child("visualization");
  if (!node.valid()) return;
  node.CheckAttributes({});
  for (const ConfigNode& child : node.Children()) {
    // Every renderer draws with the image renderer's backend.
    if (!HaveImageRenderer()) {
      child.ElementError(NoImageRendererMessage("the renderer <" + child.name() + ">"));
      continue;
    }
    if (const auto* entry = FindPlugin<Renderer>(child, "renderer", child.name(), "default")) {
      child.CheckAttributes(entry->info.AttributeNames());
      spec_.renderers.push_back(PluginSpec{child.name(), "default", "", child});
    }
  }
}

void SpecReader::ReadLoopFunctions(const ConfigNode& root) {
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
    message +=
        labels.empty() ? "; none is loaded (give library=\"...\")" : "; accepted: " + Join(labels);
    node.Error("label", label, message);
    return;
  }
  node.CheckAttributes({"library", "label"});
  if (const ConfigNode params = node.Child("params"); params.valid()) {
    // "*": loop functions that read their own parameters (ARGoS's, through
    // the C++ compatibility layer).
    const auto names = entry->info.AttributeNames();
    if (std::find(names.begin(), names.end(), "*") == names.end()) params.CheckAttributes(names);
  }
  spec_.loop_functions = PluginSpec{label, "default", "", node};
}

void SpecReader::ReadArena(const ConfigNode& root) {
  const ConfigNode arena = root.Child("arena");
  if (!arena.valid()) {
    if (HasMisspelt(root, "arena")) return;
    root.ElementError("missing <arena size=\"x,y,z\"> holding the robots and objects");
    return;
  }
  std::vector<std::string> children = {"floor", "ceiling", "walls", "distribute"};
  for (const auto& l : Registry<EntityType>::Get().Labels()) children.push_back(l);
  arena.CheckAttributes({"size", "center", "positional_grid_size"});
  arena.CheckChildren(children);
  arena.CheckAtMostOne("floor");
  arena.CheckAtMostOne("ceiling");
  arena.CheckAtMostOne("walls");
  // Without a size nothing can be placed; other problems do not stop the
  // entities from being checked, so all are reported together.
  const size_t errors_before = diag().size();
  const auto size = arena.RequireTriple("size", {0, kMaxArenaExtent, true});
  const auto c = arena.GetTriple("center", {0, 0, size[2] / 2},
                                 Range::Between(-kMaxArenaExtent, kMaxArenaExtent));
  if (diag().size() != errors_before) return;
  spec_.arena.size = Vec3(size[0], size[1], size[2]);
  spec_.arena.center = Vec3(c[0], c[1], c[2]);
  if (const ConfigNode floor = arena.Child("floor"); floor.valid()) ReadFloor(floor);
  if (const ConfigNode ceiling = arena.Child("ceiling"); ceiling.valid()) ReadCeiling(ceiling);
  if (const ConfigNode walls = arena.Child("walls"); walls.valid()) ReadWalls(walls);
  for (const ConfigNode& child : arena.Children()) {
    const std::string n = child.name();
    if (n == "floor" || n == "ceiling" || n == "walls") continue;
    if (n == "distribute") {
      ReadDistribute(child);
      continue;
    }
    if (!Registry<EntityType>::Get().Find(n)) continue;
    EntityDesc desc;
    if (ReadEntity(child, false, true, desc)) spec_.arena.contents.push_back(std::move(desc));
  }
}

void SpecReader::ReadFloor(const ConfigNode& floor) {
  const Vec3& s = spec_.arena.size;
  const Vec3 lo = spec_.arena.center - 0.5 * s, hi = spec_.arena.center + 0.5 * s;
  FloorSpec& out = spec_.arena.floor;
  out.line = floor.line();
  floor.CheckAttributes({"id", "color", "source", "path", "pixels_per_meter"});
  floor.CheckChildren({"ditch"});
  const auto ditches = floor.Children("ditch");
  const bool too_many = static_cast<int64_t>(ditches.size()) > kMaxDitches;
  if (too_many) {
    ditches[kMaxDitches].ElementError("the floor has " + std::to_string(ditches.size()) +
                                      " ditches; accepted: at most " + std::to_string(kMaxDitches) +
                                      " <ditch> elements (join neighbouring ones)");
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
    if (ditch.min_x < lo.x() || ditch.max_x > hi.x() || ditch.min_y < lo.y() ||
        ditch.max_y > hi.y()) {
      d.Error("center", d.GetString("center", ""),
              "the ditch reaches outside the arena; accepted: a centre and size "
              "keeping it within the arena's floor");
      continue;
    }
    if (depth >= s.z()) {
      d.Error("depth", d.GetString("depth", ""),
              "the ditch is deeper than the arena is high; accepted: a depth > 0 and < " +
                  FormatNumber(s.z()));
      continue;
    }
    out.ditches.push_back(ditch);
  }
  const std::string source = floor.GetChoice("source", {"color", "image", "loop_functions"},
                                             floor.Has("path") ? "image" : "color");
  out.color = floor.GetColor("color", Color::White());
  if (source == "image") out.image = floor.RequireString("path");
  if (source == "loop_functions") {
    // As many pixels as an image floor may have, at most.
    const double area = std::max(s.x() * s.y(), 1e-12);
    const double most = std::floor(std::sqrt(static_cast<double>(kMaxFloorImagePixels) / area));
    out.loop_functions_pixels_per_meter =
        floor.RequireDouble("pixels_per_meter", Range{0.0, most, true});
    if (!spec_.loop_functions) {
      floor.Error("source", "loop_functions",
                  "the floor is coloured by the loop functions, but none are declared; accepted: "
                  "<loop_functions library=... label=...> that colour the floor, or "
                  "source=\"color\" or \"image\"");
    }
  } else if (floor.Has("pixels_per_meter")) {
    floor.Error("pixels_per_meter", floor.GetString("pixels_per_meter", ""),
                "only a floor with source=\"loop_functions\" takes pixels_per_meter");
  }
}

void SpecReader::ReadCeiling(const ConfigNode& ceiling) {
  CeilingSpec& out = spec_.arena.ceiling;
  out.line = ceiling.line();
  ceiling.CheckAttributes({"height", "ferromagnetic"});
  ceiling.CheckChildren({});
  const double top = spec_.arena.size.z();
  const size_t before = diag().size();
  out.height = ceiling.RequireDouble("height", Range::Positive());
  out.ferromagnetic = ceiling.GetBool("ferromagnetic", true);
  if (diag().size() != before) return;
  if (out.height > top) {
    const std::string raw = ceiling.GetString("height", "");
    ceiling.Error("height", raw,
                  "'" + raw +
                      "' puts the ceiling above the arena's top; accepted: a height > 0 and <= the "
                      "arena's height (" +
                      FormatNumber(top) + " m)");
    return;
  }
  out.present = true;
}

void SpecReader::ReadWalls(const ConfigNode& walls) {
  const Vec3& s = spec_.arena.size;
  const Vec3& center = spec_.arena.center;
  const Vec3 lo = center - 0.5 * s, hi = center + 0.5 * s;
  walls.CheckAttributes({"thickness", "height", "color"});
  walls.CheckChildren({});
  const size_t wall_errors = diag().size();
  const double t = walls.GetDouble("thickness", 0.1, Range::Positive());
  const double h = walls.GetDouble("height", 0.5, Range::Positive());
  const std::string color = walls.GetString("color", "gray50");
  const std::optional<Color> parsed_color = ParseColor(color);
  if (!parsed_color)
    walls.Error("color", color, "'" + color + "' is not a colour; accepted: " + kColorAccepted);
  if (2 * t >= std::min(s.x(), s.y())) {
    const std::string raw = walls.GetString("thickness", "");
    walls.Error("thickness", raw,
                "walls " + raw +
                    " m thick leave no room inside the arena; accepted: a number > 0 and < " +
                    FormatNumber(std::min(s.x(), s.y()) / 2) + " (half the arena's smaller side)");
  }
  if (h > s.z()) {
    const std::string raw = walls.GetString("height", "");
    walls.Error("height", raw,
                "walls are taller than the arena; accepted: a number > 0 and <= " +
                    FormatNumber(s.z()) + " (the arena's height)");
  }
  // Bad walls are reported; the entities are still checked.
  if (diag().size() != wall_errors) return;
  // Four fixed boxes lining the inside of the arena's edges.
  struct Side {
    const char* id;
    double x, y, sx, sy;
  } sides[] = {
      {"wall_north", center.x(), hi.y() - t / 2, s.x(), t},
      {"wall_south", center.x(), lo.y() + t / 2, s.x(), t},
      {"wall_east", hi.x() - t / 2, center.y(), t, s.y() - 2 * t},
      {"wall_west", lo.x() + t / 2, center.y(), t, s.y() - 2 * t},
  };
  for (const Side& side : sides) {
    EntityDesc wall;
    wall.type = "box";
    wall.line = walls.line();
    Space::EntityInit& init = wall.init;
    init.id = side.id;
    init.pose.position = Vec3(side.x, side.y, lo.z());
    init.geometry.shape = ShapeKind::kBox;
    init.geometry.size = Vec3(side.sx, side.sy, h);
    init.geometry.radius = init.geometry.BoundingRadius();
    init.flags = kSolid;
    init.mass = 0;
    init.color = *parsed_color;
    spec_.arena.walls.push_back(std::move(wall));
  }
}

bool SpecReader::ReadEntity(const ConfigNode& node, bool is_template, bool check_controllers,
                            EntityDesc& desc) {
  const auto* entry = FindPlugin<EntityType>(node, "entity type", node.name(), "default");
  if (!entry) return false;
  const EntityType& type = EntityTypeInstance(*entry);
  auto names = entry->info.AttributeNames();
  names.push_back("id");
  node.CheckAttributes(names);
  // Unknown attributes are reported, but do not stop the entity from being built.
  const size_t before = diag().size();
  desc.type = node.name();
  desc.line = node.line();
  desc.init.id = is_template ? node.GetString("id", "") : node.RequireString("id");
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
    } else if (!is_template) {
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
      std::vector<std::string> ids;
      for (const ControllerSpec& controller : spec_.controllers)
        ids.push_back(controller.plugin.id);
      const bool found = std::find(ids.begin(), ids.end(), desc.controller) != ids.end();
      if (check_controllers && !found && !desc.controller.empty()) {
        std::string message =
            "no controller with id '" + desc.controller + "' is defined in <controllers>";
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
  return diag().size() == before;
}

// Reads one <position> or <orientation> of a <distribute>.
void SpecReader::ReadDraw(const ConfigNode& g, bool degrees, DistributeDraw& out) {
  using Method = DistributeDraw::Method;
  const std::string method = g.GetChoice("method", {"uniform", "gaussian", "constant", "grid"}, "");
  if (!g.Has("method"))
    g.Error("method", "",
            "required attribute is missing; accepted: uniform, gaussian, constant, grid");
  out.degrees = degrees;
  if (method == "uniform") {
    out.method = Method::kUniform;
    g.CheckAttributes({"method", "min", "max"});
    out.a = g.RequireTriple("min");
    out.b = g.RequireTriple("max");
    for (int k = 0; k < 3; ++k)
      if (out.a[k] > out.b[k])
        g.Error("max", g.GetString("max", ""),
                "each component of max must be >= the same component of min");
  } else if (method == "gaussian") {
    out.method = Method::kGaussian;
    g.CheckAttributes({"method", "mean", "std_dev"});
    out.a = g.RequireTriple("mean");
    out.b = g.RequireTriple("std_dev", Range::NonNegative());
  } else if (method == "constant") {
    out.method = Method::kConstant;
    g.CheckAttributes({"method", "values"});
    out.a = g.RequireTriple("values");
  } else if (method == "grid") {
    out.method = Method::kGrid;
    g.CheckAttributes({"method", "center", "distances", "layout"});
    out.a = g.RequireTriple("center");
    out.b = g.RequireTriple("distances", Range::NonNegative());
    const auto layout = g.RequireTriple("layout", Range::Between(1, 1e7));
    const double places = layout[0] * layout[1] * layout[2];
    bool whole = true;
    for (double v : layout) whole = whole && v == std::floor(v);
    if (!whole || places > 1e7) {
      g.Error(
          "layout", g.GetString("layout", ""),
          "'" + g.GetString("layout", "") +
              "' is not a usable grid; accepted: three whole numbers >= 1 (places along x, y, z) "
              "whose product is at most 10000000");
      return;
    }
    for (int k = 0; k < 3; ++k) out.layout[k] = static_cast<int64_t>(layout[k]);
  }
}

void SpecReader::ReadDistribute(const ConfigNode& node) {
  // Problems found elsewhere do not stop this block from being checked.
  const size_t errors_before = diag().size();
  node.CheckAttributes({});
  node.CheckChildren({"position", "orientation", "entity"});
  for (const char* part : {"position", "orientation", "entity"}) {
    node.CheckAtMostOne(part);
    if (!node.Child(part).valid()) node.ElementError(std::string("missing <") + part + ">");
  }
  if (diag().size() != errors_before) return;
  const ConfigNode pos_node = node.Child("position"), ori_node = node.Child("orientation"),
                   ent_node = node.Child("entity");
  DistributeSpec block;
  block.line = node.line();
  block.entity_line = ent_node.line();
  ReadDraw(pos_node, false, block.position);
  ReadDraw(ori_node, true, block.orientation);
  ent_node.CheckAttributes({"quantity", "max_trials", "base_num", "order"});
  block.quantity = ent_node.RequireInt("quantity", 1, kMaxDistributeQuantity);
  block.max_trials = ent_node.GetInt("max_trials", 100, 1, 1'000'000);
  block.base_num = ent_node.GetInt("base_num", 0, 0, INT64_MAX);
  block.order_by_place = ent_node.GetChoice("order", {"drawn", "place"}, "drawn") == "place";
  const auto templates = ent_node.Children();
  if (templates.size() != 1)
    ent_node.ElementError(
        "must hold exactly one entity element (e.g. <marxbot id=\"mb\">), found " +
        std::to_string(templates.size()));
  if (diag().size() != errors_before) return;
  if (block.position.method == DistributeDraw::Method::kGrid &&
      block.position.places() < block.quantity) {
    pos_node.Error("layout", pos_node.GetString("layout", ""),
                   "the grid has " + std::to_string(block.position.places()) +
                       " places, fewer than quantity=" + std::to_string(block.quantity));
    return;
  }
  // The template is read once; each entity is a copy with its own id and pose.
  if (!ReadEntity(templates.front(), true, true, block.entity)) return;
  spec_.arena.contents.push_back(std::move(block));
}

}  // namespace

ExperimentSpec ReadExperimentSpec(const ExperimentOptions& options) {
  ExperimentSpec spec;
  spec.file = options.file.empty() ? std::string("<string>") : options.file;
  spec.run_folder = options.run_folder;
  spec.document = std::make_shared<SpecDocument>();
  spec.document->context.file = spec.file;
  const std::string text = options.text.empty() && !options.file.empty()
                               ? ReadExperimentText(options.file)
                               : options.text;
  tinyxml2::XMLDocument& doc = *spec.document->xml;
  ParseExperimentXml(text, spec.file, doc);
  AdaptArgosDocument(doc, spec.file);
  for (const auto& o : options.overrides) ApplyOverride(doc, o, spec.file);
  SpecReader reader(spec, spec.document->context);
  reader.Read(ConfigNode(doc.RootElement(), &spec.document->context), options);
  return spec;
}

EntityDesc ReadEntityDesc(const std::string& xml, const std::string& source) {
  tinyxml2::XMLDocument fragment;
  if (fragment.Parse(xml.c_str()) != tinyxml2::XML_SUCCESS || !fragment.RootElement()) {
    throw ConfigError(source + ": not well-formed XML: " + std::string(fragment.ErrorStr()));
  }
  ExperimentSpec none;
  ConfigContext context{source, {}};
  SpecReader reader(none, context);
  EntityDesc desc;
  reader.ReadEntity(ConfigNode(fragment.RootElement(), &context), false, false, desc);
  context.diagnostics.ThrowIfAny();
  desc.line = 0;
  return desc;
}

}  // namespace colony
