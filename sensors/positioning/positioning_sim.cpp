// Simulated positioning: the robot's pose from the space; position noise on
// each axis and angle noise on the heading.
#include "core/device.h"
#include "core/simulation.h"
#include "sensors/positioning/positioning.h"

namespace colony {
namespace {

struct PositioningInstance : PositioningSensor, InstanceBase {
  using Interface = PositioningSensor;
  void Set(double x, double y, double z, double yaw) {
    x_ = x;
    y_ = y;
    z_ = z;
    yaw_ = yaw;
  }
};

class PositioningSystem : public SensorSystem {
 public:
  void Configure(const ConfigNode& node) override {
    noise_ = NoiseModel::Read(node);
    angle_std_dev_ = node.GetDouble("angle_noise_std_dev", 0, Range::NonNegative());
  }
  Sensor* Attach(EntityHandle robot, const RandomStream& rng) override {
    return &instances_.Add(robot, rng);
  }
  void Detach(Sensor* s) override { instances_.Remove(static_cast<PositioningSensor*>(s)); }
  size_t size() const override { return instances_.size(); }

  void Update(size_t begin, size_t end) override {
    const Space& space = sim().space();
    for (size_t k = begin; k < end; ++k) {
      PositioningInstance& p = instances_[k];
      if (!p.alive) continue;
      const Pose& pose = space.pose(p.robot.index);
      double x = pose.position.x(), y = pose.position.y(), z = pose.position.z();
      double yaw = YawOf(pose.orientation);
      if (noise_.enabled()) {
        x = noise_.Apply(x, p.rng);
        y = noise_.Apply(y, p.rng);
        z = noise_.Apply(z, p.rng);
      }
      if (angle_std_dev_ > 0) yaw = WrapAngle(p.rng.Gaussian(yaw, angle_std_dev_));
      p.Set(x, y, z, yaw);
    }
  }

  void Hash(StateHasher& h) const override {
    for (size_t k = 0; k < instances_.size(); ++k) {
      const auto& p = instances_[k];
      if (!p.alive) continue;
      const double v[4] = {p.x(), p.y(), p.z(), p.yaw()};
      h.Add(v, sizeof v);
    }
  }

 private:
  NoiseModel noise_;
  double angle_std_dev_ = 0;
  InstanceStore<PositioningInstance> instances_;
};

std::vector<AttributeDoc> PositioningAttributes() {
  auto a = NoiseModel::Attributes(/*with_drop=*/false);
  a.push_back({"angle_noise_std_dev", "a number >= 0 (rad)", "0", "gaussian noise on the heading"});
  return a;
}

COLONY_REGISTER_SENSOR(
    PositioningSystem, "positioning", "default",
    "the robot's position (m) and heading (rad) in the arena, with optional noise",
    DeviceInterface{"sensors/positioning/positioning.h",
                    "colony::PositioningSensor",
                    {"x(), y(), z(): the robot's position in the arena (m)",
                     "yaw(): heading, ccw from +x, (-pi, pi] (rad)"}},
    PositioningAttributes());

}  // namespace
}  // namespace colony
