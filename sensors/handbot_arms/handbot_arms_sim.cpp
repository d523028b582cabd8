// Simulated hand-bot arms sensor: each arm joint as the physics model left
// it after the step (HandbotArmsState), with optional noise on the torques.
#include "actuators/handbot_arms/handbot_arms_state.h"
#include "core/device.h"
#include "core/noise.h"
#include "core/simulation.h"
#include "sensors/handbot_arms/handbot_arms.h"

namespace colony {
namespace {

struct ArmsSensorInstance : HandbotArmsSensor, InstanceBase {
  using Interface = HandbotArmsSensor;
  void Set(int k, const HandbotJoint& j, double torque) {
    extension_[k] = j.position;
    velocity_[k] = j.velocity;
    torque_[k] = torque;
    stalled_[k] = j.stalled;
  }
};

class HandbotArmsSensorSystem : public SensorSystem {
 public:
  void Configure(const ConfigNode& node) override { noise_ = NoiseModel::Read(node); }
  std::vector<std::string> NeededComponents() const override {
    return {HandbotArmsState::kComponentName};
  }
  Sensor* Attach(EntityHandle robot, const RandomStream& rng) override {
    return &instances_.Add(robot, rng);
  }
  void Detach(Sensor* s) override { instances_.Remove(static_cast<HandbotArmsSensor*>(s)); }
  size_t size() const override { return instances_.size(); }
  void Update(size_t begin, size_t end) override {
    const Space& space = sim().space();
    for (size_t i = begin; i < end; ++i) {
      ArmsSensorInstance& s = instances_[i];
      if (!s.alive) continue;
      const HandbotArmsState& arms = *space.Get<HandbotArmsState>(s.robot.index);
      for (int k = 0; k < 2; ++k) {
        const HandbotJoint& arm = arms.arm[k];
        s.Set(k, arm, noise_.enabled() ? noise_.Apply(arm.torque, s.rng) : arm.torque);
      }
    }
  }
  void Hash(StateHasher& h) const override {
    for (size_t i = 0; i < instances_.size(); ++i) {
      const auto& s = instances_[i];
      if (!s.alive) continue;
      for (int k = 0; k < 2; ++k) {
        const double v[4] = {s.extension(k), s.velocity(k), s.torque(k), s.stalled(k) ? 1.0 : 0.0};
        h.Add(v, sizeof v);
      }
    }
  }

 private:
  NoiseModel noise_;
  InstanceStore<ArmsSensorInstance> instances_;
};

COLONY_REGISTER_SENSOR(
    HandbotArmsSensorSystem, "handbot_arms", "default",
    "the hand-bot's arms: extension of each (rad), speed (rad/s), motor torque (N m), stalled",
    DeviceInterface{
        "sensors/handbot_arms/handbot_arms.h",
        "colony::HandbotArmsSensor",
        {"extension(arm): 0 folded .. pi/2 straight ahead (rad); arm: kLeft or kRight",
         "velocity(arm): rad/s", "torque(arm): the motor's, averaged over the tick (N m)",
         "stalled(arm): about its stall torque, not moving to its target"}},
    NoiseModel::Attributes(false));

}  // namespace
}  // namespace colony
