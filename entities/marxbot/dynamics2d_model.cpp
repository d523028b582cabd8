// The marXbot in dynamics2d (engines/dynamics2d): a disc driven by its
// treels (force- and torque-limited, they slip when pushing hard), with a
// gripper that welds what is in front of its jaws. A marXbot without a
// drive slides on the floor like an object. With manipulator="true" it also
// simulates the construction manipulator, kinematically, after the step
// (manipulator2d.h); a pocket's own model takes its body out of the world
// while it is held (entities/objects/dynamics2d_model.cpp).
#include <string_view>
#include <vector>

#include "engines/dynamics2d/dynamics2d.h"
#include "entities/marxbot/manipulator2d.h"

namespace colony {
namespace {

class MarxbotDynamics2dModel : public Dynamics2dModel {
 public:
  void Add(Engine& engine, uint32_t s) override {
    if (engine.entities().drive(s)) {
      treels_.Add(engine, s);
    } else {
      engine.AddFloorFriction(s);
    }
    manipulator_.Add(engine.entities(), s);
  }
  void Remove(Engine& engine, uint32_t s) override {
    (void)engine;
    treels_.Remove(s);
  }
  void EntityLeaving(Engine& engine, uint32_t s) override {
    gripper_.Forget(engine, s);
    manipulator_.Leaving(engine.entities(), s, kNoHook);
  }
  void BeforeStep(Engine& engine, double dt) override {
    (void)dt;
    gripper_.Update(engine, treels_.slots());
  }
  void BeforeSubstep(Engine& engine, double h) override { treels_.Drive(engine, h); }
  void AfterStep(Engine& engine, double dt) override {
    treels_.WriteOdometry(engine, dt);
    manipulator_.Step(engine.entities(), dt, kNoHook);
  }
  bool Anchor(const Space& space, uint32_t s, std::string_view name, Pose& pose) const override {
    return Manipulator2d::Anchor(space, s, name, pose);
  }

 private:
  // Carrying needs nothing of this engine: the pocket's model reads its holder.
  inline static const Manipulator2d::CarriedHook kNoHook = [](uint32_t, bool) {};

  dynamics2d::Treels treels_;
  dynamics2d::WeldGripper gripper_;
  Manipulator2d manipulator_;
};

COLONY_REGISTER_PHYSICS_MODEL(
    MarxbotDynamics2dModel, "dynamics2d:marxbot",
    "circular body driven by force- and torque-limited treels (slip when pushing hard); with "
    "manipulator=\"true\" a kinematic head (elevation, rotation, tilt) whose magnet carries "
    "pockets",
    (std::vector<std::string>{"drive", "gripper", "manipulator"}));

}  // namespace
}  // namespace colony
