// kinematics2d's interface to the physics models of entity types
// (core/engine.h). The engine knows two kinds of entity: discs driven by the
// differential drive of their DriveState component (moved, blocked, never
// overlapping), and obstacles (read from the space, never moved). A model
// says which its entity type is.
#pragma once

#include <cstdint>
#include <vector>

#include "core/engine.h"

namespace colony {

namespace kinematics2d {

// What the engine offers the models that hook into its step (a marXbot's
// manipulator carrying a pocket).
class Engine : public PhysicsEngine {
 public:
  Space& entities();
  // Entity `s` is carried (true) or no longer (false): while carried, the
  // engine's collision test ignores it (it moves with its carrier, above or
  // in front of it, and blocks no robot).
  void SetCarried(uint32_t s, bool carried);

 protected:
  bool carried(uint32_t s) const { return s < carried_.size() && carried_[s]; }

 private:
  std::vector<uint8_t> carried_;  // per space slot
};

}  // namespace kinematics2d

class Kinematics2dModel : public PhysicsModel {
 public:
  // True: the engine moves the type's entities as discs (the footprint's
  // bounding circle) driven by their DriveState; false: they are fixed
  // obstacles, movable or not.
  virtual bool driven() const = 0;
  // Hooks, for models that simulate more than a disc (none by default).
  // Entity `s` of this model enters the engine.
  virtual void Add(kinematics2d::Engine& engine, uint32_t s) { (void)engine, (void)s; }
  // Any entity `s` leaves the engine (a model holding it lets go first).
  virtual void EntityLeaving(kinematics2d::Engine& engine, uint32_t s) { (void)engine, (void)s; }
  // Once per tick, after the engine moved the discs (serially, models in the
  // order their first entity came).
  virtual void AfterStep(kinematics2d::Engine& engine, double dt) { (void)engine, (void)dt; }
};

// The model of a type that is only an obstacle in kinematics2d.
class Kinematics2dObstacleModel : public Kinematics2dModel {
 public:
  bool driven() const override { return false; }
};

// The model of a type whose entities are discs driven by differential drive.
class Kinematics2dDrivenDiscModel : public Kinematics2dModel {
 public:
  bool driven() const override { return true; }
};

}  // namespace colony
