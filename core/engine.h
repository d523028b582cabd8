// Physics engines (plugin kind "engine"). An engine steps the poses of the
// entities it owns. Several engines may share an experiment, each owning a
// region (<boundaries>); a movable entity belongs to the one engine whose
// region holds it and migrates when it crosses into another's; fixed
// entities are present in every engine whose region they touch. Engines then
// step in parallel, so an engine reads only its own entities and fixed ones,
// never another engine's movables.
//
// An engine knows no robot. Each entity type it can simulate has a registered
// physics model for the (engine, entity type) pair (plugin kind
// "physics_model", label "engine:entity", e.g. entities/marxbot/
// dynamics3d_model.cpp registers "dynamics3d:marxbot"): the code that builds
// that type's bodies and joints in the engine, steps its motors and writes
// its state back. The registration lists the components (core/component.h)
// the model simulates; devices name the components they need, and the host
// checks one against the other when it attaches a device and whenever a
// robot migrates (core/simulation.cpp). A missing pair is a load-time error
// naming both.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/config.h"
#include "core/region.h"
#include "core/registry.h"
#include "core/simulation_bound.h"
#include "core/space.h"

namespace colony {

class Simulation;

// How one engine simulates one entity type. The host makes one instance per
// engine and entity type of an experiment, so a model may keep the entities
// it was given in that engine and step them as a batch. Each engine defines
// the interface its models implement (a subclass of this, in the engine's
// header), and calls it from AddEntity, Step and RemoveEntity.
class PhysicsModel {
 public:
  virtual ~PhysicsModel() = default;
  // Anchors: named frames on an entity's moving parts (a manipulator's
  // head, a gripper, a camera mount), where the engine put them. Sets `pose`
  // (world frame) to anchor `name` of entity `slot`, one of this model's
  // entities in its engine, and returns true; false if the model has no such
  // anchor (`space`: the entity's). A model computes an anchor when a device asks (Simulation::
  // Anchor), from its bodies' poses after the last step, so an anchor nobody
  // reads costs nothing. Called from the devices' parallel chunks: it must
  // only read.
  virtual bool Anchor(const Space& space, uint32_t slot, std::string_view name, Pose& pose) const {
    (void)space, (void)slot, (void)name, (void)pose;
    return false;
  }
};

class PhysicsEngine : public NamedSimulationBound {
 public:
  virtual ~PhysicsEngine() = default;

  // Reads the engine's element in <physics_engines> (attributes already
  // checked against the registered list).
  virtual void Configure(const ConfigNode& node) { (void)node; }
  // Takes the entity in slot `entity` under this engine, simulated by `model`
  // (this engine's instance of the model registered for this engine and the
  // entity's type), starting from its pose and velocity in the space (it may
  // be migrating in).
  virtual void AddEntity(EntityHandle entity, PhysicsModel& model) = 0;
  virtual void RemoveEntity(EntityHandle entity) = 0;
  // Whether it simulates the third dimension (gravity, falling, stacking):
  // the engines of one experiment must agree (a property of the engine, not
  // of what it simulates of a robot).
  virtual bool Is3D() const { return false; }
  // Advances the owned entities by dt seconds.
  virtual void Step(double dt) = 0;

  // The region it simulates; none: the whole arena.
  const std::optional<Region>& region() const { return region_; }
  void SetRegion(Region region) {
    region_ = std::move(region);
    box_ = region_->AxisAlignedBox(box_lo_, box_hi_);
  }
  // The entity types it takes (entities="eyebot"): every movable entity of
  // these types, wherever it is (such an engine has no region), is its own
  // and no other engine's, and it takes no movable entity of another type
  // (fixed ones, walls, it shares as every engine does). Empty: it takes the
  // movables its region holds whose types no engine takes.
  const std::vector<std::string>& entity_types() const { return entity_types_; }
  bool takes_types() const { return !entity_types_.empty(); }
  void SetEntityTypes(std::vector<std::string> types) { entity_types_ = std::move(types); }
  bool Holds(const Vec3& p) const {
    if (!region_) return true;
    return box_ ? region_->BoxContains(box_lo_, box_hi_, p) : region_->Contains(p);
  }
  // Whether entity slot `s` is one of this engine's (set by the host).
  bool Owns(uint32_t s) const { return s < owned_.size() && owned_[s]; }
  void SetOwned(uint32_t s, bool owned) {
    if (owned_.size() <= s) owned_.resize(s + 1, 0);
    owned_[s] = owned;
  }

 private:
  std::optional<Region> region_;
  // Whether the region is an axis-aligned rectangle (Region::AxisAlignedBox),
  // and its corners: Holds is then four comparisons.
  bool box_ = false;
  Vec2 box_lo_, box_hi_;
  std::vector<std::string> entity_types_;
  std::vector<uint8_t> owned_;  // per space slot
};

// The engine as messages name it: "kinematics2d 'k2d'" ("none" for null).
inline std::string EngineName(const PhysicsEngine* engine) {
  return engine ? engine->label() + " '" + engine->id() + "'" : "none";
}

}  // namespace colony
