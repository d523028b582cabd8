// Simulated ground sensors: the floor's grey level (colour or PNG image)
// under each sensor, plus noise, clamped to [0, 1]. Over a ditch the IR
// reflection is lost and the sensor reads 0 ("no ground"), unless a surface
// lies within kSurfaceGap of the sensor's height (the robot's base): the top
// of something solid in the ditch (cubes filling it into a bridge) or, for a
// robot down in the ditch, its bottom. Then it reads that surface's grey.
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/device.h"
#include "core/geometry2d.h"
#include "core/simulation.h"
#include "core/thread_pool.h"
#include "sensors/ground/ground.h"

namespace colony {
namespace {

// How far a surface may be above or below the sensor and still reflect (m).
constexpr double kSurfaceGap = 0.01;

// What the sensor at (x, y), at height z, of robot `self` reads over ditch
// `d`: the grey of the highest surface at most kSurfaceGap above z, if it is
// at most kSurfaceGap below z; else 0. `near` is scratch.
double GreyOverDitch(const Space& space, const Ditch& d, double x, double y, double z,
                     uint32_t self, std::vector<uint32_t>& near) {
  const double floor_z = space.arena_min().z();
  double top = floor_z - d.depth;  // the ditch's bottom
  double grey = space.floor().GreyAt(x, y);
  near.clear();
  space.Gather(x, y, x, y, near);
  const Vec2 p(x, y);
  for (uint32_t o : near) {
    if (o == self) continue;
    const Pose& pose = space.pose(o);
    const Geometry& g = space.geometry(o);
    const double o_top = pose.position.z() + g.height();
    if (o_top <= top || o_top > z + kSurfaceGap) continue;
    if (!CircleOverlapsFootprint(p, 1e-9, pose, g)) continue;
    top = o_top;
    grey = space.color(o).Grey();
  }
  return top >= z - kSurfaceGap ? grey : 0.0;
}

struct GroundInstance : GroundSensor, InstanceBase {
  using Interface = GroundSensor;
  std::vector<Reading>& mutable_readings() { return readings_; }
  std::vector<Vec2> offsets;  // sensor positions in the robot frame (m), on a ring
};

// Whether a ditch comes within `reach` of (x, y) (a cheap test per robot,
// before testing each sensor).
bool NearDitch(const Floor& floor, double x, double y, double reach) {
  for (const Ditch& d : floor.ditches()) {
    if (x > d.min_x - reach && x < d.max_x + reach && y > d.min_y - reach && y < d.max_y + reach)
      return true;
  }
  return false;
}

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

  // Ditches are looked for only on floors that have some, and only for
  // robots next to one: everywhere else the loop is the flat floor's.
  void Update(size_t begin, size_t end) override {
    if (sim().space().floor().ditches().empty()) {
      UpdateRange<false>(begin, end);
    } else {
      UpdateRange<true>(begin, end);
    }
  }

  void Hash(StateHasher& h) const override {
    for (size_t k = 0; k < instances_.size(); ++k) {
      const auto& r = instances_[k].readings();
      if (instances_[k].alive) h.Add(r.data(), r.size() * sizeof(r[0]));
    }
  }

 private:
  // Not inlined: each variant is compiled on its own, so the flat floor's
  // is exactly the loop it was before ditches existed.
  template <bool kDitches>
  [[gnu::noinline]] void UpdateRange(size_t begin, size_t end) {
    const Space& space = sim().space();
    const Floor& floor = space.floor();
    ChunkScratch<std::vector<uint32_t>> scratch;  // this thread's list (no allocation once warm)
    std::vector<uint32_t>& near = *scratch;
    near.clear();
    near.reserve(64);  // once per thread: enough for any crowd seen so far
    for (size_t k = begin; k < end; ++k) {
      GroundInstance& g = instances_[k];
      if (!g.alive) continue;
      const Pose& pose = space.pose(g.robot.index);
      const double yaw = YawOf(pose.orientation);
      const double c = std::cos(yaw), s = std::sin(yaw);
      if constexpr (kDitches) {
        if (NearDitch(floor, pose.position.x(), pose.position.y(),
                      g.offsets.empty() ? 0 : g.offsets[0].norm())) {
          ReadNearDitch(g, pose, c, s, near);
          continue;
        }
      }
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

  // The readings of a robot with a ditch within reach of its sensors (c, s:
  // cosine and sine of its yaw).
  [[gnu::noinline]] void ReadNearDitch(GroundInstance& g, const Pose& pose, double c, double s,
                                       std::vector<uint32_t>& near) {
    const Space& space = sim().space();
    const Floor& floor = space.floor();
    auto& readings = g.mutable_readings();
    for (size_t i = 0; i < readings.size(); ++i) {
      const Vec2& o = g.offsets[i];
      const double x = pose.position.x() + c * o.x() - s * o.y();
      const double y = pose.position.y() + s * o.x() + c * o.y();
      const Ditch* ditch = floor.DitchAt(x, y);
      double value =
          ditch ? GreyOverDitch(space, *ditch, x, y, pose.position.z(), g.robot.index, near)
                : floor.GreyAt(x, y);
      if (noise_.enabled()) {
        value = noise_.Drop(g.rng) ? 0.0 : std::clamp(noise_.Apply(value, g.rng), 0.0, 1.0);
      }
      readings[i].value = static_cast<float>(value);
    }
  }

  NoiseModel noise_;
  InstanceStore<GroundInstance> instances_;
};

COLONY_REGISTER_SENSOR(
    GroundSystem, "ground", "default",
    "downward sensors reading the floor's grey level (0 black .. 1 white) under each sensor; "
    "0 over a ditch unless something fills it up to the floor",
    DeviceInterface{"sensors/ground/ground.h",
                    "colony::GroundSensor",
                    {"readings(): one per sensor, each: value (grey level, 0 black .. 1 white; 0 "
                     "over a hole), angle (rad, the sensor's direction from the centre)"}},
    NoiseModel::Attributes(), {"footbot_base_ground", "footbot_motor_ground"});

}  // namespace
}  // namespace colony
