// Simulated rope traction sensor: copies the robot's RopeState (status,
// length, tension, stall) as its physics model left it after the step, with
// optional noise on the traction (never below 0).
#include <algorithm>

#include "actuators/rope_launcher/rope_state.h"
#include "core/device.h"
#include "core/noise.h"
#include "core/simulation.h"
#include "sensors/rope_traction/rope_traction.h"

namespace colony {
namespace {

struct RopeTractionInstance : RopeTractionSensor, InstanceBase {
  using Interface = RopeTractionSensor;
  void Set(const RopeState& rope, double traction) {
    switch (rope.status) {
      case RopeState::Status::kStowed:
        status_ = Status::kStowed;
        break;
      case RopeState::Status::kAttached:
        status_ = Status::kAttached;
        break;
      case RopeState::Status::kFailed:
        status_ = Status::kLaunchFailed;
        break;
    }
    length_ = rope.length;
    traction_ = traction;
    stalled_ = rope.stalled;
  }
};

class RopeTractionSystem : public SensorSystem {
 public:
  void Configure(const ConfigNode& node) override { noise_ = NoiseModel::Read(node); }
  std::vector<std::string> NeededComponents() const override { return {RopeState::kComponentName}; }
  Sensor* Attach(EntityHandle robot, const RandomStream& rng) override {
    return &instances_.Add(robot, rng);
  }
  void Detach(Sensor* s) override { instances_.Remove(static_cast<RopeTractionSensor*>(s)); }
  size_t size() const override { return instances_.size(); }

  void Update(size_t begin, size_t end) override {
    const Space& space = sim().space();
    for (size_t k = begin; k < end; ++k) {
      RopeTractionInstance& s = instances_[k];
      if (!s.alive) continue;
      const RopeState& rope = *space.Get<RopeState>(s.robot.index);
      double traction = rope.tension;
      if (rope.attached() && noise_.enabled()) {
        traction = noise_.Drop(s.rng) ? 0.0 : noise_.ApplyNonNegative(traction, s.rng);
      }
      s.Set(rope, traction);
    }
  }

  void Hash(StateHasher& h) const override {
    for (size_t k = 0; k < instances_.size(); ++k) {
      const auto& s = instances_[k];
      if (!s.alive) continue;
      const double v[4] = {static_cast<double>(s.status()), s.length(), s.traction(),
                           s.stalled() ? 1.0 : 0.0};
      h.Add(v, sizeof v);
    }
  }

 private:
  NoiseModel noise_;
  InstanceStore<RopeTractionInstance> instances_;
};

COLONY_REGISTER_SENSOR(
    RopeTractionSystem, "rope_traction", "default",
    "the hand-bot's rope: stowed / attached / launch failed, length (m), traction (N), "
    "motor stalled (needs an engine that simulates the rope: dynamics3d)",
    DeviceInterface{
        "sensors/rope_traction/rope_traction.h",
        "colony::RopeTractionSensor",
        {"status(): kStowed, kAttached or kLaunchFailed; attached(), launch_failed()",
         "length(): from the magnet to the launcher (m, 0 unless attached)",
         "traction(): the rope's pull on the robot (N)",
         "stalled(): climbing, the motor pulls its most and the rope does not shorten"}},
    NoiseModel::Attributes());

}  // namespace
}  // namespace colony
