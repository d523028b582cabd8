// dynamics2d's interface to the physics models of entity types
// (core/engine.h): the engine (a Box2D world seen from above, floor friction,
// one body per entity built from its footprint) knows no robot; a model adds
// what its type needs to the body (floor friction, treels, a gripper) and
// drives it each (sub-)step. Reusable pieces models compose are at the end.
#pragma once

#include <box2d/box2d.h>

#include <cstdint>
#include <vector>

#include "core/engine.h"

namespace colony {
namespace dynamics2d {

inline constexpr uint32_t kNone = 0xFFFFFFFFu;
inline constexpr double kGravity = 9.81;

// The engine's attributes, as models read them.
struct Params {
  double friction = 0.5;          // between bodies
  double floor_friction = 0.5;    // of things sliding on the floor
  double robot_max_force = 15;    // N, treels
  double robot_max_torque = 1.5;  // N m, treels
};

class Engine;

}  // namespace dynamics2d

// How one entity type is simulated in dynamics2d. One instance per engine
// and type (core/engine.h): it keeps the entities it was given and steps
// them as a batch. The engine makes every entity's body (static if the
// entity is fixed, else dynamic with the entity's mass) from its footprint
// before calling Add.
class Dynamics2dModel : public PhysicsModel {
 public:
  using Engine = dynamics2d::Engine;
  // Movable entity `s` has its body (Engine::BodyOf): add what the type needs.
  virtual void Add(Engine& engine, uint32_t s) = 0;
  // `s`, one of this model's entities, is leaving the engine; the engine then
  // destroys its body (and the joints on it).
  virtual void Remove(Engine& engine, uint32_t s) { (void)engine, (void)s; }
  // Any entity `s` is leaving the engine (a model holding it lets go first).
  virtual void EntityLeaving(Engine& engine, uint32_t s) { (void)engine, (void)s; }
  // Each tick: before the sub-steps, before each sub-step, after the tick
  // (the engine has written pose, velocity and contact).
  virtual void BeforeStep(Engine& engine, double dt) { (void)engine, (void)dt; }
  virtual void BeforeSubstep(Engine& engine, double h) { (void)engine, (void)h; }
  virtual void AfterStep(Engine& engine, double dt) { (void)engine, (void)dt; }
};

namespace dynamics2d {

// What the engine offers its models.
class Engine : public PhysicsEngine {
 public:
  const Params& params() const { return params_; }
  b2World& world() { return *world_; }
  Space& entities();
  b2Body* BodyOf(uint32_t s) const { return s < bodies_.size() ? bodies_[s] : nullptr; }
  // Slides body `s` on the floor: a friction joint to the ground whose most
  // force is floor_friction x m x g (and torque that force at the footprint's
  // bounding radius).
  void AddFloorFriction(uint32_t s);
  // Slot of the lowest-slot movable body other than `self` covering p, or kNone.
  uint32_t MovableAt(const b2Vec2& p, const b2Body* self);

 protected:
  Params params_;
  std::unique_ptr<b2World> world_;
  b2Body* ground_ = nullptr;
  std::vector<b2Body*> bodies_;  // per space slot
};

// Treels: a differential drive pushing a body towards the velocity its
// DriveState commands (forwards speed and turn rate, no sideways motion)
// with a force and a torque no larger than the engine's robot_max_force and
// robot_max_torque: when it pushes too hard the wheels slip and it falls
// behind its command. The encoders count what the body really did.
class Treels {
 public:
  void Add(Engine& engine, uint32_t s);
  void Remove(uint32_t s);
  // Force and torque towards the command, for every robot (sub-step `h`).
  void Drive(Engine& engine, double h);
  // The travelled distances of the last tick `dt`.
  void WriteOdometry(Engine& engine, double dt);
  const std::vector<uint32_t>& slots() const { return slots_; }

 private:
  // The cosine and sine of a body's angle (Box2D's float, by its bits): the
  // odometry's at the end of a tick are the drive's at the start of the
  // next, when the body was not moved in between.
  struct Heading {
    bool known = false;
    uint32_t angle_bits = 0;
    double cos = 0, sin = 0;
  };
  const Heading& HeadingOf(size_t k, float angle);

  std::vector<uint32_t> slots_;    // in the order they came
  std::vector<Heading> headings_;  // per slot of slots_
};

// A gripper that welds the thing in front of its jaws (a movable object,
// another robot) to its body until it releases; a grip does not survive the
// robot or the held thing leaving the engine. Works on GripperState.
class WeldGripper {
 public:
  // Releases what robots no longer want to hold; grips what is in front of
  // the jaws of robots (`robots`, in order) that want to hold something.
  void Update(Engine& engine, const std::vector<uint32_t>& robots);
  // Lets go of every grip that involves `s`.
  void Forget(Engine& engine, uint32_t s);

 private:
  struct Grip {
    uint32_t robot, target;
    b2Joint* joint;
  };
  void Ungrip(Engine& engine, size_t k);
  std::vector<Grip> grips_;
};

}  // namespace dynamics2d
}  // namespace colony
