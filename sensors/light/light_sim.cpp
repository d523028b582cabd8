// Simulated light sensors: every light entity in the space contributes to the
// sensors that face it. For a light of intensity I at distance d (m, 3D, from
// the robot's axis at the ring's height) and horizontal bearing b in the
// robot's frame, sensor i (facing a_i) gains
//   I / (1 + d^2) * cos(b - a_i)      when |b - a_i| < 90 degrees, else 0,
// summed over the lights it sees, then noise is added and the value clamped to
// [0, 1]. A light hidden behind a solid body (checked along the straight
// line from the ring to the light) contributes nothing.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <deque>
#include <limits>
#include <mutex>
#include <utility>
#include <vector>

#include "core/device.h"
#include "core/entity_type.h"
#include "core/geometry2d.h"
#include "core/simulation.h"
#include "core/thread_pool.h"
#include "sensors/light/light.h"

namespace colony {
namespace {

struct LightInstance : LightSensor, InstanceBase {
  using Interface = LightSensor;
  std::vector<Reading>& mutable_readings() { return readings_; }
  const RingMount* mount = nullptr;
  // Unit vectors of the sensors in the robot frame (owned by the system,
  // shared by every robot with the same ring).
  const Vec2* directions = nullptr;
};

// What every robot's update needs from the space, gathered once per tick:
// the lights (few, not solid, so not in the spatial index), and the heights
// above which fewer bodies can hide a light: above max_top none; above
// max_movable_top only the fixed bodies listed in `tall` (walls, pillars).
struct LightScene {
  struct Light {
    Vec3 position;
    double intensity;
  };
  std::vector<Light> lights;
  double max_top = 0;
  double max_movable_top = 0;
  std::vector<uint32_t> tall;  // fixed solid bodies whose top is above max_movable_top
};

// Beyond this many tall fixed bodies, lines are walked through the grid up to
// max_top instead of testing each of them.
constexpr size_t kMaxTallTestedDirectly = 64;

class LightSystem : public SensorSystem {
 public:
  void Configure(const ConfigNode& node) override {
    check_occlusions_ = node.GetBool("check_occlusions", true);
    noise_ = NoiseModel::Read(node);
  }

  Sensor* Attach(EntityHandle robot, const RandomStream& rng) override {
    const RingMount* mount = sim().MountsOf(robot).Ring("light");
    if (!mount) throw AttachError("it has no light sensor ring");
    LightInstance& s = instances_.Add(robot, rng);
    s.mount = mount;
    s.mutable_readings().resize(mount->count);
    for (int i = 0; i < mount->count; ++i) {
      s.mutable_readings()[i] = {0.0f, static_cast<float>(WrapAngle(mount->AngleOf(i)))};
    }
    s.directions = directions_.Of(*mount);
    return &s;
  }
  void Detach(Sensor* s) override { instances_.Remove(static_cast<LightSensor*>(s)); }
  size_t size() const override { return instances_.size(); }

  void Update(size_t begin, size_t end) override {
    const Space& space = sim().space();
    const LightScene& scene = SceneOfThisTick();
    ChunkScratch<std::vector<uint32_t>> scratch;  // this thread's list (no allocation once warm)
    std::vector<uint32_t>& near = *scratch;
    near.clear();
    near.reserve(64);  // once per thread: enough for any crowd seen so far
    for (size_t k = begin; k < end; ++k) {
      LightInstance& s = instances_[k];
      if (!s.alive) continue;
      const uint32_t self = s.robot.index;
      const Pose& pose = space.pose(self);
      const Vec3 from(pose.position.x(), pose.position.y(), pose.position.z() + s.mount->elevation);
      const double yaw = YawOf(pose.orientation);
      const double cy = std::cos(yaw), sy = std::sin(yaw);
      auto& readings = s.mutable_readings();
      for (auto& r : readings) r.value = 0.0f;
      for (const LightScene::Light& light : scene.lights) {
        const Vec3 v = light.position - from;
        const double horizontal = std::hypot(v.x(), v.y());
        // A light straight above faces no sensor of a horizontal ring.
        if (horizontal < 1e-9) continue;
        if (check_occlusions_ && Occluded(space, self, from, light.position, scene, near)) continue;
        const double strength = light.intensity / (1.0 + v.squaredNorm());
        // The light's horizontal direction in the robot's frame.
        const double lx = (cy * v.x() + sy * v.y()) / horizontal;
        const double ly = (-sy * v.x() + cy * v.y()) / horizontal;
        for (size_t i = 0; i < readings.size(); ++i) {
          const double c = s.directions[i].x() * lx + s.directions[i].y() * ly;
          if (c > 0) readings[i].value += static_cast<float>(strength * c);
        }
      }
      for (auto& r : readings) r.value = static_cast<float>(Noisy(r.value, s.rng));
    }
  }

  void Hash(StateHasher& h) const override {
    for (size_t k = 0; k < instances_.size(); ++k) {
      const auto& r = instances_[k].readings();
      if (instances_[k].alive) h.Add(r.data(), r.size() * sizeof(r[0]));
    }
  }

 private:
  double Noisy(double value, RandomStream& rng) const {
    if (noise_.enabled()) {
      if (noise_.Drop(rng)) return 0.0;
      value = noise_.Apply(value, rng);
    }
    return std::clamp(value, 0.0, 1.0);
  }

  // The lights and the tallest solid top as of this tick. Built by whichever
  // chunk comes first (under a lock); the result is the same whoever builds it.
  const LightScene& SceneOfThisTick() {
    const uint64_t tick = sim().tick();
    if (scene_tick_.load(std::memory_order_acquire) != tick) {
      std::lock_guard lock(scene_mutex_);
      if (scene_tick_.load(std::memory_order_relaxed) != tick) {
        const Space& space = sim().space();
        scene_.lights.clear();
        scene_.tall.clear();
        scene_.max_top = scene_.max_movable_top = -std::numeric_limits<double>::infinity();
        auto top = [&](uint32_t i) {
          return space.pose(i).position.z() + space.geometry(i).height();
        };
        for (uint32_t i = 0; i < space.slots(); ++i) {
          if (!space.alive(i)) continue;
          if (const LightSource* light = space.light(i)) {
            scene_.lights.push_back({space.pose(i).position, light->intensity});
          }
          if (!(space.flags(i) & kSolid)) continue;
          scene_.max_top = std::max(scene_.max_top, top(i));
          if (space.movable(i)) scene_.max_movable_top = std::max(scene_.max_movable_top, top(i));
        }
        for (uint32_t i = 0; i < space.slots(); ++i) {
          if (space.alive(i) && (space.flags(i) & kSolid) && !space.movable(i) &&
              top(i) > scene_.max_movable_top) {
            scene_.tall.push_back(i);
          }
        }
        scene_tick_.store(tick, std::memory_order_release);
      }
    }
    return scene_;
  }

  // Whether a solid body other than the robot itself cuts the straight line
  // from `from` to `to`. Where the line is low enough for any body to cut it
  // (below the tallest movable body; below the tallest body if there are many
  // tall fixed ones), it is walked in pieces one grid cell long and each
  // piece's neighbours are gathered from the spatial index, so a check costs
  // what lies along the line and stops at the first body found. Higher up,
  // only the few tall fixed bodies can cut it: they are tested directly.
  bool Occluded(const Space& space, uint32_t self, const Vec3& from, const Vec3& to,
                const LightScene& scene, std::vector<uint32_t>& near) const {
    const Vec2 a = from.head<2>(), b = to.head<2>();
    const double length = (b - a).norm();
    const Vec2 u = (b - a) / length;
    const double z0 = from.z(), z1 = to.z();
    auto z_at = [&](double t) { return z0 + (z1 - z0) * t / length; };
    // Whether body o cuts the line: where the line enters and leaves its
    // footprint, the line's height range must meet the body's.
    auto cuts = [&](uint32_t o) {
      const Pose& op = space.pose(o);
      const Geometry& og = space.geometry(o);
      // Cheap rejection by the bounding circle.
      const Vec2 q = op.position.head<2>() - a;
      const double along = q.dot(u);
      const double across = std::abs(q.x() * u.y() - q.y() * u.x());
      const double r = og.BoundingRadius();
      if (across >= r || along <= -r || along >= length + r) return false;
      const double t_in = RayFootprint(a, u, op, og);
      if (t_in >= length) return false;
      const double back = RayFootprint(b, -u, op, og);
      const double t_out = back == kNoHit ? t_in : length - back;
      const double z_in = z_at(t_in), z_out = z_at(t_out);
      const double bottom = op.position.z(), top = bottom + og.height();
      return std::max(z_in, z_out) > bottom && std::min(z_in, z_out) < top;
    };
    const bool direct = scene.tall.size() <= kMaxTallTestedDirectly;
    if (direct) {
      for (uint32_t o : scene.tall) {
        if (o != self && cuts(o)) return true;
      }
    }
    // The stretch [lo, hi] of the line below `ceiling`, walked through the grid.
    const double ceiling = direct ? scene.max_movable_top : scene.max_top;
    if (z0 >= ceiling && z1 >= ceiling) return false;
    double lo = 0, hi = length;
    if (z1 > ceiling) hi = length * (ceiling - z0) / (z1 - z0);
    if (z0 > ceiling) lo = length * (z0 - ceiling) / (z0 - z1);
    const double step = space.cell_size();
    for (double s0 = lo; s0 < hi; s0 += step) {
      const Vec2 p0 = a + s0 * u, p1 = a + std::min(s0 + step, hi) * u;
      near.clear();
      space.Gather(std::min(p0.x(), p1.x()), std::min(p0.y(), p1.y()), std::max(p0.x(), p1.x()),
                   std::max(p0.y(), p1.y()), near);
      for (uint32_t o : near) {
        if (o != self && cuts(o)) return true;
      }
    }
    return false;
  }

  bool check_occlusions_ = true;
  NoiseModel noise_;
  InstanceStore<LightInstance> instances_;
  RingDirections directions_;  // per ring mount (one per robot type)
  LightScene scene_;
  std::atomic<uint64_t> scene_tick_{~uint64_t{0}};
  std::mutex scene_mutex_;
};

std::vector<AttributeDoc> LightAttributes() {
  std::vector<AttributeDoc> a = {
      {"check_occlusions", "true, false", "true",
       "lights hidden behind solid bodies are not seen (false: faster, sees through)"}};
  for (auto& n : NoiseModel::Attributes()) a.push_back(n);
  return a;
}

COLONY_REGISTER_SENSOR(
    LightSystem, "light", "default",
    "ring of light sensors: per sensor, the sum over visible lights of "
    "intensity / (1 + d^2) x cos(angle to the light) within +-90 degrees, in [0, 1]",
    DeviceInterface{"sensors/light/light.h",
                    "colony::LightSensor",
                    {"readings(): one per sensor in ring order, each: value (0 no light; larger: "
                     "more light), angle (rad, ccw from the front)"}},
    LightAttributes(), {"footbot_light"});

}  // namespace
}  // namespace colony
