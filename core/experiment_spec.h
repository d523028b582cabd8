// An experiment as values, between the experiment file and the simulation,
// as MuJoCo separates reading its XML from compiling the model:
//
//   XML file (+ --set overrides) --ReadExperimentSpec--> ExperimentSpec --Simulation::Create-->
//   Simulation
//
// The reader (core/spec_reader.cpp) checks everything the file says that can
// be checked without building anything: element and attribute names,
// values and ranges, ids, the arena's geometry, the entities' descriptions.
// Simulation::Create (core/simulation_create.cpp) builds the plugins, places
// the entities and reports what only building reveals: a plugin's own
// parameters, overlaps, entities no engine can simulate, memory. Both report
// every problem with the file, line, element and attribute.
//
// Framework settings, output, the arena (floor, walls, entities,
// <distribute> blocks) and engines' regions are plain values: a program may
// read a spec, change it (more robots, another seed) and create from it.
// Plugins (media, controllers and their devices, engines, renderers, loop
// functions) keep their XML element as a ConfigNode: their parameters are
// plugin-defined and each plugin reads its own (Configure, Init). The spec
// shares ownership of the parsed document those elements point into.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "core/color.h"
#include "core/config.h"
#include "core/control_interface.h"
#include "core/entity_type.h"
#include "core/floor.h"
#include "core/math.h"
#include "core/region.h"
#include "core/registry.h"

namespace tinyxml2 {
class XMLDocument;
}

namespace colony {

// How to load an experiment (from the command line or a test).
struct ExperimentOptions {
  std::string file;                    // path of the XML file, or
  std::string text;                    // the XML itself (file then only names it in messages)
  std::vector<std::string> overrides;  // "path=value", see ApplyOverride (core/overrides.h)
  std::optional<int> threads;          // replaces <system threads>
  std::optional<uint64_t> seed;        // replaces <experiment random_seed>
  // The folder the run's files go to (`colony run --out`, or the fresh one
  // under runs/); "" when the run writes none (a test, a library user). Loop
  // functions write their own files there (Simulation::run_folder()).
  std::string run_folder;
};

// <output>.
struct OutputConfig {
  uint64_t metrics_every = 1;  // ticks between rows of metrics.csv (0: none)
  uint64_t hash_every = 0;     // ticks between state hashes printed to hashes.csv (0: none)
  // Ticks between records of every robot's pose and values in the
  // trajectories table (0: none; docs/data-output.md).
  uint64_t trajectories_every = 0;
  enum class Format { kCsv, kHdf5 };
  Format trajectories_format = Format::kCsv;  // trajectories.csv or trajectories.h5
  bool trajectories_gzip = false;             // trajectories.csv.gz, or deflated HDF5 chunks
  // led_r, led_g, led_b columns: the colour each robot shows (its first
  // LED's, else its body colour), as the viewer's frames carry it.
  bool trajectories_leds = false;
};

// The parsed experiment file (overrides applied) that the plugin elements of
// a spec point into, shared by copies of the spec and by the simulations
// created from it.
struct SpecDocument {
  SpecDocument();
  ~SpecDocument();
  std::unique_ptr<tinyxml2::XMLDocument> xml;
  ConfigContext context;  // the file's name, and what reading its plugin elements records
};

// A plugin an element of the file names. The plugin reads its parameters
// from `node` itself.
struct PluginSpec {
  std::string label;                       // the element's name: a registered label or alias
  std::string implementation = "default";  // sensors and actuators may have several
  std::string id;                          // controllers, engines, media ("" elsewhere)
  ConfigNode node;                         // the element
};

// One element of <controllers>: a controller configuration robots name.
struct ControllerSpec {
  PluginSpec plugin;                  // the controller: its label and id
  Params params;                      // the attributes of its <params>
  std::vector<PluginSpec> sensors;    // <sensors>, in file order
  std::vector<PluginSpec> actuators;  // <actuators>, in file order
};

// One element of <physics_engines>.
struct EngineSpec {
  PluginSpec plugin;             // the engine: its label and id
  std::optional<Region> region;  // <boundaries>; none: the whole arena
  // entities="...": the entity types (labels, aliases resolved) this engine
  // takes wherever they are, and no other engine does; empty: it takes
  // what its region holds.
  std::vector<std::string> entity_types;
};

// How a <distribute> block draws one triple per entity: a position (m), or
// an orientation (yaw, pitch, roll).
struct DistributeDraw {
  enum class Method { kUniform, kGaussian, kConstant, kGrid };
  Method method = Method::kConstant;
  // kUniform: min, max; kGaussian: mean, std_dev; kConstant: the values (a);
  // kGrid: the centre and the distances between places.
  std::array<double, 3> a{}, b{};
  std::array<int64_t, 3> layout{1, 1, 1};  // kGrid: places along x, y, z, filled x fastest
  // An orientation's a and b are degrees, as in the file (ARGoS's
  // convention); what is drawn is converted to radians.
  bool degrees = false;
  int64_t places() const { return layout[0] * layout[1] * layout[2]; }
};

// A <distribute> block: `quantity` copies of one entity, each at the first
// drawn pose where it fits (core/placement.h).
struct DistributeSpec {
  DistributeDraw position, orientation;
  int64_t quantity = 0;      // 1 .. kMaxDistributeQuantity
  int64_t max_trials = 100;  // draws per entity before giving up
  int64_t base_num = 0;      // entity i gets the id entity.init.id + (base_num + i)
  // order="drawn" (the default): entity i is the i-th drawn. order="place":
  // the entities are numbered, and so stored, in the order of their places
  // row by row over the arena (rows as wide as the space's grid cells), so
  // that robots near each other on the floor are near each other in memory,
  // in the order the space's grid lists them (PlaceDistributed).
  bool order_by_place = false;
  EntityDesc entity;  // the template: its id is the ids' prefix; its pose is replaced by the draws
  int line = 0;       // of <distribute>; it also names the block's random stream
  int entity_line = 0;  // of its <entity>, for messages
};

// <floor>.
struct FloorSpec {
  Color color = Color::White();
  std::vector<Ditch> ditches;
  // A PNG stretched over the arena, as written in the file ("" for none); a
  // relative path is looked for beside the experiment file first.
  std::string image;
  // source="loop_functions" (as in ARGoS): the loop functions colour the
  // floor (LoopFunctions::FloorColor), sampled at this many pixels per metre.
  double loop_functions_pixels_per_meter = 0;  // 0: not from loop functions
  int line = 0;                                // of <floor>, for messages
};

// <ceiling>: a flat ceiling over the whole arena.
struct CeilingSpec {
  bool present = false;
  double height = 0;          // above the floor (m)
  bool ferromagnetic = true;  // a magnet (a hand-bot's rope) holds to it
  int line = 0;               // of <ceiling>, for messages
};

// <arena>: an axis-aligned box (m) and what is in it.
struct ArenaSpec {
  Vec3 center = Vec3::Zero();
  Vec3 size = Vec3::Zero();
  FloorSpec floor;
  CeilingSpec ceiling;
  // The four fixed boxes <walls> lines the arena's edges with (wall_north,
  // wall_south, wall_east, wall_west), built first; empty without <walls>.
  std::vector<EntityDesc> walls;
  // The entities and <distribute> blocks, in file order (the order they are
  // built in, which the simulation's results depend on).
  std::vector<std::variant<EntityDesc, DistributeSpec>> contents;
};

struct ExperimentSpec {
  std::string file;                        // names the experiment in messages ("<string>" for text)
  std::shared_ptr<SpecDocument> document;  // what the plugin elements point into
  std::string run_folder;                  // ExperimentOptions::run_folder

  // <framework>
  double dt = 0.1;            // seconds per tick: 1 / ticks_per_second
  uint64_t length_ticks = 0;  // 0: until the loop functions end the run
  uint64_t seed = 0;
  int threads = 1;  // >= 1: 1 runs everything on the calling thread

  OutputConfig output;
  std::vector<PluginSpec> media;             // <media>, in file order
  std::vector<ControllerSpec> controllers;   // <controllers>, in file order
  std::vector<EngineSpec> engines;           // <physics_engines>, in file order
  std::vector<PluginSpec> renderers;         // <visualization>, in file order
  std::optional<PluginSpec> loop_functions;  // label from label="..."; node: <loop_functions>
  ArenaSpec arena;
};

// Reads, checks and resolves an experiment file (or text) and its
// overrides. Throws ConfigError listing every problem found.
ExperimentSpec ReadExperimentSpec(const ExperimentOptions& options);

// Reads one entity element, as in <arena> (e.g. "<box id='b' size='1,1,1'>
// <body position='0,0,0'/></box>"), into a description whose line is 0 (it
// is not part of an experiment file). `source` names the text in messages.
// Throws ConfigError. A robot's <controller config> is checked when the
// entity is added (Simulation::AddEntity).
EntityDesc ReadEntityDesc(const std::string& xml, const std::string& source);

// The one stateless instance of a registered entity type.
const EntityType& EntityTypeInstance(const Registry<EntityType>::Entry& entry);

}  // namespace colony
