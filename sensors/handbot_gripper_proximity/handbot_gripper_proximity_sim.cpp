// Simulated hand-bot gripper proximity sensor. Each gripper's sensors sit at
// the middle of its tip, where the physics model put it (anchors
// gripper_left, gripper_right: x out of the claws), and look out in a cone
// around the gripper's axis. Each casts one ray of `range` (12 cm) against
// the 3D footprints of the solid entities near it (core/geometry3d.h), the
// floor and the ceiling; the hand-bot itself and what that gripper holds are
// not seen. The reading falls with the distance d to the nearest hit, as for
// the base's proximity ring:
//   value = min(1, 0.01 m / d) if d <= range, else 0
// then noise is added and the value clamped to [0, 1].
//
// Layouts (implementation=): "default", 12 sensors on a cone 30 degrees
// about the axis, 30 degrees apart around it; "simple", 3 sensors: one on
// the axis and two 30 degrees to either side in the gripper's xy plane;
// "full", 24 sensors: 12 at 20 and 12 at 50 degrees, offset by 15 degrees.
// The sources give the counts and the range, not the directions: those are
// our choice.
#include <algorithm>
#include <cmath>
#include <vector>

#include "actuators/handbot_arms/handbot_arms_state.h"
#include "core/device.h"
#include "core/geometry3d.h"
#include "core/noise.h"
#include "core/simulation.h"
#include "core/thread_pool.h"
#include "sensors/handbot_gripper_proximity/handbot_gripper_proximity.h"

namespace colony {
namespace {

constexpr const char* kAnchors[2] = {"gripper_left", "gripper_right"};

struct Direction {
  double around, tilt;
  Vec3 Local() const {  // in the gripper's frame, x its axis
    return Vec3(std::cos(tilt), std::sin(tilt) * std::cos(around),
                std::sin(tilt) * std::sin(around));
  }
};

std::vector<Direction> Layout(int count) {
  std::vector<Direction> out;
  if (count == 3) return {{0, 0}, {0, M_PI / 6}, {M_PI, M_PI / 6}};
  const auto ring = [&](int n, double tilt, double offset) {
    for (int i = 0; i < n; ++i) out.push_back({offset + 2 * M_PI * i / n, tilt});
  };
  if (count == 12) ring(12, M_PI / 6, 0);
  if (count == 24) {
    ring(12, M_PI / 9, 0);
    ring(12, 5 * M_PI / 18, M_PI / 12);
  }
  return out;
}

struct GripperIrInstance : HandbotGripperProximitySensor, InstanceBase {
  using Interface = HandbotGripperProximitySensor;
  std::vector<Reading>& mutable_readings(int g) { return readings_[g]; }
};

template <int kCount>
class GripperIrSystem : public SensorSystem {
 public:
  void Configure(const ConfigNode& node) override {
    range_ = node.GetDouble("range", 0.12, Range::Positive());
    noise_ = NoiseModel::Read(node);
  }
  std::vector<std::string> NeededComponents() const override {
    return {HandbotArmsState::kComponentName};
  }

  Sensor* Attach(EntityHandle robot, const RandomStream& rng) override {
    Pose pose;
    for (const char* anchor : kAnchors) {
      if (!sim().Anchor(robot, anchor, pose)) {
        throw AttachError(std::string("its physics model gives no '") + anchor + "' anchor");
      }
    }
    GripperIrInstance& s = instances_.Add(robot, rng);
    for (int g = 0; g < 2; ++g) {
      for (const Direction& d : layout_) {
        s.mutable_readings(g).push_back(
            {0.0f, static_cast<float>(d.around), static_cast<float>(d.tilt)});
      }
    }
    return &s;
  }
  void Detach(Sensor* s) override {
    instances_.Remove(static_cast<HandbotGripperProximitySensor*>(s));
  }
  size_t size() const override { return instances_.size(); }

  void Update(size_t begin, size_t end) override {
    const Space& space = sim().space();
    const double floor_z = space.arena_min().z();
    ChunkScratch<std::vector<uint32_t>> scratch;  // this thread's list (no allocation once warm)
    std::vector<uint32_t>& near = *scratch;
    near.clear();
    near.reserve(64);  // once per thread: enough for any crowd seen so far
    for (size_t k = begin; k < end; ++k) {
      GripperIrInstance& s = instances_[k];
      if (!s.alive) continue;
      const uint32_t self = s.robot.index;
      const HandbotArmsState& arms = *space.Get<HandbotArmsState>(self);
      for (int g = 0; g < 2; ++g) {
        Pose tip;
        // Attach checked the anchors; a robot migrates only into engines whose
        // model simulates the arms.
        if (!sim().Anchor(s.robot, kAnchors[g], tip)) continue;
        const Vec3& o = tip.position;
        near.clear();
        space.Gather(o.x() - range_, o.y() - range_, o.x() + range_, o.y() + range_, near);
        size_t kept = 0;
        for (uint32_t e : near) {
          if (e == self || e == arms.claws[g].held) continue;
          const Vec3& p = space.pose(e).position;
          const Geometry& eg = space.geometry(e);
          const double limit = range_ + eg.BoundingRadius() + 1e-6;
          if ((p.head<2>() - o.head<2>()).squaredNorm() >= limit * limit) continue;
          if (o.z() + range_ < p.z() || o.z() - range_ > p.z() + eg.height()) continue;
          near[kept++] = e;
        }
        near.resize(kept);
        auto& readings = s.mutable_readings(g);
        for (size_t i = 0; i < layout_.size(); ++i) {
          const Vec3 d = tip.orientation * layout_[i].Local();
          double best = std::min(RayPlaneZ(o, d, floor_z),
                                 space.ceiling() ? RayPlaneZ(o, d, space.ceiling()->z) : kNoHit);
          for (uint32_t e : near)
            best = std::min(best, RayFootprint3d(o, d, space.pose(e), space.geometry(e)));
          double value = best <= range_ ? std::min(1.0, 0.01 / std::max(best, 1e-6)) : 0.0;
          if (noise_.enabled()) {
            value = noise_.Drop(s.rng) ? 0.0 : std::clamp(noise_.Apply(value, s.rng), 0.0, 1.0);
          }
          readings[i].value = static_cast<float>(value);
        }
      }
    }
  }

  void Hash(StateHasher& h) const override {
    for (size_t k = 0; k < instances_.size(); ++k) {
      const auto& s = instances_[k];
      if (!s.alive) continue;
      for (int g = 0; g < 2; ++g)
        h.Add(s.readings(g).data(), s.readings(g).size() * sizeof(Reading));
    }
  }

 private:
  using Reading = HandbotGripperProximitySensor::Reading;
  const std::vector<Direction> layout_ = Layout(kCount);
  double range_ = 0.12;
  NoiseModel noise_;
  InstanceStore<GripperIrInstance> instances_;
};

std::vector<AttributeDoc> Attributes() {
  std::vector<AttributeDoc> a = {{"range", "a number > 0 (m)", "0.12", "how far the sensors see"}};
  const auto noise = NoiseModel::Attributes();
  a.insert(a.end(), noise.begin(), noise.end());
  return a;
}

using Default = GripperIrSystem<12>;
using Simple = GripperIrSystem<3>;
using Full = GripperIrSystem<24>;

// What a controller sees of this sensor, whichever implementation.
DeviceInterface ControlInterface() {
  return {"sensors/handbot_gripper_proximity/handbot_gripper_proximity.h",
          "colony::HandbotGripperProximitySensor",
          {"readings(gripper): gripper kLeft or kRight, one reading per sensor, each: value (0 "
           "nothing .. 1 within 1 cm), around (rad, about the gripper's axis), tilt (rad, from the "
           "gripper's axis)"}};
}

COLONY_REGISTER_SENSOR(
    Default, "handbot_gripper_proximity", "default",
    "the hand-bot's gripper IR sensors: 12 per gripper in a cone around its axis, 12 cm",
    ControlInterface(), Attributes());
COLONY_REGISTER_SENSOR(
    Simple, "handbot_gripper_proximity", "simple",
    "the hand-bot's gripper IR sensors: 3 per gripper (on the axis and 30 degrees either side)",
    ControlInterface(), Attributes());
COLONY_REGISTER_SENSOR(
    Full, "handbot_gripper_proximity", "full",
    "the hand-bot's gripper IR sensors: 24 per gripper on two cones (20 and 50 degrees)",
    ControlInterface(), Attributes());

}  // namespace
}  // namespace colony
