// Simulated proximity sensors: one horizontal ray per sensor, from the body's
// surface outwards, at the sensor's height, against every solid footprint in
// the space. A reading falls with the distance d to the nearest hit:
//   value = min(1, 0.01 m / d)   (1 within 1 cm, 0.1 at 10 cm, 0 beyond range)
// then noise is added and the value clamped to [0, 1].
#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <deque>
#include <limits>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "core/device.h"
#include "core/entity_type.h"
#include "core/geometry2d.h"
#include "core/sensor_events.h"
#include "core/simulation.h"
#include "core/thread_pool.h"
#include "sensors/proximity/proximity.h"

namespace colony {
namespace {

// What every robot with the same ring shares (owned by the system): a private
// copy of the directions would cost 24 x 16 bytes per robot, of the angles
// 24 x 4.
struct ProximityRing {
  const RingMount* mount = nullptr;
  // Unit vectors of the sensors in the robot frame, one per reading, x and y
  // apart (so that the loop over all rays at once vectorizes).
  std::vector<double> dx, dy;
  // The sensors' angles as the readings give them (rad, wrapped to (-pi, pi]).
  std::vector<float> angles;
  std::atomic<bool>* any_watch = nullptr;  // the system's: some instance has watches
};

// The random stream of a ring with noise is kept by the system (most rings
// have none and draw nothing).
struct ProximityInstance : ProximitySensor, InstanceBaseWithoutStream {
  using Interface = ProximitySensor;
  std::span<float> values() { return {values_, count_}; }
  // The readings, without counting a poll (ProximitySensor::readings does).
  Readings stored() const { return {values_, angles_, count_}; }
  void SetRing(const ProximityRing& shared, std::span<float> values) {
    ring = &shared;
    values_ = values.data();
    angles_ = shared.angles.data();
    count_ = static_cast<uint32_t>(values.size());
  }
  int Watch(const ThresholdWatch& watch) override {
    if (!watches) watches = std::make_unique<ThresholdWatches>();
    const int id =
        watches->Add(watch, static_cast<int>(count_), [this](int i) { return values_[i]; });
    ring->any_watch->store(true, std::memory_order_relaxed);
    return id;
  }
  // Null until the controller calls Watch: most robots never do.
  std::unique_ptr<ThresholdWatches> watches;
  const ProximityRing* ring = nullptr;
};

// A footprint some ray of a robot may hit, with the circle around it
// relative to the robot's axis.
struct Target {
  Footprint footprint;
  Vec2 offset;       // centre - the robot's axis
  double bound = 0;  // bounding radius, with slack
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
    if (noise_.enabled()) streams_.push_back(rng);
    p.SetRing(RingOf(*mount), values_.Take(static_cast<size_t>(mount->count)));
    return &p;
  }
  void Detach(Sensor* s) override { instances_.Remove(static_cast<ProximitySensor*>(s)); }
  size_t size() const override { return instances_.size(); }
  bool HasWatches() const override { return any_watch_.load(std::memory_order_relaxed); }
  void TakeEvents(Sensor* s, std::vector<SensorEvent>& out) override {
    auto* p = static_cast<ProximityInstance*>(static_cast<ProximitySensor*>(s));
    if (p->watches) p->watches->Take(out);
  }
  size_t BusValues(const Sensor* s) const override {
    return static_cast<const ProximityInstance*>(static_cast<const ProximitySensor*>(s))
        ->stored()
        .size();
  }

  // Most robots of a swarm have nothing within the few centimetres their
  // sensors reach, so neighbours are first culled by distance (cheap, from
  // the centres) and the 24 rays are only cast against what survives. The
  // cull keeps every footprint that a ray could hit within range, so the
  // readings are exactly those of casting every ray at every gathered entity.
  void Update(size_t begin, size_t end) override {
    const Space& space = sim().space();
    // This thread's lists (ChunkScratch: no allocation once warm).
    struct Lists {
      std::vector<uint32_t> near, ahead;
      std::vector<Target> targets;
    };
    ChunkScratch<Lists, ProximitySystem> lists;
    std::vector<uint32_t>* near_list = &lists->near;
    std::vector<uint32_t>* ahead = &lists->ahead;
    std::vector<Target>& targets = lists->targets;
    near_list->reserve(64);  // once per thread: enough for any crowd seen so far
    ahead->reserve(64);
    targets.reserve(64);
    // A robot's neighbours are wherever they were placed in the space's
    // arrays, and with a swarm larger than the caches so is its own place in
    // the grid: what the robots a few ahead will read is asked for early (the
    // grid's cells three ahead, their entries two ahead, the neighbours'
    // poses and footprints one ahead), so that it arrives while the robot
    // before is sensing.
    auto query = [&](size_t k, auto&& fn) {
      const ProximityInstance& p = instances_[k];
      const Vec3& position = space.pose(p.robot.index).position;
      const RingMount& m = *p.ring->mount;
      const double reach = m.radius + (range_ > 0 ? range_ : m.range);
      fn(position.x() - reach, position.y() - reach, position.x() + reach, position.y() + reach);
    };
    auto prefetch_cells = [&](size_t k) {
      if (k < end && instances_[k].alive) {
        query(k, [&](double x0, double y0, double x1, double y1) {
          space.PrefetchGatherCells(x0, y0, x1, y1);
        });
      }
    };
    auto prefetch_items = [&](size_t k) {
      if (k < end && instances_[k].alive) {
        query(k, [&](double x0, double y0, double x1, double y1) {
          space.PrefetchGatherItems(x0, y0, x1, y1);
        });
      }
    };
    auto next_alive = [&](size_t k) {
      while (k < end && !instances_[k].alive) ++k;
      return k;
    };
    auto gather_ahead = [&](size_t k) {
      ahead->clear();
      query(k, [&](double x0, double y0, double x1, double y1) {
        space.Gather(x0, y0, x1, y1, *ahead);
      });
      for (uint32_t o : *ahead) {
        __builtin_prefetch(&space.pose(o));
        __builtin_prefetch(&space.geometry(o));
      }
    };
    size_t following = next_alive(begin);
    if (following < end) gather_ahead(following);
    for (size_t k = following; k < end; k = following) {
      ProximityInstance& p = instances_[k];
      std::swap(near_list, ahead);
      prefetch_cells(k + 3);
      prefetch_items(k + 2);
      following = next_alive(k + 1);
      if (following < end) gather_ahead(following);
      std::vector<uint32_t>& near = *near_list;
      const uint32_t self = p.robot.index;
      const Pose& pose = space.pose(self);
      const RingMount& m = *p.ring->mount;
      const double range = range_ > 0 ? range_ : m.range;
      const double reach = m.radius + range;
      const Vec2 c = pose.position.head<2>();
      const double z = pose.position.z() + m.elevation;
      // Keep the neighbours whose height spans the sensors' plane and whose
      // footprint comes within `reach` of the robot's axis: a ray hit at a
      // distance t <= range from the body's surface lies m.radius + t from the
      // axis, so a footprint whose bounding circle is farther away cannot give
      // a reading. (The small slack only guards against rounding.)
      targets.clear();
      for (uint32_t o : near) {
        if (o == self) continue;
        const Pose& op = space.pose(o);
        const Geometry& og = space.geometry(o);
        if (og.shape == ShapeKind::kNone) continue;  // nothing a ray can hit
        if (!(z >= op.position.z() && z < op.position.z() + og.height())) continue;
        const double bound = og.BoundingRadius() + 1e-6;
        const double limit = reach + bound;
        const Vec2 offset = op.position.head<2>() - c;
        if (offset.squaredNorm() >= limit * limit) continue;
        targets.push_back({Footprint::Of(op, og), offset, bound});
      }
      const std::span<float> values = p.values();
      if (targets.empty()) {
        // Nothing in range: every ray misses.
        if (noise_.enabled()) {
          for (float& v : values) v = static_cast<float>(Noisy(0.0, k));
        } else {
          std::fill(values.begin(), values.end(), 0.0f);
        }
        if (p.watches) CheckWatches(p);
        continue;
      }
      const double yaw = YawOf(pose.orientation);
      const double cy = std::cos(yaw), sy = std::sin(yaw);
      const size_t count = values.size();
      const double* dx = p.ring->dx.data();
      const double* dy = p.ring->dy.data();
      // A ray lies on a line through the robot's axis: a footprint whose
      // bounding circle stays off that line, or wholly behind the ray's
      // origin, is not hit (the slack in `bound` is far above rounding, so
      // every hit the ray test finds passes).
      auto misses = [&](const Vec2& dir, const Vec2& offset, double bound) {
        const double across = dir.x() * offset.y() - dir.y() * offset.x();
        return std::abs(across) > bound || dir.dot(offset) + bound < m.radius;
      };
      // The rays that may hit some target, found for all rays at once with
      // each target's offset turned into the robot's frame (one loop over
      // the ring's directions, x and y apart); most rays pass none and are
      // not cast. (This test's rounding differs from the world-frame one
      // below by far less than the slack: every ray that one passes is
      // marked here.) Rings of more than 64 cast every ray.
      uint64_t may_hit = ~uint64_t{0};
      if (count <= 64) {
        // How far each ray passes outside every target's circle (or behind
        // its origin), the least over targets: min and max only, so the
        // loop vectorizes. A ray is marked where that is <= 0 (for finite
        // numbers, a - b <= 0 exactly when a <= b).
        double excess[64];
        std::fill(excess, excess + count, std::numeric_limits<double>::infinity());
        bool finite = true;
        for (const Target& t : targets) {
          const double lx = cy * t.offset.x() + sy * t.offset.y();
          const double ly = cy * t.offset.y() - sy * t.offset.x();
          const double bound = t.bound, behind = m.radius - t.bound;
          finite = finite && std::isfinite(lx) && std::isfinite(ly);
          for (size_t i = 0; i < count; ++i) {
            const double across = dx[i] * ly - dy[i] * lx;
            const double along = dx[i] * lx + dy[i] * ly;
            excess[i] = std::min(excess[i], std::max(std::abs(across) - bound, behind - along));
          }
        }
        may_hit = 0;
        for (size_t i = 0; i < count; ++i) may_hit |= uint64_t{excess[i] <= 0} << i;
        if (!finite) may_hit = ~uint64_t{0};  // cast every ray, as the world-frame test would
      }
      // The nearest hit of each marked ray, every other ray missing.
      auto cast = [&](size_t i) {
        const Vec2 dir(cy * dx[i] - sy * dy[i], sy * dx[i] + cy * dy[i]);
        const Vec2 origin = c + m.radius * dir;
        double best = kNoHit;
        for (const Target& t : targets) {
          if (!misses(dir, t.offset, t.bound)) best = std::min(best, t.footprint.Ray(origin, dir));
        }
        return best <= range ? std::min(1.0, 0.01 / std::max(best, 1e-6)) : 0.0;
      };
      if (!noise_.enabled() && count <= 64) {
        std::fill(values.begin(), values.end(), 0.0f);
        for (uint64_t bits = may_hit; bits != 0; bits &= bits - 1) {
          const size_t i = static_cast<size_t>(std::countr_zero(bits));
          values[i] = static_cast<float>(cast(i));
        }
      } else {
        // Noise is drawn ray by ray, in ring order.
        for (size_t i = 0; i < count; ++i) {
          const double value = (i >= 64 || (may_hit >> i & 1)) ? cast(i) : 0.0;
          values[i] = static_cast<float>(Noisy(value, k));
        }
      }
      if (p.watches) CheckWatches(p);
    }
  }

  // Each robot's readings as {value, angle} pairs in ring order: the bytes
  // of an array of Reading (the hash is FNV-1a, byte by byte).
  void Hash(StateHasher& h) const override {
    for (size_t k = 0; k < instances_.size(); ++k) {
      if (!instances_[k].alive) continue;
      for (const ProximitySensor::Reading r : instances_[k].stored()) h.Add(&r, sizeof r);
    }
  }

 private:
  const ProximityRing& RingOf(const RingMount& mount) {
    for (const ProximityRing& ring : rings_) {
      if (ring.mount == &mount) return ring;
    }
    ProximityRing& ring = rings_.emplace_back();
    ring.mount = &mount;
    ring.any_watch = &any_watch_;
    for (int i = 0; i < mount.count; ++i) {
      const double a = mount.AngleOf(i);
      ring.angles.push_back(static_cast<float>(WrapAngle(a)));
      ring.dx.push_back(std::cos(a));
      ring.dy.push_back(std::sin(a));
    }
    return ring;
  }
  static void CheckWatches(ProximityInstance& p) {
    const float* values = p.values().data();
    p.watches->Check(&p, [values](int i) { return values[i]; });
  }
  // `value` with instance k's noise (drawn from its stream), if any.
  double Noisy(double value, size_t k) {
    if (!noise_.enabled()) return value;
    RandomStream& rng = streams_[k];
    return noise_.Drop(rng) ? 0.0 : std::clamp(noise_.Apply(value, rng), 0.0, 1.0);
  }

  double range_ = -1;
  NoiseModel noise_;
  InstanceStore<ProximityInstance> instances_;
  // Every instance's values, in blocks (addresses stay put as robots come).
  ArrayBlocks<float> values_;
  // One stream per instance, in the same order, only with noise.
  std::deque<RandomStream> streams_;
  std::deque<ProximityRing> rings_;  // per ring mount; a deque keeps them in place
  std::atomic<bool> any_watch_{false};
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
                       DeviceInterface{
                           "sensors/proximity/proximity.h",
                           "colony::ProximitySensor",
                           {"readings(): one Reading per sensor in ring order, each: value (0 "
                            "nothing in range .. 1 touching), angle (rad, ccw from the front)"}},
                       ProximityAttributes(), {"footbot_proximity"});

}  // namespace
}  // namespace colony
