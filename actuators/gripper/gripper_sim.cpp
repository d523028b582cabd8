// Simulated turret and gripper: the turret turns towards its target at
// turret_speed (not while holding); the grip command goes to the engine,
// which joins the robot to what is in front of the jaws. It needs the robot's
// "gripper" component, which only dynamics2d's marXbot model simulates;
// elsewhere it is a load-time error.
#include <algorithm>
#include <cmath>

#include "actuators/gripper/gripper.h"
#include "actuators/gripper/gripper_state.h"
#include "core/device.h"
#include "core/simulation.h"

namespace colony {
namespace {

struct GripperInstance : GripperActuator, InstanceBase {
  using Interface = GripperActuator;
};

class GripperSystem : public ActuatorSystem {
 public:
  void Configure(const ConfigNode& node) override {
    turret_speed_ = node.GetDouble("turret_speed", 1.0, Range::Positive());
    reach_ = node.GetDouble("reach", 0.02, Range::Positive());
    // ARGoS has two devices where Colony has one: under ARGoS's names this
    // instance drives only its own half, so a controller declaring both
    // footbot_gripper and footbot_turret has each command reach the robot once.
    const std::string name = node.name();
    drives_grip_ = name != "footbot_turret";
    drives_turret_ = name != "footbot_gripper";
  }

  Actuator* Attach(EntityHandle robot, const RandomStream& rng) override {
    GripperState* g = sim().space().Get<GripperState>(robot.index);  // checked by the host
    if (drives_turret_) g->turret_speed = turret_speed_;
    if (drives_grip_) g->reach = reach_;
    return &instances_.Add(robot, rng);
  }
  std::vector<std::string> NeededComponents() const override {
    return {GripperState::kComponentName};
  }
  void Detach(Actuator* a) override { instances_.Remove(static_cast<GripperActuator*>(a)); }
  size_t size() const override { return instances_.size(); }

  void Act(size_t begin, size_t end) override {
    Space& space = sim().space();
    const double max_turn = turret_speed_ * sim().dt();
    for (size_t k = begin; k < end; ++k) {
      GripperInstance& a = instances_[k];
      if (!a.alive) continue;
      GripperState& g = *space.Get<GripperState>(a.robot.index);
      if (drives_grip_) g.want_grip = a.gripping();
      if (!drives_turret_ || g.holding()) continue;
      const double target =
          std::isfinite(a.turret_target()) ? WrapAngle(a.turret_target()) : g.turret;
      g.turret =
          WrapAngle(g.turret + std::clamp(WrapAngle(target - g.turret), -max_turn, max_turn));
    }
  }

 private:
  double turret_speed_ = 1.0, reach_ = 0.02;
  bool drives_grip_ = true, drives_turret_ = true;
  InstanceStore<GripperInstance> instances_;
};

COLONY_REGISTER_ACTUATOR(
    GripperSystem, "gripper", "default",
    "the marXbot's docking turret and gripper: turn the turret, grip what is in front of the jaws, "
    "release (needs an engine that simulates gripping: dynamics2d)",
    DeviceInterface{"actuators/gripper/gripper.h",
                    "colony::GripperActuator",
                    {"SetTurretAngle(angle): from the robot's front, ccw (rad)",
                     "Grip(), Release()", "turret_target() (rad), gripping()"}},
    (std::vector<AttributeDoc>{
        {"turret_speed", "a number > 0 (rad/s)", "1", "how fast the turret turns"},
        {"reach", "a number > 0 (m)", "0.02",
         "how far beyond the body the jaws close on something"},
    }),
    {"footbot_gripper", "footbot_turret"});

}  // namespace
}  // namespace colony
