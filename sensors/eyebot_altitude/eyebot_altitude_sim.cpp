// Simulated eye-bot altitude sensor: one ray straight down from the centre
// of the bottom of the body, against the floor (the arena's bottom) and the
// solid entities under the robot's axis (their footprints with their
// heights, core/geometry3d.h), within the sensor's range; then noise from
// the instance's own stream, kept within [0, range].
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/device.h"
#include "core/geometry3d.h"
#include "core/simulation.h"
#include "core/thread_pool.h"
#include "sensors/eyebot_altitude/eyebot_altitude.h"

namespace colony {
namespace {

constexpr double kNothing = std::numeric_limits<double>::infinity();

struct AltitudeInstance : EyebotAltitudeSensor, InstanceBase {
  using Interface = EyebotAltitudeSensor;
  void SetRange(double r) { range_ = r; }
  void Set(double altitude) { altitude_ = altitude; }
};

class EyebotAltitudeSystem : public SensorSystem {
 public:
  void Configure(const ConfigNode& node) override {
    range_ = node.GetDouble("range", 10.0, Range::Positive());
    noise_ = NoiseModel::Read(node);
  }
  Sensor* Attach(EntityHandle robot, const RandomStream& rng) override {
    AltitudeInstance& a = instances_.Add(robot, rng);
    a.SetRange(range_);
    return &a;
  }
  void Detach(Sensor* s) override { instances_.Remove(static_cast<EyebotAltitudeSensor*>(s)); }
  size_t size() const override { return instances_.size(); }

  void Update(size_t begin, size_t end) override {
    const Space& space = sim().space();
    const Vec3 down(0, 0, -1);
    ChunkScratch<std::vector<uint32_t>> scratch;  // this thread's list (no allocation once warm)
    std::vector<uint32_t>& near = *scratch;
    for (size_t k = begin; k < end; ++k) {
      AltitudeInstance& a = instances_[k];
      if (!a.alive) continue;
      const uint32_t self = a.robot.index;
      const Vec3& from = space.pose(self).position;
      double d = from.z() - space.arena_min().z();  // the floor
      near.clear();
      space.Gather(from.x(), from.y(), from.x(), from.y(), near);
      for (uint32_t o : near) {
        if (o == self) continue;
        d = std::min(d, RayFootprint3d(from, down, space.pose(o), space.geometry(o)));
      }
      d = std::max(d, 0.0);
      if (d > range_) {
        a.Set(kNothing);
        continue;
      }
      if (noise_.enabled()) {
        if (noise_.Drop(a.rng)) {
          a.Set(kNothing);
          continue;
        }
        d = std::clamp(noise_.Apply(d, a.rng), 0.0, range_);
      }
      a.Set(d);
    }
  }

  void Hash(StateHasher& h) const override {
    for (size_t k = 0; k < instances_.size(); ++k) {
      if (!instances_[k].alive) continue;
      const double v = instances_[k].altitude();
      h.Add(&v, sizeof v);
    }
  }

 private:
  double range_ = 10.0;
  NoiseModel noise_;
  InstanceStore<AltitudeInstance> instances_;
};

std::vector<AttributeDoc> AltitudeAttributes() {
  std::vector<AttributeDoc> a = {
      {"range", "a number > 0 (m)", "10",
       "farthest it measures; beyond, it reads +infinity (no reading)"},
  };
  for (auto& n : NoiseModel::Attributes()) {
    if (n.name == "drop_probability")
      n.summary = "probability that a reading is lost (reads +infinity)";
    a.push_back(n);
  }
  return a;
}

COLONY_REGISTER_SENSOR(
    EyebotAltitudeSystem, "eyebot_altitude", "default",
    "distance (m) from the bottom of the body down to the floor or to what is "
    "under the robot's axis (a rangefinder looking down)",
    DeviceInterface{
        "sensors/eyebot_altitude/eyebot_altitude.h",
        "colony::EyebotAltitudeSensor",
        {"altitude(): from the feet down to the floor or what is below (m); +infinity out of range",
         "range(): farthest it measures (m)"}},
    AltitudeAttributes());

}  // namespace
}  // namespace colony
