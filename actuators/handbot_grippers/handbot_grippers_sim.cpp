// Simulated hand-bot grippers actuator: writes each gripper's target
// rotation (wrapped to (-pi, pi]) and speed (at most the motor's no-load
// speed, with a warning), and its claws' target aperture (within [0, pi/2],
// with a warning outside), into the robot's HandbotArmsState; the physics
// model turns the grippers, moves the claws and grasps.
#include "actuators/handbot_arms/handbot_arms_state.h"
#include "actuators/handbot_arms/handbot_commands.h"
#include "actuators/handbot_grippers/handbot_grippers.h"
#include "core/device.h"
#include "core/simulation.h"

namespace colony {
namespace {

struct GrippersInstance : HandbotGrippersActuator, InstanceBase {
  using Interface = HandbotGrippersActuator;
  double nominal[2] = {};
  handbot_commands::Warned warned[2], claws_warned[2];
};

class HandbotGrippersSystem : public ActuatorSystem {
 public:
  void Configure(const ConfigNode&) override {}
  std::vector<std::string> NeededComponents() const override {
    return {HandbotArmsState::kComponentName};
  }
  Actuator* Attach(EntityHandle robot, const RandomStream& rng) override {
    GrippersInstance& a = instances_.Add(robot, rng);
    const HandbotArmsState& arms = *sim().space().Get<HandbotArmsState>(robot.index);
    for (int k = 0; k < 2; ++k) a.nominal[k] = arms.wrist[k].speed;
    return &a;
  }
  void Detach(Actuator* a) override { instances_.Remove(static_cast<HandbotGrippersActuator*>(a)); }
  size_t size() const override { return instances_.size(); }
  void Act(size_t begin, size_t end) override {
    Space& space = sim().space();
    for (size_t i = begin; i < end; ++i) {
      GrippersInstance& a = instances_[i];
      if (!a.alive) continue;
      HandbotArmsState& arms = *space.Get<HandbotArmsState>(a.robot.index);
      const std::string& id = space.id(a.robot.index);
      for (int k = 0; k < 2; ++k) {
        HandbotJoint& wrist = arms.wrist[k];
        const char* name = k == HandbotGrippersActuator::kLeft ? "left gripper rotation"
                                                               : "right gripper rotation";
        wrist.speed = handbot_commands::Speed(a.rotation_speed(k), a.nominal[k], wrist, id, name,
                                              a.warned[k]);
        wrist.target =
            WrapAngle(std::isfinite(a.rotation_target(k)) ? a.rotation_target(k) : wrist.position);
        auto& claws = arms.claws[k];
        claws.target = handbot_commands::Target(
            a.aperture_target(k), claws.aperture, 0.0, M_PI / 2, id,
            k == HandbotGrippersActuator::kLeft ? "left claws' aperture" : "right claws' aperture",
            a.claws_warned[k]);
      }
    }
  }

 private:
  InstanceStore<GrippersInstance> instances_;
};

COLONY_REGISTER_ACTUATOR(
    HandbotGrippersSystem, "handbot_grippers", "default",
    "the hand-bot's two grippers: rotation about the arm (rad, rad/s; motor: stall 0.265 N m, "
    "no-load 0.604 rad/s) and claws' aperture, 0 closed to pi/2 open; closing on something "
    "grasps it (25 N, holds up to 4 kg)",
    DeviceInterface{
        "actuators/handbot_grippers/handbot_grippers.h",
        "colony::HandbotGrippersActuator",
        {"SetRotation(g, angle) (rad), SetRotationSpeed(g, speed) (rad/s): about the arm; g: kLeft "
         "or kRight",
         "SetAperture(g, angle): the claws, 0 closed .. pi/2 open (rad); Open(g), Close(g)",
         "rotation_target(g), rotation_speed(g), aperture_target(g)"}},
    (std::vector<AttributeDoc>{}));

}  // namespace
}  // namespace colony
