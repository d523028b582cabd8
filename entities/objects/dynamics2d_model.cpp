// Objects in dynamics2d (engines/dynamics2d): boxes and cylinders pushed
// against floor friction if movable, static bodies otherwise; landmarks
// static bodies; pockets kinematic bodies (robots stop at them, nothing
// pushes them) that follow the pose the space gives them and stop colliding
// while a manipulator holds them.
#include <algorithm>
#include <vector>

#include "engines/dynamics2d/dynamics2d.h"
#include "entities/objects/pocket.h"

namespace colony {
namespace {

class SlidingModel : public Dynamics2dModel {
 public:
  void Add(Engine& engine, uint32_t s) override { engine.AddFloorFriction(s); }
};

COLONY_REGISTER_PHYSICS_MODEL(SlidingModel, "dynamics2d:box",
                              "box: pushed against floor friction if movable, static otherwise",
                              (std::vector<std::string>{}));
COLONY_REGISTER_PHYSICS_MODEL(
    SlidingModel, "dynamics2d:cylinder",
    "cylinder: pushed against floor friction if movable, static otherwise",
    (std::vector<std::string>{}));
COLONY_REGISTER_PHYSICS_MODEL(SlidingModel, "dynamics2d:landmark",
                              "landmark: a static upright cylinder", (std::vector<std::string>{}));

class PocketModel : public Dynamics2dModel {
 public:
  void Add(Engine& engine, uint32_t s) override {
    engine.BodyOf(s)->SetType(b2_kinematicBody);
    slots_.push_back(s);
  }
  void Remove(Engine&, uint32_t s) override {
    slots_.erase(std::find(slots_.begin(), slots_.end(), s));
  }
  // Each body where the space has its pocket (a manipulator may have moved
  // it), at rest; a held pocket collides with nothing.
  void BeforeStep(Engine& engine, double) override {
    const Space& space = engine.entities();
    for (uint32_t s : slots_) {
      b2Body* body = engine.BodyOf(s);
      const Pose& pose = space.pose(s);
      body->SetEnabled(space.Get<PocketState>(s)->holder == PocketState::kNobody);
      body->SetTransform(
          b2Vec2(static_cast<float>(pose.position.x()), static_cast<float>(pose.position.y())),
          static_cast<float>(YawOf(pose.orientation)));
      body->SetLinearVelocity(b2Vec2(0, 0));
      body->SetAngularVelocity(0);
    }
  }

 private:
  std::vector<uint32_t> slots_;  // in the order they came
};

COLONY_REGISTER_PHYSICS_MODEL(
    PocketModel, "dynamics2d:pocket",
    "pocket: a kinematic body robots stop at and cannot push, where the space puts it; "
    "collides with nothing while held",
    (std::vector<std::string>{}));

}  // namespace
}  // namespace colony
