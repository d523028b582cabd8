// The marXbot in dynamics2d (engines/dynamics2d): a disc driven by its
// treels (force- and torque-limited, they slip when pushing hard), with a
// gripper that welds what is in front of its jaws. A marXbot without a
// drive slides on the floor like an object.
#include <vector>

#include "engines/dynamics2d/dynamics2d.h"

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
  }
  void Remove(Engine& engine, uint32_t s) override {
    (void)engine;
    treels_.Remove(s);
  }
  void EntityLeaving(Engine& engine, uint32_t s) override { gripper_.Forget(engine, s); }
  void BeforeStep(Engine& engine, double dt) override {
    (void)dt;
    gripper_.Update(engine, treels_.slots());
  }
  void BeforeSubstep(Engine& engine, double h) override { treels_.Drive(engine, h); }
  void AfterStep(Engine& engine, double dt) override { treels_.WriteOdometry(engine, dt); }

 private:
  dynamics2d::Treels treels_;
  dynamics2d::WeldGripper gripper_;
};

COLONY_REGISTER_PHYSICS_MODEL(
    MarxbotDynamics2dModel, "dynamics2d:marxbot",
    "circular body driven by force- and torque-limited treels (slip when pushing hard)",
    (std::vector<std::string>{"drive", "gripper"}));

}  // namespace
}  // namespace colony
