// Simulated hand-bot head sensor: the head joint as the physics model left
// it after the step (HandbotArmsState), with optional noise on the torque.
#include "actuators/handbot_arms/handbot_arms_state.h"
#include "core/device.h"
#include "core/noise.h"
#include "core/simulation.h"
#include "sensors/handbot_head/handbot_head.h"

namespace colony {
namespace {

struct HeadSensorInstance : HandbotHeadSensor, InstanceBase {
  using Interface = HandbotHeadSensor;
  void Set(const HandbotJoint& j, double torque) {
    rotation_ = j.position;
    velocity_ = j.velocity;
    torque_ = torque;
    stalled_ = j.stalled;
  }
};

class HandbotHeadSensorSystem : public SensorSystem {
 public:
  void Configure(const ConfigNode& node) override { noise_ = NoiseModel::Read(node); }
  std::vector<std::string> NeededComponents() const override {
    return {HandbotArmsState::kComponentName};
  }
  Sensor* Attach(EntityHandle robot, const RandomStream& rng) override {
    return &instances_.Add(robot, rng);
  }
  void Detach(Sensor* s) override { instances_.Remove(static_cast<HandbotHeadSensor*>(s)); }
  size_t size() const override { return instances_.size(); }
  void Update(size_t begin, size_t end) override {
    const Space& space = sim().space();
    for (size_t k = begin; k < end; ++k) {
      HeadSensorInstance& s = instances_[k];
      if (!s.alive) continue;
      const HandbotJoint& head = space.Get<HandbotArmsState>(s.robot.index)->head;
      s.Set(head, noise_.enabled() ? noise_.Apply(head.torque, s.rng) : head.torque);
    }
  }
  void Hash(StateHasher& h) const override {
    for (size_t k = 0; k < instances_.size(); ++k) {
      const auto& s = instances_[k];
      if (!s.alive) continue;
      const double v[4] = {s.rotation(), s.velocity(), s.torque(), s.stalled() ? 1.0 : 0.0};
      h.Add(v, sizeof v);
    }
  }

 private:
  NoiseModel noise_;
  InstanceStore<HeadSensorInstance> instances_;
};

COLONY_REGISTER_SENSOR(
    HandbotHeadSensorSystem, "handbot_head", "default",
    "the hand-bot's head: rotation (rad), speed (rad/s), motor torque (N m), stalled",
    DeviceInterface{"sensors/handbot_head/handbot_head.h",
                    "colony::HandbotHeadSensor",
                    {"rotation(): (-pi, pi] (rad)", "velocity(): rad/s",
                     "torque(): the motor's, averaged over the tick (N m)",
                     "stalled(): about its stall torque, not moving to its target"}},
    NoiseModel::Attributes(false));

}  // namespace
}  // namespace colony
