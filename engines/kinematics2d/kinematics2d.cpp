// kinematics2d: the fastest engine, for very large swarms. Velocity-driven,
// no forces, on the floor plane.
//
// Each tick every wheeled robot proposes the pose its wheel speeds take it to
// (exact for a constant turn rate over the tick). A robot whose proposal
// would overlap a wall, an object, another robot or leave the arena is
// blocked: it keeps its position and only turns (its footprint is a circle,
// so turning never overlaps). Blocking repeats until no proposal overlaps;
// the set of blocked robots only grows, so this ends, and it ends at the same
// set whatever the order or thread count. Robots therefore never
// interpenetrate. Objects (boxes, cylinders), movable or not, are fixed
// obstacles in this engine: robots stop at them and do not push them
// (use dynamics2d to push things).
#include <algorithm>
#include <atomic>
#include <vector>

#include "core/engine.h"
#include "core/geometry2d.h"
#include "core/simulation.h"

namespace colony {
namespace {

class Kinematics2dModel : public PhysicsModel {
 public:
  explicit Kinematics2dModel(bool driven) : driven_(driven) {}
  bool driven() const { return driven_; }

 private:
  bool driven_;
};

// A robot driven by its wheels.
class WheeledRobotModel : public Kinematics2dModel {
 public:
  WheeledRobotModel() : Kinematics2dModel(true) {}
};

// Anything else solid: a fixed obstacle.
class ObstacleModel : public Kinematics2dModel {
 public:
  ObstacleModel() : Kinematics2dModel(false) {}
};

COLONY_REGISTER_PHYSICS_MODEL(WheeledRobotModel, "kinematics2d:marxbot",
                              "circular footprint moved by its differential drive; stops at obstacles");
COLONY_REGISTER_PHYSICS_MODEL(ObstacleModel, "kinematics2d:box",
                              "fixed obstacle, movable or not (not pushed in this engine)");
COLONY_REGISTER_PHYSICS_MODEL(ObstacleModel, "kinematics2d:cylinder",
                              "fixed obstacle, movable or not (not pushed in this engine)");

class Kinematics2dEngine : public PhysicsEngine {
 public:
  void AddEntity(EntityHandle entity, const PhysicsModel& model) override {
    const auto& m = dynamic_cast<const Kinematics2dModel&>(model);
    if (!m.driven() || !sim().space().drive(entity.index)) return;  // obstacles are read from the space
    robots_.push_back(entity.index);
    Reindex();
  }

  void RemoveEntity(EntityHandle entity) override {
    auto it = std::find(robots_.begin(), robots_.end(), entity.index);
    if (it == robots_.end()) return;
    robots_.erase(it);
    Reindex();
  }

  void Step(double dt) override {
    Space& space = sim().space();
    const size_t n = robots_.size();
    if (n == 0) return;
    candidate_.resize(n);
    yaw_.resize(n);
    blocked_.assign(n, 0);
    newly_.assign(n, 0);
    ThreadPool& pool = sim().pool();

    // Proposals.
    std::atomic<double> max_step{0.0};
    pool.ParallelFor(n, 256, [&](size_t b, size_t e) {
      double local_max = 0;
      for (size_t i = b; i < e; ++i) {
        const uint32_t s = robots_[i];
        const DriveState& d = *space.drive(s);
        const Pose& pose = space.pose(s);
        const double v = 0.5 * (d.left + d.right);
        const double w = (d.right - d.left) / d.wheel_base;
        const double yaw0 = YawOf(pose.orientation);
        const double mid = yaw0 + 0.5 * w * dt;
        // Chord of the arc driven at constant v and w.
        const double chord = std::abs(w * dt) > 1e-12 ? v * dt * std::sin(0.5 * w * dt) / (0.5 * w * dt) : v * dt;
        candidate_[i] = pose.position.head<2>() + chord * Vec2(std::cos(mid), std::sin(mid));
        yaw_[i] = yaw0 + w * dt;
        local_max = std::max(local_max, std::abs(chord));
      }
      double seen = max_step.load();
      while (local_max > seen && !max_step.compare_exchange_weak(seen, local_max)) {
      }
    });
    const double margin = max_step.load();

    // Block proposals that overlap, until none does.
    bool changed = true;
    while (changed) {
      pool.ParallelFor(n, 128, [&](size_t b, size_t e) {
        static thread_local std::vector<uint32_t> near;
        for (size_t i = b; i < e; ++i) {
          if (blocked_[i]) continue;
          newly_[i] = Collides(space, i, margin, near) ? 1 : 0;
        }
      });
      changed = false;
      for (size_t i = 0; i < n; ++i) {
        if (newly_[i]) {
          blocked_[i] = 1;
          newly_[i] = 0;
          changed = true;
        }
      }
    }

    // Commit.
    pool.ParallelFor(n, 256, [&](size_t b, size_t e) {
      for (size_t i = b; i < e; ++i) {
        const uint32_t s = robots_[i];
        DriveState& d = *space.drive(s);
        Pose& pose = space.pose(s);
        Twist& twist = space.twist(s);
        const double w = (d.right - d.left) / d.wheel_base;
        pose.orientation = FromYaw(WrapAngle(yaw_[i]));
        twist.angular = Vec3(0, 0, w);
        if (blocked_[i]) {
          // Wheels only turn the robot on the spot; the rest slips.
          twist.linear.setZero();
          d.travelled_left = -0.5 * w * d.wheel_base * dt;
          d.travelled_right = 0.5 * w * d.wheel_base * dt;
        } else {
          const Vec2 delta = candidate_[i] - pose.position.head<2>();
          twist.linear = Vec3(delta.x() / dt, delta.y() / dt, 0);
          pose.position.head<2>() = candidate_[i];
          d.travelled_left = d.left * dt;
          d.travelled_right = d.right * dt;
        }
        space.set_in_contact(s, blocked_[i]);
      }
    });
  }

 private:
  void Reindex() {
    robot_index_.assign(sim().space().slots(), -1);
    for (size_t i = 0; i < robots_.size(); ++i) robot_index_[robots_[i]] = static_cast<int32_t>(i);
  }

  // Whether robot i's proposal overlaps the arena's edge or anything solid,
  // taking other robots of this engine at their proposal (or where they
  // stay, if blocked).
  bool Collides(const Space& space, size_t i, double margin, std::vector<uint32_t>& near) const {
    const uint32_t s = robots_[i];
    const Geometry& g = space.geometry(s);
    const double r = g.radius;
    const Vec2& c = candidate_[i];
    const Vec3& lo = space.arena_min();
    const Vec3& hi = space.arena_max();
    if (c.x() - r < lo.x() || c.x() + r > hi.x() || c.y() - r < lo.y() || c.y() + r > hi.y()) return true;
    const double z0 = space.pose(s).position.z(), z1 = z0 + g.height();
    near.clear();
    const double reach = r + margin;
    space.Gather(c.x() - reach, c.y() - reach, c.x() + reach, c.y() + reach, near);
    for (uint32_t o : near) {
      if (o == s) continue;
      const Pose& other = space.pose(o);
      const Geometry& og = space.geometry(o);
      if (other.position.z() >= z1 || z0 >= other.position.z() + og.height()) continue;
      const int32_t j = o < robot_index_.size() ? robot_index_[o] : -1;
      if (j >= 0) {
        const Vec2 p = blocked_[j] ? other.position.head<2>() : candidate_[j];
        const double rr = r + og.radius;
        if ((p - c).squaredNorm() < rr * rr) return true;
      } else if (CircleOverlapsFootprint(c, r, other, og)) {
        return true;
      }
    }
    return false;
  }

  std::vector<uint32_t> robots_;       // space slots of the wheeled robots
  std::vector<int32_t> robot_index_;   // per space slot: index in robots_, or -1
  std::vector<Vec2> candidate_;
  std::vector<double> yaw_;
  std::vector<uint8_t> blocked_, newly_;
};

COLONY_REGISTER_ENGINE(Kinematics2dEngine, "kinematics2d",
                       "velocity-driven 2D engine for very large swarms: no forces; robots stop at "
                       "obstacles and never overlap; objects are fixed obstacles",
                       {});

}  // namespace
}  // namespace colony
