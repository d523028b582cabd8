// Simulated hand-bot head actuator: writes the target rotation (wrapped to
// (-pi, pi]) and speed (at most the motor's no-load speed, with a warning)
// into the robot's HandbotArmsState; the physics model turns the head with
// the torque its motor gives (dynamics3d).
#include "actuators/handbot_arms/handbot_arms_state.h"
#include "actuators/handbot_arms/handbot_commands.h"
#include "actuators/handbot_head/handbot_head.h"
#include "core/device.h"
#include "core/simulation.h"

namespace colony {
namespace {

struct HeadInstance : HandbotHeadActuator, InstanceBase {
  using Interface = HandbotHeadActuator;
  double nominal = 0;
  handbot_commands::Warned warned;
};

class HandbotHeadSystem : public ActuatorSystem {
 public:
  void Configure(const ConfigNode&) override {}
  std::vector<std::string> NeededComponents() const override {
    return {HandbotArmsState::kComponentName};
  }
  Actuator* Attach(EntityHandle robot, const RandomStream& rng) override {
    HeadInstance& a = instances_.Add(robot, rng);
    a.nominal = sim().space().Get<HandbotArmsState>(robot.index)->head.speed;
    return &a;
  }
  void Detach(Actuator* a) override { instances_.Remove(static_cast<HandbotHeadActuator*>(a)); }
  size_t size() const override { return instances_.size(); }
  void Act(size_t begin, size_t end) override {
    Space& space = sim().space();
    for (size_t k = begin; k < end; ++k) {
      HeadInstance& a = instances_[k];
      if (!a.alive) continue;
      HandbotJoint& head = space.Get<HandbotArmsState>(a.robot.index)->head;
      const std::string& id = space.id(a.robot.index);
      head.speed = handbot_commands::Speed(a.speed(), a.nominal, head, id, "head", a.warned);
      head.target =
          WrapAngle(std::isfinite(a.rotation_target()) ? a.rotation_target() : head.position);
    }
  }

 private:
  InstanceStore<HeadInstance> instances_;
};

COLONY_REGISTER_ACTUATOR(
    HandbotHeadSystem, "handbot_head", "default",
    "the hand-bot's head: rotation of both arms about the robot's forward axis (rad, rad/s; "
    "motor: stall 1.44 N m, no-load 2.85 rad/s)",
    DeviceInterface{"actuators/handbot_head/handbot_head.h",
                    "colony::HandbotHeadActuator",
                    {"SetRotation(angle): both arms about the robot's forward axis (rad)",
                     "SetSpeed(speed): rad/s", "rotation_target(), speed()"}},
    (std::vector<AttributeDoc>{}));

}  // namespace
}  // namespace colony
