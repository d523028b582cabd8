// The space: the single source of truth for the state of the simulation at a
// tick. Every entity (robot, wall, box, light...) lives in one slot; its hot
// state sits in parallel arrays indexed by slot (structure of arrays), so the
// engines and sensors that sweep over 100,000 robots read memory in order and
// never chase pointers. Entities are addressed by id string (from XML) or by
// an EntityHandle (slot + generation) that detects reuse of a freed slot.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/color.h"
#include "core/component.h"
#include "core/floor.h"
#include "core/math.h"
#include "core/state_hash.h"

namespace colony {

class ThreadPool;

struct EntityHandle {
  static constexpr uint32_t kInvalid = 0xFFFFFFFFu;
  uint32_t index = kInvalid;
  uint32_t generation = 0;
  bool valid() const { return index != kInvalid; }
  friend bool operator==(const EntityHandle&, const EntityHandle&) = default;
};

enum class ShapeKind : uint8_t { kNone, kCylinder, kBox };

// Collision shape, in the entity's frame; the body's origin is at the centre
// of its base (z = bottom).
struct Geometry {
  ShapeKind shape = ShapeKind::kNone;
  double radius = 0;         // cylinder radius (m)
  Vec3 size = Vec3::Zero();  // box: full size x, y, z; cylinder: z is the height (m)
  double height() const { return size.z(); }
  // Radius of the smallest vertical cylinder around the origin holding the shape.
  double BoundingRadius() const {
    return shape == ShapeKind::kBox ? 0.5 * std::hypot(size.x(), size.y()) : radius;
  }
};

// Half extents along x and y of the axis-aligned rectangle holding the
// footprint of `g` turned by `orientation` about Z.
inline Vec2 FootprintHalfExtents(const Geometry& g, const Quat& orientation) {
  if (g.shape != ShapeKind::kBox) return Vec2(g.radius, g.radius);
  const double yaw = YawOf(orientation);
  const double c = std::abs(std::cos(yaw)), s = std::abs(std::sin(yaw));
  return Vec2(0.5 * (c * g.size.x() + s * g.size.y()), 0.5 * (s * g.size.x() + c * g.size.y()));
}

// Per-entity flags.
enum EntityFlag : uint8_t {
  kAlive = 1,
  kMovable = 2,  // can change pose (robots, movable objects)
  kSolid = 4,    // takes part in collisions and blocks rays
  kRobot = 8,    // carries a controller
};

// Differential drive of a wheeled robot: written by the steering actuator,
// read by engines; engines write back what the wheels really did.
struct DriveState {
  static constexpr const char* kComponentName = "drive";
  double target_left = 0, target_right = 0;        // commanded wheel speeds (m/s)
  double left = 0, right = 0;                      // wheel speeds after acceleration limits (m/s)
  double wheel_base = 0;                           // distance between the wheels (m)
  double wheel_radius = 0;                         // m
  double max_speed = 0;                            // m/s
  double travelled_left = 0, travelled_right = 0;  // distance each wheel moved last tick (m)
  // False when the robot has no power (e.g. its battery is empty): the
  // steering actuator then commands both wheels to stop.
  bool powered = true;
  void Hash(StateHasher& h) const {
    const double v[4] = {target_left, target_right, left, right};
    h.Add(v, sizeof v);
  }
};

// A point light seen by light sensors.
struct LightSource {
  double intensity = 0;
};

class Space {
 public:
  // What an entity is made of when it is added.
  struct EntityInit {
    std::string id;
    uint16_t type = 0;
    Pose pose;
    Geometry geometry;
    uint8_t flags = kSolid;
    Color color = Color::White();
    int led_count = 0;
    double light_intensity = 0;  // > 0 makes it a light
    double mass = 0;             // kg, for dynamics engines (0: immovable)
    // Its parts' state: a drive, a gripper... (core/component.h).
    ComponentList components;
  };

  // Entity types are registered once; their id is a small integer.
  uint16_t TypeId(const std::string& label);
  const std::string& TypeLabel(uint16_t type) const { return type_labels_[type]; }
  size_t type_count() const { return type_labels_.size(); }

  // Adds an entity; the id must be new (checked by the caller).
  EntityHandle Add(const EntityInit& init) { return Add(init, init.type); }
  // As Add(init), of type `type` whatever init.type says (no copy of `init`).
  EntityHandle Add(const EntityInit& init, uint16_t type);
  // Makes room for `more` entities like `like` beyond those alive, so that
  // adding them grows no array (no doubling slack, no copy at the peak).
  void Reserve(size_t more, const EntityInit& like);
  void Remove(EntityHandle h);
  bool IsAlive(EntityHandle h) const {
    return h.index < generation_.size() && generation_[h.index] == h.generation &&
           (flags_[h.index] & kAlive);
  }
  EntityHandle Find(std::string_view id) const;
  // Asks for the id table's entry where `id` would be looked for, for a
  // caller that knows the next id it will add (a <distribute> block): in a
  // big swarm each lookup is a miss at a random place. Changes no result.
  void PrefetchId(std::string_view id) const {
    if (!id_table_.empty())
      __builtin_prefetch(&id_table_[std::hash<std::string_view>()(id) & (id_table_.size() - 1)]);
  }
  EntityHandle HandleOf(uint32_t index) const { return {index, generation_[index]}; }

  // Number of slots (alive or not); iterate 0..slots() and test alive().
  uint32_t slots() const { return static_cast<uint32_t>(flags_.size()); }
  size_t alive_count() const { return alive_count_; }
  bool alive(uint32_t i) const { return flags_[i] & kAlive; }
  uint8_t flags(uint32_t i) const { return flags_[i]; }
  bool movable(uint32_t i) const { return flags_[i] & kMovable; }
  const std::string& id(uint32_t i) const { return ids_[i]; }
  uint16_t type(uint32_t i) const { return types_[i]; }
  Pose& pose(uint32_t i) { return poses_[i]; }
  const Pose& pose(uint32_t i) const { return poses_[i]; }
  Twist& twist(uint32_t i) { return twists_[i]; }
  const Twist& twist(uint32_t i) const { return twists_[i]; }
  const Geometry& geometry(uint32_t i) const { return geometries_[i]; }
  Color color(uint32_t i) const { return colors_[i]; }
  double mass(uint32_t i) const { return masses_[i]; }
  // Set by engines when the entity touched something during the last tick.
  bool in_contact(uint32_t i) const { return contact_[i]; }
  void set_in_contact(uint32_t i, bool c) { contact_[i] = c; }

  // LEDs of an entity (empty if it has none).
  std::span<Color> leds(uint32_t i) { return {leds_.data() + led_offset_[i], led_count_[i]}; }
  std::span<const Color> leds(uint32_t i) const {
    return {leds_.data() + led_offset_[i], led_count_[i]};
  }
  // The component of type T of entity `i`, or nullptr if it has none
  // (core/component.h). A scan of the entity's few components.
  template <class T>
  T* Get(uint32_t i) {
    const ComponentType t = ComponentTypeOf<T>();
    const ComponentRef* refs = component_refs_.data() + component_begin_[i];
    for (uint32_t k = 0, n = component_count_[i]; k < n; ++k) {
      if (refs[k].type == t) return &static_cast<ComponentPool<T>&>(*pools_[t])[refs[k].index];
    }
    return nullptr;
  }
  template <class T>
  const T* Get(uint32_t i) const {
    return const_cast<Space*>(this)->Get<T>(i);
  }
  bool Has(uint32_t i, ComponentType type) const {
    const ComponentRef* refs = component_refs_.data() + component_begin_[i];
    for (uint32_t k = 0, n = component_count_[i]; k < n; ++k) {
      if (refs[k].type == type) return true;
    }
    return false;
  }
  // The component types entity `i` carries, in the order they were added.
  std::vector<ComponentType> ComponentsOf(uint32_t i) const;
  // Every item of component type T, with owners (ComponentPoolBase::owner).
  template <class T>
  ComponentPool<T>& Pool() {
    const ComponentType t = ComponentTypeOf<T>();
    if (pools_.size() <= t) pools_.resize(t + 1);
    if (!pools_[t]) pools_[t] = std::make_unique<ComponentPool<T>>();
    return static_cast<ComponentPool<T>&>(*pools_[t]);
  }
  // Drive of a wheeled robot, or nullptr.
  DriveState* drive(uint32_t i) { return Get<DriveState>(i); }
  const DriveState* drive(uint32_t i) const { return Get<DriveState>(i); }
  const LightSource* light(uint32_t i) const {
    return light_slot_[i] < 0 ? nullptr : &lights_[light_slot_[i]];
  }
  // Slots of the alive entities of one type, in the order they were added.
  const std::vector<uint32_t>& OfType(uint16_t type) const;

  // The arena: an axis-aligned box given by centre and size.
  void SetArena(const Vec3& center, const Vec3& size);
  const Vec3& arena_min() const { return arena_min_; }
  const Vec3& arena_max() const { return arena_max_; }
  // The side of the grid's cells (m) when the largest movable entity's
  // bounding radius is `max_movable_radius` (before the cap on the cell
  // count that grows the cells of a huge, nearly empty arena).
  static double GridCellSize(double max_movable_radius) {
    return std::max(0.5, 2.0 * max_movable_radius);
  }
  Floor& floor() { return floor_; }
  const Floor& floor() const { return floor_; }
  // A flat ceiling over the arena (<ceiling>): its height z (world frame),
  // and whether a magnet holds to it. None: the arena is open above.
  struct Ceiling {
    double z = 0;
    bool ferromagnetic = true;
  };
  const std::optional<Ceiling>& ceiling() const { return ceiling_; }
  void SetCeiling(std::optional<Ceiling> ceiling) { ceiling_ = ceiling; }

  // Rebuilds the spatial index from the current poses. Called once per tick
  // after physics and whenever entities were added or removed.
  void UpdateIndex();
  // The pool the spatial index is rebuilt with (the simulation's; none: on
  // the calling thread alone). The result is the same either way.
  void set_pool(ThreadPool* pool) { pool_ = pool; }
  bool index_dirty() const { return index_dirty_; }
  // Appends to `out` every solid entity whose footprint may overlap the
  // rectangle [x0, x1] x [y0, y1], each once, in slot order per grid cell.
  void Gather(double x0, double y0, double x1, double y1, std::vector<uint32_t>& out) const;
  // For callers that gather around many places in turn (a sensor, robot by
  // robot): asks for what Gather over the same rectangle will read, so that
  // it arrives while the caller works on the places before. With a swarm
  // larger than the caches, each read is a miss at a random place. First the
  // cells' starts (a few places ahead), then, once those are in the cache,
  // the cells' entries (one or two places ahead). Changes no result.
  [[gnu::always_inline]] void PrefetchGatherCells(double x0, double y0, double x1,
                                                  double y1) const {
    const double m = max_movable_radius_;
    const int cx0 = CellX(x0 - m);
    for (int cy = CellY(y0 - m), cy1 = CellY(y1 + m); cy <= cy1; ++cy) {
      __builtin_prefetch(&cell_start_[static_cast<size_t>(cy) * nx_ + cx0]);
    }
  }
  [[gnu::always_inline]] void PrefetchGatherItems(double x0, double y0, double x1,
                                                  double y1) const {
    const double m = max_movable_radius_;
    const int cx0 = CellX(x0 - m);
    for (int cy = CellY(y0 - m), cy1 = CellY(y1 + m); cy <= cy1; ++cy) {
      __builtin_prefetch(movable_items_.data() +
                         cell_start_[static_cast<size_t>(cy) * nx_ + cx0].movable);
    }
  }
  // The movable solid entities' slots grouped by grid cell, cells row by row,
  // as of the last UpdateIndex: a spatially coherent order for sweeps.
  const std::vector<uint32_t>& movable_by_cell() const { return movable_items_; }
  // Largest bounding radius among movable solid entities (m).
  double max_movable_radius() const { return max_movable_radius_; }
  double cell_size() const { return cell_; }

  // Hash of every alive entity's pose, velocity, LEDs and drive.
  void Hash(StateHasher& h) const;

 private:
  // Where a cell's entries start in movable_items_ and fixed_items_. The two
  // tables are interleaved so that a query reads one cache line per row of
  // cells for both kinds: the grid is read once or twice per robot per tick,
  // at random places, and these lookups were the cost of a query.
  struct CellStart {
    uint32_t movable = 0;
    uint32_t fixed = 0;
  };
  void ConfigureGrid();
  void BuildMovableGrid();
  void BuildStaticGrid();
  // Inline: called for every query box corner, several times per robot per tick.
  int CellX(double x) const { return ClampedCellIndex((x - arena_min_.x()) * inv_cell_, nx_); }
  int CellY(double y) const { return ClampedCellIndex((y - arena_min_.y()) * inv_cell_, ny_); }

  // Hot arrays, indexed by slot.
  std::vector<uint8_t> flags_;
  std::vector<uint32_t> generation_;
  std::vector<uint16_t> types_;
  std::vector<Pose> poses_;
  std::vector<Twist> twists_;
  std::vector<Geometry> geometries_;
  std::vector<Color> colors_;
  std::vector<double> masses_;
  std::vector<uint8_t> contact_;
  std::vector<uint32_t> led_offset_;
  std::vector<uint16_t> led_count_;
  std::vector<int32_t> light_slot_;
  std::vector<uint32_t> component_begin_;  // into component_refs_
  std::vector<uint8_t> component_count_;
  // Components, packed.
  struct ComponentRef {
    ComponentType type;
    uint32_t index;  // in pools_[type]
  };
  std::vector<ComponentRef> component_refs_;
  std::vector<std::unique_ptr<ComponentPoolBase>> pools_;  // by component type
  std::vector<Color> leds_;
  std::vector<LightSource> lights_;
  // Cold data.
  // A deque: an id's address stays valid while its entity lives (a
  // controller's id() refers to it).
  std::deque<std::string> ids_;
  // Id index: open addressing with linear probing over slots (kNoSlot:
  // empty, kRemovedSlot: a removed entry), a power of two long and at most
  // half full. 4 to 8 bytes per entity, where a hash map's node per id cost
  // about 70.
  static constexpr uint32_t kNoSlot = UINT32_MAX, kRemovedSlot = UINT32_MAX - 1;
  size_t IdPosition(std::string_view id) const;
  void IndexId(uint32_t slot);
  void UnindexId(uint32_t slot);
  void GrowIdTable(size_t entries);
  std::vector<uint32_t> id_table_;
  size_t id_table_used_ = 0;  // entries, removed ones included
  std::vector<std::vector<uint32_t>> by_type_;
  std::vector<std::string> type_labels_;
  std::vector<uint32_t> free_slots_;
  size_t alive_count_ = 0;

  Vec3 arena_min_ = Vec3(-1, -1, 0), arena_max_ = Vec3(1, 1, 1);
  Floor floor_;
  std::optional<Ceiling> ceiling_;

  // Spatial index, a uniform grid over the arena: movable solid entities by
  // the cell of their centre (rebuilt every tick); non-movable solid ones in
  // every cell their footprint touches (rebuilt only when they change). At
  // most GridCellCap(entities) cells (core/bounds.h), whatever the arena.
  double cell_ = 0.5, inv_cell_ = 2.0;
  int nx_ = 0, ny_ = 0;
  std::vector<CellStart> cell_start_;    // nx*ny + 1, row by row
  std::vector<uint32_t> movable_items_;  // entity slots grouped by cell
  std::vector<uint32_t> fixed_items_;
  bool index_dirty_ = true, static_dirty_ = true;
  double max_movable_radius_ = 0;
  std::vector<uint32_t> cell_scratch_;
  std::vector<uint32_t> band_offset_;  // movable entries before each band of rows
  ThreadPool* pool_ = nullptr;
  std::vector<uint32_t> cell_cursor_;
};

template <class T>
uint32_t ComponentList::Item<T>::AddTo(Space& space, uint32_t slot) const {
  return space.Pool<T>().Add(slot, value);
}

template <class T>
void ComponentList::Item<T>::ReserveIn(Space& space, size_t more) const {
  space.Pool<T>().Reserve(more);
}

}  // namespace colony
