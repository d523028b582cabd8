// Simulated ground sensors: the floor's grey level (colour or PNG image)
// under each sensor, plus noise, clamped to [0, 1].
#include <algorithm>
#include <cmath>

#include "core/device.h"
#include "core/simulation.h"
#include "sensors/ground/ground.h"

namespace colony {
namespace {

struct GroundInstance : GroundSensor, InstanceBase {
  using Interface = GroundSensor;
  std::vector<Reading>& mutable_readings() { return readings_; }
  std::vector<Vec2> offsets;  // sensor positions in the robot frame (m)
};

class GroundSystem : public SensorSystem {
 public:
  void Configure(const ConfigNode& node) override { noise_ = NoiseModel::Read(node); }

  Sensor* Attach(EntityHandle robot, const RandomStream& rng) override {
    const RingMount* mount = sim().MountsOf(robot).Ring("ground");
    if (!mount) throw AttachError("it has no ground sensors");
    GroundInstance& g = instances_.Add(robot, rng);
    for (int i = 0; i < mount->count; ++i) {
      const double a = mount->AngleOf(i);
      g.mutable_readings().push_back({0.0f, static_cast<float>(WrapAngle(a))});
      g.offsets.emplace_back(mount->radius * std::cos(a), mount->radius * std::sin(a));
    }
    return &g;
  }
  void Detach(Sensor* s) override { instances_.Remove(static_cast<GroundSensor*>(s)); }
  size_t size() const override { return instances_.size(); }

  void Update(size_t begin, size_t end) override {
    const Space& space = sim().space();
    const Floor& floor = space.floor();
    for (size_t k = begin; k < end; ++k) {
      GroundInstance& g = instances_[k];
      if (!g.alive) continue;
      const Pose& pose = space.pose(g.robot.index);
      const double yaw = YawOf(pose.orientation);
      const double c = std::cos(yaw), s = std::sin(yaw);
      auto& readings = g.mutable_readings();
      for (size_t i = 0; i < readings.size(); ++i) {
        const Vec2& o = g.offsets[i];
        const double x = pose.position.x() + c * o.x() - s * o.y();
        const double y = pose.position.y() + s * o.x() + c * o.y();
        double value = floor.GreyAt(x, y);
        if (noise_.enabled()) {
          value = noise_.Drop(g.rng) ? 0.0 : std::clamp(noise_.Apply(value, g.rng), 0.0, 1.0);
        }
        readings[i].value = static_cast<float>(value);
      }
    }
  }

  void Hash(StateHasher& h) const override {
    for (size_t k = 0; k < instances_.size(); ++k) {
      const auto& r = instances_[k].readings();
      if (instances_[k].alive) h.Add(r.data(), r.size() * sizeof(r[0]));
    }
  }

 private:
  NoiseModel noise_;
  InstanceStore<GroundInstance> instances_;
};

COLONY_REGISTER_SENSOR(GroundSystem, "ground", "default",
                       "downward sensors reading the floor's grey level (0 black .. 1 white) under each sensor",
                       NoiseModel::Attributes());

}  // namespace
}  // namespace colony
