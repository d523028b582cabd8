// Simulated wheel encoders: the distance each wheel really moved (as the
// engine reports it; in kinematics2d a blocked robot's wheels only turn it),
// with slip: each distance is shortened by a fraction |N(0, slip)| that grows
// with the turn rate (treels slip most when turning), then additive noise.
#include <cmath>

#include "core/device.h"
#include "core/simulation.h"
#include "sensors/wheel_encoders/wheel_encoders.h"

namespace colony {
namespace {

struct EncoderInstance : WheelEncoders, InstanceBase {
  using Interface = WheelEncoders;
  void Set(double l, double r, double b) {
    left_ = l;
    right_ = r;
    wheel_base_ = b;
  }
};

class EncoderSystem : public SensorSystem {
 public:
  void Configure(const ConfigNode& node) override {
    noise_ = NoiseModel::Read(node);
    slip_ = node.GetDouble("slip", 0, Range::Between(0, 1));
  }
  std::vector<std::string> NeededComponents() const override {
    return {DriveState::kComponentName};
  }
  Sensor* Attach(EntityHandle robot, const RandomStream& rng) override {
    EncoderInstance& e = instances_.Add(robot, rng);
    // The wheel base is known from the start (a controller's Init reads it).
    if (const DriveState* d = sim().space().drive(robot.index)) e.Set(0, 0, d->wheel_base);
    return &e;
  }
  void Detach(Sensor* s) override { instances_.Remove(static_cast<WheelEncoders*>(s)); }
  size_t size() const override { return instances_.size(); }

  void Update(size_t begin, size_t end) override {
    const Space& space = sim().space();
    for (size_t k = begin; k < end; ++k) {
      EncoderInstance& e = instances_[k];
      if (!e.alive) continue;
      const DriveState& d = *space.drive(e.robot.index);
      double l = d.travelled_left, r = d.travelled_right;
      if (slip_ > 0) {
        // Relative turning: 0 driving straight, 1 turning on the spot.
        const double turning = std::abs(r - l) / std::max(1e-9, std::abs(r) + std::abs(l));
        const double scale = slip_ * (0.25 + turning);
        l *= 1.0 - std::min(1.0, std::abs(e.rng.Gaussian(0, scale)));
        r *= 1.0 - std::min(1.0, std::abs(e.rng.Gaussian(0, scale)));
      }
      if (noise_.enabled()) {
        l = noise_.Apply(l, e.rng);
        r = noise_.Apply(r, e.rng);
      }
      e.Set(l, r, d.wheel_base);
    }
  }

  void Hash(StateHasher& h) const override {
    for (size_t k = 0; k < instances_.size(); ++k) {
      const auto& e = instances_[k];
      if (!e.alive) continue;
      const double v[2] = {e.distance_left(), e.distance_right()};
      h.Add(v, sizeof v);
    }
  }

 private:
  NoiseModel noise_;
  double slip_ = 0;
  InstanceStore<EncoderInstance> instances_;
};

std::vector<AttributeDoc> EncoderAttributes() {
  auto a = NoiseModel::Attributes(/*with_drop=*/false);
  a.push_back({"slip", "a number in [0, 1]", "0",
               "scale of random wheel slip (distance lost), larger when turning"});
  return a;
}

COLONY_REGISTER_SENSOR(EncoderSystem, "wheel_encoders", "default",
                       "distance each wheel moved during the last tick (m), with slip and noise",
                       DeviceInterface{"sensors/wheel_encoders/wheel_encoders.h",
                                       "colony::WheelEncoders",
                                       {"distance_left(), distance_right(): how far each wheel "
                                        "moved during the last tick (m, < 0 backwards)",
                                        "wheel_base(): between the wheels (m)"}},
                       EncoderAttributes(), {"differential_steering", "footbot_encoder"});

}  // namespace
}  // namespace colony
