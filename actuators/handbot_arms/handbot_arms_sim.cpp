// Simulated hand-bot arms actuator: writes each arm's target extension
// (within [0, pi/2], with a warning outside) and speed (at most the motor's
// no-load speed, with a warning) into the robot's HandbotArmsState; the
// physics model moves the arms with the torque their motors give.
#include "actuators/handbot_arms/handbot_arms.h"
#include "actuators/handbot_arms/handbot_arms_state.h"
#include "actuators/handbot_arms/handbot_commands.h"
#include "core/device.h"
#include "core/simulation.h"

namespace colony {
namespace {

struct ArmsInstance : HandbotArmsActuator, InstanceBase {
  using Interface = HandbotArmsActuator;
  double nominal[2] = {};
  handbot_commands::Warned warned[2];
};

class HandbotArmsSystem : public ActuatorSystem {
 public:
  void Configure(const ConfigNode&) override {}
  std::vector<std::string> NeededComponents() const override {
    return {HandbotArmsState::kComponentName};
  }
  Actuator* Attach(EntityHandle robot, const RandomStream& rng) override {
    ArmsInstance& a = instances_.Add(robot, rng);
    const HandbotArmsState& arms = *sim().space().Get<HandbotArmsState>(robot.index);
    for (int k = 0; k < 2; ++k) a.nominal[k] = arms.arm[k].speed;
    return &a;
  }
  void Detach(Actuator* a) override { instances_.Remove(static_cast<HandbotArmsActuator*>(a)); }
  size_t size() const override { return instances_.size(); }
  void Act(size_t begin, size_t end) override {
    Space& space = sim().space();
    for (size_t i = begin; i < end; ++i) {
      ArmsInstance& a = instances_[i];
      if (!a.alive) continue;
      HandbotArmsState& arms = *space.Get<HandbotArmsState>(a.robot.index);
      const std::string& id = space.id(a.robot.index);
      for (int k = 0; k < 2; ++k) {
        HandbotJoint& arm = arms.arm[k];
        const char* name = k == HandbotArmsActuator::kLeft ? "left arm" : "right arm";
        arm.speed = handbot_commands::Speed(a.speed(k), a.nominal[k], arm, id, name, a.warned[k]);
        arm.target = handbot_commands::Target(a.extension_target(k), arm.position, arm.min, arm.max,
                                              id, name, a.warned[k]);
      }
    }
  }

 private:
  InstanceStore<ArmsInstance> instances_;
};

COLONY_REGISTER_ACTUATOR(
    HandbotArmsSystem, "handbot_arms", "default",
    "the hand-bot's two arms: extension of each, 0 folded to pi/2 straight ahead (rad, rad/s; "
    "motors: stall 2.27 N m, no-load 2.61 rad/s)",
    DeviceInterface{
        "actuators/handbot_arms/handbot_arms.h",
        "colony::HandbotArmsActuator",
        {"SetExtension(arm, angle): 0 folded .. pi/2 straight ahead (rad); arm: kLeft or kRight",
         "SetSpeed(arm, speed): rad/s", "extension_target(arm), speed(arm)"}},
    (std::vector<AttributeDoc>{}));

}  // namespace
}  // namespace colony
