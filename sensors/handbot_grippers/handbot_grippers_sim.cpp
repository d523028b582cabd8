// Simulated hand-bot grippers sensor: each gripper's rotation joint and
// claws as the physics model left them after the step (HandbotArmsState),
// with optional noise on the rotation torques.
#include "actuators/handbot_arms/handbot_arms_state.h"
#include "core/device.h"
#include "core/noise.h"
#include "core/simulation.h"
#include "sensors/handbot_grippers/handbot_grippers.h"

namespace colony {
namespace {

struct GrippersSensorInstance : HandbotGrippersSensor, InstanceBase {
  using Interface = HandbotGrippersSensor;
  void Set(int k, const HandbotJoint& wrist, double torque, const HandbotArmsState::Claws& claws) {
    rotation_[k] = wrist.position;
    torque_[k] = torque;
    stalled_[k] = wrist.stalled;
    aperture_[k] = claws.aperture;
    holding_[k] = claws.holding();
  }
};

class HandbotGrippersSensorSystem : public SensorSystem {
 public:
  void Configure(const ConfigNode& node) override { noise_ = NoiseModel::Read(node); }
  std::vector<std::string> NeededComponents() const override {
    return {HandbotArmsState::kComponentName};
  }
  Sensor* Attach(EntityHandle robot, const RandomStream& rng) override {
    return &instances_.Add(robot, rng);
  }
  void Detach(Sensor* s) override { instances_.Remove(static_cast<HandbotGrippersSensor*>(s)); }
  size_t size() const override { return instances_.size(); }
  void Update(size_t begin, size_t end) override {
    const Space& space = sim().space();
    for (size_t i = begin; i < end; ++i) {
      GrippersSensorInstance& s = instances_[i];
      if (!s.alive) continue;
      const HandbotArmsState& arms = *space.Get<HandbotArmsState>(s.robot.index);
      for (int k = 0; k < 2; ++k) {
        const HandbotJoint& wrist = arms.wrist[k];
        s.Set(k, wrist, noise_.enabled() ? noise_.Apply(wrist.torque, s.rng) : wrist.torque,
              arms.claws[k]);
      }
    }
  }
  void Hash(StateHasher& h) const override {
    for (size_t i = 0; i < instances_.size(); ++i) {
      const auto& s = instances_[i];
      if (!s.alive) continue;
      for (int k = 0; k < 2; ++k) {
        const double v[4] = {s.rotation(k), s.torque(k), s.aperture(k), s.holding(k) ? 1.0 : 0.0};
        h.Add(v, sizeof v);
      }
    }
  }

 private:
  NoiseModel noise_;
  InstanceStore<GrippersSensorInstance> instances_;
};

COLONY_REGISTER_SENSOR(
    HandbotGrippersSensorSystem, "handbot_grippers", "default",
    "the hand-bot's grippers: rotation of each about its arm (rad), its motor torque (N m), "
    "stalled, claws' aperture (rad), holding",
    DeviceInterface{
        "sensors/handbot_grippers/handbot_grippers.h",
        "colony::HandbotGrippersSensor",
        {"rotation(g): about the arm, (-pi, pi] (rad); g: kLeft or kRight",
         "torque(g): the rotation motor's (N m)", "stalled(g): the rotation motor is stalled",
         "aperture(g): the claws, 0 closed .. pi/2 open (rad)",
         "holding(g): the claws grasp something"}},
    NoiseModel::Attributes(false));

}  // namespace
}  // namespace colony
