// Simulated proximity sensors: one horizontal ray per sensor, from the body's
// surface outwards, at the sensor's height, against every solid footprint in
// the space. A reading falls with the distance d to the nearest hit:
//   value = min(1, 0.01 m / d)   (1 within 1 cm, 0.1 at 10 cm, 0 beyond range)
// then noise is added and the value clamped to [0, 1].
#include "sensors/proximity/proximity.h"

#include <cmath>

#include "core/device.h"
#include "core/entity_type.h"
#include "core/geometry2d.h"
#include "core/simulation.h"

namespace colony {
namespace {

struct ProximityInstance : ProximitySensor, InstanceBase {
  using Interface = ProximitySensor;
  std::vector<Reading>& mutable_readings() { return readings_; }
  const RingMount* mount = nullptr;
  std::vector<Vec2> directions;  // unit vectors in the robot frame
};

class ProximitySystem : public SensorSystem {
 public:
  void Configure(const ConfigNode& node) override {
    range_ = node.GetDouble("range", -1, Range::Positive());
    noise_ = NoiseModel::Read(node);
  }

  Sensor* Attach(EntityHandle robot, const RandomStream& rng) override {
    const RingMount* mount = sim().MountsOf(robot).Ring("proximity");
    if (!mount) throw AttachError("it has no proximity ring");
    ProximityInstance& p = instances_.Add(robot, rng);
    p.mount = mount;
    p.mutable_readings().resize(mount->count);
    for (int i = 0; i < mount->count; ++i) {
      const double a = mount->AngleOf(i);
      p.mutable_readings()[i] = {0.0f, static_cast<float>(WrapAngle(a))};
      p.directions.emplace_back(std::cos(a), std::sin(a));
    }
    return &p;
  }
  void Detach(Sensor* s) override { instances_.Remove(static_cast<ProximitySensor*>(s)); }
  size_t size() const override { return instances_.size(); }

  void Update(size_t begin, size_t end) override {
    const Space& space = sim().space();
    static thread_local std::vector<uint32_t> near;
    for (size_t k = begin; k < end; ++k) {
      ProximityInstance& p = instances_[k];
      if (!p.alive) continue;
      const uint32_t self = p.robot.index;
      const Pose& pose = space.pose(self);
      const RingMount& m = *p.mount;
      const double range = range_ > 0 ? range_ : m.range;
      const double reach = m.radius + range;
      const Vec2 c = pose.position.head<2>();
      const double z = pose.position.z() + m.elevation;
      near.clear();
      space.Gather(c.x() - reach, c.y() - reach, c.x() + reach, c.y() + reach, near);
      // Keep the neighbours whose height spans the sensors' plane.
      size_t kept = 0;
      for (uint32_t o : near) {
        if (o == self) continue;
        const double oz = space.pose(o).position.z();
        if (z >= oz && z < oz + space.geometry(o).height()) near[kept++] = o;
      }
      near.resize(kept);
      const double yaw = YawOf(pose.orientation);
      const double cy = std::cos(yaw), sy = std::sin(yaw);
      auto& readings = p.mutable_readings();
      for (size_t i = 0; i < readings.size(); ++i) {
        const Vec2& l = p.directions[i];
        const Vec2 dir(cy * l.x() - sy * l.y(), sy * l.x() + cy * l.y());
        double best = kNoHit;
        if (!near.empty()) {
          const Vec2 origin = c + m.radius * dir;
          for (uint32_t o : near) best = std::min(best, RayFootprint(origin, dir, space.pose(o), space.geometry(o)));
        }
        double value = best <= range ? std::min(1.0, 0.01 / std::max(best, 1e-6)) : 0.0;
        if (noise_.enabled()) {
          value = noise_.Drop(p.rng) ? 0.0 : std::clamp(noise_.Apply(value, p.rng), 0.0, 1.0);
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
  double range_ = -1;
  NoiseModel noise_;
  InstanceStore<ProximityInstance> instances_;
};

std::vector<AttributeDoc> ProximityAttributes() {
  std::vector<AttributeDoc> a = {{"range", "a number > 0 (m)", "the robot's (marXbot: 0.1)",
                                  "how far from the body's surface objects are seen"}};
  for (auto& n : NoiseModel::Attributes()) a.push_back(n);
  return a;
}

COLONY_REGISTER_SENSOR(ProximitySystem, "proximity", "default",
                       "ring of IR proximity sensors: one reading per sensor in [0, 1], 0.01/d of "
                       "the distance d to the nearest object, 0 beyond range",
                       ProximityAttributes());

}  // namespace
}  // namespace colony
