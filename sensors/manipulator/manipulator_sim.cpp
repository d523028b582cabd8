// Simulated manipulator sensor: the head's joint positions, magnet and
// holding state from the robot's ManipulatorState, and its 6 IR proximity
// sensors.
//
// The head is where the robot's physics model put it (its anchor
// ManipulatorState::kHeadAnchor: the head's centre, x axis out of the magnet
// face); its size is the marXbot's (entities/marxbot/marxbot.h): 3 cm deep,
// 5 cm wide. The IR side is the face opposite the magnet. The 6 IR sensors
// sit along that face, 5/6 cm apart, and look out fanned 15 degrees apart
// (-37.5 .. +37.5 degrees from the face's normal), horizontally, at the
// height of the head's centre. Each casts one horizontal ray against the
// footprints of the solid entities whose height span contains the ray's
// height. Once the head is tilted, the rays pitch with it: each is cast in
// 3D against the upright prisms of those footprints (their height spans);
// the floor is not seen. The robot's own body blocks a ray (with the magnet to the front
// the IR side faces the body) but is not seen; the object the magnet holds
// is ignored. As for the base's proximity ring, the reading falls with the
// distance d to the nearest hit:
//   value = min(1, 0.01 m / d) if d <= range, else 0
// then noise is added and the value clamped to [0, 1].
#include <algorithm>
#include <cmath>
#include <vector>

#include "actuators/manipulator/manipulator_state.h"
#include "core/device.h"
#include "core/geometry2d.h"
#include "core/simulation.h"
#include "core/thread_pool.h"
#include "entities/marxbot/marxbot.h"
#include "sensors/manipulator/manipulator.h"

namespace colony {
namespace {

constexpr int kIrCount = 6;
constexpr double kIrFan = M_PI / 12;  // 15 degrees between neighbouring sensors' directions
constexpr double kIrSpacing = marxbot::kHeadWidth / kIrCount;  // m between sensors along the face

// Sensor i from the IR side's right: its direction from the face's normal
// (rad) and its offset along the face, to the left (m).
constexpr double IrAngle(int i) { return (i - 0.5 * (kIrCount - 1)) * kIrFan; }
constexpr double IrOffset(int i) { return (i - 0.5 * (kIrCount - 1)) * kIrSpacing; }
// Farthest a sensor is from the IR face's centre (for culling).
constexpr double kIrReach = 0.5 * marxbot::kHeadWidth;

// Distance along the ray o + t d (d of unit length, in 3D) to the upright
// prism of a footprint between heights z0 and z1 (0 when o is inside,
// kNoHit when missed): the ray's stretch within the height span, then the
// first point of that stretch over the (convex) footprint.
double RayPrism(const Vec3& o, const Vec3& d, const Pose& pose, const Geometry& g, double z0,
                double z1) {
  double t0 = 0, t1 = kNoHit;
  if (std::abs(d.z()) < 1e-12) {
    if (o.z() < z0 || o.z() >= z1) return kNoHit;
  } else {
    const double a = (z0 - o.z()) / d.z(), b = (z1 - o.z()) / d.z();
    t0 = std::max(t0, std::min(a, b));
    t1 = std::min(t1, std::max(a, b));
    if (t0 > t1) return kNoHit;
  }
  const double horizontal = d.head<2>().norm();
  const Vec2 start = o.head<2>() + t0 * d.head<2>();
  if (horizontal < 1e-12) return CircleOverlapsFootprint(start, 1e-9, pose, g) ? t0 : kNoHit;
  const double along = RayFootprint(start, d.head<2>() / horizontal, pose, g);
  if (along == kNoHit) return kNoHit;
  const double t = t0 + along / horizontal;
  return t <= t1 ? t : kNoHit;
}

struct ManipulatorSensorInstance : ManipulatorSensor, InstanceBase {
  using Interface = ManipulatorSensor;
  void SetJoints(const ManipulatorState& m) {
    elevation_ = m.elevation;
    rotation_ = m.rotation;
    tilt_ = m.tilt;
    magnet_ = m.magnet;
    holding_ = m.holding();
  }
  std::vector<Reading>& mutable_readings() { return readings_; }
};

class ManipulatorSensorSystem : public SensorSystem {
 public:
  void Configure(const ConfigNode& node) override {
    range_ = node.GetDouble("range", 0.1, Range::Positive());
    noise_ = NoiseModel::Read(node);
  }

  std::vector<std::string> NeededComponents() const override {
    return {ManipulatorState::kComponentName};
  }

  Sensor* Attach(EntityHandle robot, const RandomStream& rng) override {
    Pose head;
    if (!sim().Anchor(robot, ManipulatorState::kHeadAnchor, head)) {
      throw AttachError(std::string("its physics model gives no '") +
                        ManipulatorState::kHeadAnchor + "' anchor");
    }
    ManipulatorSensorInstance& s = instances_.Add(robot, rng);
    for (int i = 0; i < kIrCount; ++i)
      s.mutable_readings().push_back({0.0f, static_cast<float>(IrAngle(i))});
    return &s;
  }
  void Detach(Sensor* s) override { instances_.Remove(static_cast<ManipulatorSensor*>(s)); }
  size_t size() const override { return instances_.size(); }

  // As in the proximity sensor, neighbours are first culled by height and by
  // distance from the IR face's centre (a hit within range lies at most
  // kIrReach + range from it), and the rays are cast only against what
  // survives.
  void Update(size_t begin, size_t end) override {
    const Space& space = sim().space();
    ChunkScratch<std::vector<uint32_t>> scratch;  // this thread's list (no allocation once warm)
    std::vector<uint32_t>& near = *scratch;
    near.clear();
    near.reserve(64);  // once per thread: enough for any crowd seen so far
    for (size_t k = begin; k < end; ++k) {
      ManipulatorSensorInstance& s = instances_[k];
      if (!s.alive) continue;
      const uint32_t self = s.robot.index;
      const ManipulatorState& m = *space.Get<ManipulatorState>(self);
      s.SetJoints(m);
      // Attach checked that the model gives the anchor, and a robot migrates
      // only into engines whose model simulates the manipulator.
      Pose head;
      if (!sim().Anchor(s.robot, ManipulatorState::kHeadAnchor, head)) continue;
      if (m.tilt != 0) {
        TiltedRays(space, s, m, head, near);
        continue;
      }
      // The IR face: its centre, and the directions along its normal and
      // its width, in the horizontal plane.
      const Vec3 magnet = head.orientation * Vec3::UnitX();
      const double facing = std::atan2(-magnet.y(), -magnet.x());
      const Vec2 normal(std::cos(facing), std::sin(facing)), across(-normal.y(), normal.x());
      const Vec2 face = (head.position - 0.5 * marxbot::kHeadDepth * magnet).head<2>();
      const double z = head.position.z();
      const double reach = kIrReach + range_;
      GatherAround(space, face, reach, self, m.held, near,
                   [z](double bottom, double top) { return z >= bottom && z < top; });
      auto& readings = s.mutable_readings();
      const Pose& pose = space.pose(self);
      for (int i = 0; i < kIrCount; ++i) {
        double value = 0;
        if (!near.empty()) {
          const double a = facing + IrAngle(i);
          const Vec2 dir(std::cos(a), std::sin(a));
          const Vec2 origin = face + IrOffset(i) * across;
          double best = kNoHit;
          for (uint32_t o : near)
            best = std::min(best, RayFootprint(origin, dir, space.pose(o), space.geometry(o)));
          // What lies behind the robot's own body is hidden.
          if (best <= range_ && RayFootprint(origin, dir, pose, space.geometry(self)) > best) {
            value = std::min(1.0, 0.01 / std::max(best, 1e-6));
          }
        }
        if (noise_.enabled()) {
          value = noise_.Drop(s.rng) ? 0.0 : std::clamp(noise_.Apply(value, s.rng), 0.0, 1.0);
        }
        readings[i].value = static_cast<float>(value);
      }
    }
  }

  void Hash(StateHasher& h) const override {
    for (size_t k = 0; k < instances_.size(); ++k) {
      const auto& s = instances_[k];
      if (!s.alive) continue;
      const double joints[4] = {s.elevation(), s.rotation(), s.magnet(), s.holding() ? 1.0 : 0.0};
      h.Add(joints, sizeof joints);
      // As in ManipulatorState: runs that never tilt keep their hashes.
      if (s.tilt() != 0) {
        const double tilt = s.tilt();
        h.Add(&tilt, sizeof tilt);
      }
      h.Add(s.readings().data(), s.readings().size() * sizeof(ManipulatorSensor::Reading));
    }
  }

 private:
  // Into `near`: the solid entities (not the robot `self`, not what it
  // holds) within `reach` of `face` horizontally (their footprint's bounding
  // circle) whose height span [bottom, top] passes `spans`.
  template <class Spans>
  static void GatherAround(const Space& space, const Vec2& face, double reach, uint32_t self,
                           uint32_t held, std::vector<uint32_t>& near, Spans spans) {
    near.clear();
    space.Gather(face.x() - reach, face.y() - reach, face.x() + reach, face.y() + reach, near);
    size_t kept = 0;
    for (uint32_t o : near) {
      if (o == self || o == held) continue;
      const Vec3& op = space.pose(o).position;
      const Geometry& og = space.geometry(o);
      if (!spans(op.z(), op.z() + og.height())) continue;
      const double limit = reach + og.BoundingRadius() + 1e-6;
      if ((op.head<2>() - face).squaredNorm() >= limit * limit) continue;
      near[kept++] = o;
    }
    near.resize(kept);
  }

  // The 6 rays of a tilted head, in 3D: from the IR face (its normal the
  // head's -x axis, the sensors along its -y axis) fanned about that normal
  // in the face's plane, against the prisms of the solid footprints near
  // the face whose height spans the rays can reach.
  void TiltedRays(const Space& space, ManipulatorSensorInstance& s, const ManipulatorState& m,
                  const Pose& head, std::vector<uint32_t>& near) const {
    const uint32_t self = s.robot.index;
    const Vec3 normal = head.orientation * -Vec3::UnitX();
    const Vec3 across = head.orientation * -Vec3::UnitY();
    const Vec3 face = head.position + 0.5 * marxbot::kHeadDepth * normal;
    const double reach = kIrReach + range_;
    GatherAround(space, face.head<2>(), reach, self, m.held, near,
                 [&face, reach](double bottom, double top) {
                   return !(bottom > face.z() + reach || top < face.z() - reach);
                 });
    const Pose& pose = space.pose(self);
    const Geometry& body = space.geometry(self);
    auto& readings = s.mutable_readings();
    for (int i = 0; i < kIrCount; ++i) {
      double value = 0;
      if (!near.empty()) {
        const Vec3 dir = std::cos(IrAngle(i)) * normal + std::sin(IrAngle(i)) * across;
        const Vec3 origin = face + IrOffset(i) * across;
        double best = kNoHit;
        for (uint32_t o : near) {
          const Pose& op = space.pose(o);
          const double bottom = op.position.z(), top = bottom + space.geometry(o).height();
          best = std::min(best, RayPrism(origin, dir, op, space.geometry(o), bottom, top));
        }
        // What lies behind the robot's own body is hidden.
        if (best <= range_ && RayPrism(origin, dir, pose, body, pose.position.z(),
                                       pose.position.z() + body.height()) > best) {
          value = std::min(1.0, 0.01 / std::max(best, 1e-6));
        }
      }
      if (noise_.enabled()) {
        value = noise_.Drop(s.rng) ? 0.0 : std::clamp(noise_.Apply(value, s.rng), 0.0, 1.0);
      }
      readings[i].value = static_cast<float>(value);
    }
  }

  double range_ = 0.1;
  NoiseModel noise_;
  InstanceStore<ManipulatorSensorInstance> instances_;
};

std::vector<AttributeDoc> ManipulatorSensorAttributes() {
  std::vector<AttributeDoc> a = {
      {"range", "a number > 0 (m)", "0.1", "how far from the head's IR side objects are seen"}};
  for (auto& n : NoiseModel::Attributes()) a.push_back(n);
  return a;
}

COLONY_REGISTER_SENSOR(
    ManipulatorSensorSystem, "manipulator", "default",
    "the construction manipulator's head elevation (m) and rotation (rad), its magnet "
    "(0..1, engaged), whether it holds something, and the 6 IR proximity sensors of the "
    "head's IR side (0.01/d, 0 beyond range)",
    DeviceInterface{"sensors/manipulator/manipulator.h",
                    "colony::ManipulatorSensor",
                    {"elevation(): the magnet's centre above the floor (m)",
                     "rotation(): the head, ccw from magnet side to the front, (-pi, pi] (rad)",
                     "tilt(): the head's pitch, 0 upright, > 0 magnet face down (rad)",
                     "magnet(): 0 disengaged .. 1 engaged; magnet_engaged(): fully engaged",
                     "holding(): the magnet holds an object",
                     "readings(): the 6 IR sensors of the IR side, right to left, each: value (0 "
                     "nothing .. 1 touching), angle (rad, from the IR side's facing direction)"}},
    ManipulatorSensorAttributes());

}  // namespace
}  // namespace colony
