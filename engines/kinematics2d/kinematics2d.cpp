// kinematics2d: the fastest engine, for very large swarms. Velocity-driven,
// no forces, on the floor plane. It knows no robot type: an entity type's
// model (kinematics2d.h; e.g. entities/marxbot/kinematics2d_model.cpp) says
// whether its entities are discs driven by their DriveState or obstacles.
//
// Each tick every driven disc ("robot" below) proposes the pose its wheel speeds take it to
// (exact for a constant turn rate over the tick). A robot whose proposal
// would overlap a wall, an object, another robot or leave the arena is
// blocked: it keeps its position and only turns (its footprint is a circle,
// so turning never overlaps). Blocking repeats until no proposal overlaps;
// the set of blocked robots only grows, so this ends, and it ends at the same
// set whatever the order or thread count. Robots therefore never
// interpenetrate. Objects (boxes, cylinders), movable or not, are fixed
// obstacles in this engine: robots stop at them and do not push them
// (use dynamics2d to push things). After the discs moved, models that hook
// into the step (kinematics2d.h) run, one after another: the marXbot's
// moves its manipulator and what the magnet carries, which the collision
// test then ignores.
#include "engines/kinematics2d/kinematics2d.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <vector>

#include "core/geometry2d.h"
#include "core/simulation.h"
#include "core/thread_pool.h"

namespace colony {

namespace kinematics2d {

Space& Engine::entities() { return sim().space(); }

void Engine::SetCarried(uint32_t s, bool carried) {
  if (carried_.size() <= s) carried_.resize(s + 1, 0);
  carried_[s] = carried;
}

}  // namespace kinematics2d

namespace {

// A Vec2 or Quat without the 16-byte alignment that would pad the per-robot
// structs below; the arithmetic on them is the same.
using UnalignedVec2 = Eigen::Matrix<double, 2, 1, Eigen::DontAlign>;
using UnalignedQuat = Eigen::Quaternion<double, Eigen::DontAlign>;

// Memory layout. A step sweeps the robots three times: proposals and commit
// read and write each robot's own state in the space (pose, drive, twist),
// and the collision test reads each robot's neighbours. The space stores
// entities by slot, roughly in the order they were added, which for a swarm
// placed at random has nothing to do with where they are. So proposals and
// commit run in the order the robots were added (streaming through the
// space's arrays), while everything the collision test reads about robots
// (Body, proposal, blocked flag) is stored by *spatial rank*, the robot's
// position in the space's cell-by-cell order, and the test runs in that
// order: a robot's neighbours then sit next to it in memory. None of this
// changes the results: each proposal and commit is the robot's own, and the
// set of blocked robots is the same whatever the order it is computed in.
class Kinematics2dEngine : public kinematics2d::Engine {
 public:
  void AddEntity(EntityHandle entity, PhysicsModel& model) override {
    auto* m = dynamic_cast<Kinematics2dModel*>(&model);
    if (!m)
      throw RuntimeFailure("the kinematics2d model of '" +
                           sim().space().TypeLabel(sim().space().type(entity.index)) +
                           "' is not a Kinematics2dModel (engines/kinematics2d/kinematics2d.h)");
    if (std::find(models_.begin(), models_.end(), m) == models_.end()) models_.push_back(m);
    m->Add(*this, entity.index);
    if (!m->driven() || !sim().space().drive(entity.index))
      return;  // obstacles are read from the space
    // Incremental (not Reindex()): loading 100,000 robots must stay linear.
    if (robot_index_.size() <= entity.index) robot_index_.resize(entity.index + 1, -1);
    robot_index_[entity.index] = static_cast<int32_t>(robots_.size());
    robots_.push_back(entity.index);
  }

  void RemoveEntity(EntityHandle entity) override {
    for (Kinematics2dModel* m : models_) m->EntityLeaving(*this, entity.index);
    SetCarried(entity.index, false);
    auto it = std::find(robots_.begin(), robots_.end(), entity.index);
    if (it == robots_.end()) return;
    robots_.erase(it);
    Reindex();
  }

  void Step(double dt) override {
    Space& space = sim().space();
    if (!robots_.empty()) MoveDiscs(space, dt);
    for (Kinematics2dModel* m : models_) m->AfterStep(*this, dt);
  }

 private:
  void MoveDiscs(Space& space, double dt) {
    const size_t n = robots_.size();
    RankBySpace(space);
    candidate_.resize(n);
    heading_.resize(n);
    body_.resize(n);
    first_.resize(n);
    blocked_.assign(n, 0);
    sensitive_.assign(n, 0);
    ThreadPool& pool = sim().pool();

    // Proposals, in robot order; results stored by rank.
    std::atomic<double> max_step{0.0};
    pool.ParallelFor(n, 256, [&](size_t b, size_t e) {
      double local_max = 0;
      for (size_t i = b; i < e; ++i) {
        const uint32_t s = robots_[i];
        const uint32_t k = rank_[i];
        const DriveState& d = *space.drive(s);
        const Pose& pose = space.pose(s);
        const Geometry& g = space.geometry(s);
        body_[k] = {pose.position.head<2>(), pose.position.z(), pose.position.z() + g.height(),
                    g.radius};
        const double v = 0.5 * (d.left + d.right);
        const double w = (d.right - d.left) / d.wheel_base;
        Heading& h = heading_[i];
        const double yaw0 = h.YawOf(pose.orientation);
        const double mid = yaw0 + 0.5 * w * dt;
        // Chord of the arc driven at constant v and w.
        const double chord =
            std::abs(w * dt) > 1e-12 ? v * dt * std::sin(0.5 * w * dt) / (0.5 * w * dt) : v * dt;
        candidate_[k] = pose.position.head<2>() + chord * h.Direction(mid);
        local_max = std::max(local_max, std::abs(chord));
      }
      double seen = max_step.load();
      while (local_max > seen && !max_step.compare_exchange_weak(seen, local_max)) {
      }
    });
    const double margin = max_step.load();

    // Block proposals that overlap, until none does. The first round tests
    // every robot (in rank order) against the others' proposals and notes
    // the robots that would overlap a neighbour if that neighbour were
    // blocked where it stands now ("sensitive"). Only those can be blocked in
    // a later round, so later rounds retest just them: the same rounds, with
    // the same outcome, as retesting every robot.
    pool.ParallelFor(n, 128, [&](size_t b, size_t e) {
      ChunkScratch<std::vector<uint32_t>, Kinematics2dEngine> scratch;  // no allocation once warm
      std::vector<uint32_t>& near = *scratch;
      near.clear();
      near.reserve(64);  // once per thread: enough for any crowd seen so far
      for (size_t k = b; k < e; ++k) {
        first_[k] = Collides(space, k, margin, near, &sensitive_[k]) ? 1 : 0;
      }
    });
    blocked_.swap(first_);
    retest_.clear();
    for (uint32_t k = 0; k < n; ++k) {
      if (!blocked_[k] && sensitive_[k]) retest_.push_back(k);
    }
    bool changed = !retest_.empty();
    while (changed) {
      newly_.clear();
      for (uint32_t k : retest_) {
        if (!blocked_[k] && Collides(space, k, margin, near_, nullptr)) newly_.push_back(k);
      }
      for (uint32_t k : newly_) blocked_[k] = 1;
      changed = !newly_.empty();
    }

    // Commit, in robot order.
    pool.ParallelFor(n, 256, [&](size_t b, size_t e) {
      for (size_t i = b; i < e; ++i) {
        const uint32_t s = robots_[i];
        const uint32_t k = rank_[i];
        DriveState& d = *space.drive(s);
        Pose& pose = space.pose(s);
        Twist& twist = space.twist(s);
        const double w = (d.right - d.left) / d.wheel_base;
        // The proposed heading, computed again rather than kept from the
        // proposals (8 bytes per robot): the same operations on the same
        // orientation and drive, so the same bits, and the memo answers YawOf.
        Heading& h = heading_[i];
        pose.orientation = h.FromYaw(h.YawOf(pose.orientation) + w * dt);
        twist.angular = Vec3(0, 0, w);
        if (blocked_[k]) {
          // Wheels only turn the robot on the spot; the rest slips.
          twist.linear.setZero();
          d.travelled_left = -0.5 * w * d.wheel_base * dt;
          d.travelled_right = 0.5 * w * d.wheel_base * dt;
        } else {
          const Vec2 delta = candidate_[k] - pose.position.head<2>();
          twist.linear = Vec3(delta.x() / dt, delta.y() / dt, 0);
          pose.position.head<2>() = candidate_[k];
          d.travelled_left = d.left * dt;
          d.travelled_right = d.right * dt;
        }
        space.set_in_contact(s, blocked_[k]);
      }
    });
  }

  // The heading conversions of one robot (atan2, sin, cos), remembered from
  // its last step. A robot driving straight has the same orientation, heading
  // and direction tick after tick, and recomputing them was a tenth of the
  // whole step. Inputs are compared bit for bit, so a remembered output is
  // exactly what computing afresh would give.
  class Heading {
   public:
    double YawOf(const Quat& q) {
      if (!Holds(q)) {
        // Only a turn about the vertical is remembered (what FromYaw makes).
        if (!Planar(q)) return colony::YawOf(q);
        z_ = q.z();
        w_ = q.w();
        yaw_ = kUnknown;
        to_yaw_ = kUnknown;
      }
      if (Same(yaw_, kUnknown)) yaw_ = colony::YawOf(Orientation());
      return yaw_;
    }
    // Unit vector at angle `a`.
    Vec2 Direction(double a) {
      if (!Same(a, angle_)) {
        angle_ = a;
        direction_ = Vec2(std::cos(a), std::sin(a));
      }
      return direction_;
    }
    // The orientation of heading `yaw`, wrapped to (-pi, pi].
    Quat FromYaw(double yaw) {
      if (!Same(yaw, to_yaw_)) {
        const Quat q = colony::FromYaw(WrapAngle(yaw));
        if (!Planar(q)) {  // a NaN yaw: not remembered
          to_yaw_ = kUnknown;
          return q;
        }
        to_yaw_ = yaw;
        z_ = q.z();
        w_ = q.w();
        yaw_ = kUnknown;
      }
      return Orientation();
    }

   private:
    static bool Same(double a, double b) {
      return std::bit_cast<uint64_t>(a) == std::bit_cast<uint64_t>(b);
    }
    // A turn by `a` about the vertical is (x, y, z, w) = (0 sin(a/2),
    // 0 sin(a/2), sin(a/2), cos(a/2)) as Eigen computes it: x and y are zeros
    // carrying the sign of z. Such an orientation is kept as z and w alone.
    static double ZeroLike(double z) { return std::copysign(0.0, z); }
    static bool Planar(const Quat& q) {
      return Same(q.x(), ZeroLike(q.z())) && Same(q.y(), ZeroLike(q.z()));
    }
    bool Holds(const Quat& q) const { return Same(q.z(), z_) && Same(q.w(), w_) && Planar(q); }
    Quat Orientation() const { return Quat(w_, ZeroLike(z_), ZeroLike(z_), z_); }
    // Marks a memo as empty, in place of a flag: a signalling NaN, which no
    // arithmetic, atan2 or caller's sum gives (they give quiet NaNs), so no
    // heading is ever taken for it.
    static constexpr double kUnknown = std::bit_cast<double>(uint64_t{0x7FF4000000000001});
    // One orientation serves both memos: the last one YawOf was given or
    // FromYaw made (a robot's orientation in the space is, while nothing
    // else turns it, what FromYaw made of it last tick), its z and w. yaw_
    // is its yaw unless kUnknown; it is FromYaw(to_yaw_) unless to_yaw_ is
    // kUnknown. 56 bytes per robot (72 with the whole orientation, 112 with
    // an orientation per memo); the results are the same (a memo only
    // returns what the function would, bit for bit).
    double z_ = 0.0, w_ = 1.0;
    UnalignedVec2 direction_ = UnalignedVec2(std::cos(0.0), std::sin(0.0));
    double yaw_ = kUnknown, angle_ = 0.0, to_yaw_ = kUnknown;
  };
  static_assert(sizeof(Heading) == 56);

  // What the collision test reads about a robot, copied from the space at
  // the start of the step (so it is exact), stored by rank (40 bytes; 48
  // with an aligned Vec2).
  struct Body {
    UnalignedVec2 position;  // where it stands now
    double bottom, top;      // height span (m)
    double radius;
  };
  static_assert(sizeof(Body) == 40);

  void Reindex() {
    robot_index_.assign(sim().space().slots(), -1);
    for (size_t i = 0; i < robots_.size(); ++i) robot_index_[robots_[i]] = static_cast<int32_t>(i);
    rank_of_slot_.assign(sim().space().slots(), -1);
  }

  // Ranks the robots in the order of the space's grid cells as of its last
  // index update (robots not in the index, if any, come last).
  void RankBySpace(const Space& space) {
    const size_t n = robots_.size();
    rank_.assign(n, UINT32_MAX);
    slot_at_.clear();
    slot_at_.reserve(n);
    for (uint32_t s : space.movable_by_cell()) {
      const int32_t i = s < robot_index_.size() ? robot_index_[s] : -1;
      if (i < 0) continue;
      rank_[i] = static_cast<uint32_t>(slot_at_.size());
      slot_at_.push_back(s);
    }
    for (size_t i = 0; slot_at_.size() < n && i < n; ++i) {
      if (rank_[i] != UINT32_MAX) continue;
      rank_[i] = static_cast<uint32_t>(slot_at_.size());
      slot_at_.push_back(robots_[i]);
    }
    if (rank_of_slot_.size() < space.slots()) rank_of_slot_.resize(space.slots(), -1);
    for (size_t k = 0; k < n; ++k) rank_of_slot_[slot_at_[k]] = static_cast<int32_t>(k);
  }

  // Whether the proposal of the robot of rank k overlaps the arena's edge or
  // anything solid, taking other robots of this engine at their proposal (or
  // where they stay, if blocked). If `sensitive` is given and there is no
  // overlap, it is set when the proposal would overlap some robot of this
  // engine standing where it is now.
  bool Collides(const Space& space, size_t k, double margin, std::vector<uint32_t>& near,
                uint8_t* sensitive) const {
    const uint32_t s = slot_at_[k];
    const Body& self = body_[k];
    const double r = self.radius;
    const Vec2& c = candidate_[k];
    const Vec3& lo = space.arena_min();
    const Vec3& hi = space.arena_max();
    if (c.x() - r < lo.x() || c.x() + r > hi.x() || c.y() - r < lo.y() || c.y() + r > hi.y())
      return true;
    const double z0 = self.bottom, z1 = self.top;
    near.clear();
    const double reach = r + margin;
    space.Gather(c.x() - reach, c.y() - reach, c.x() + reach, c.y() + reach, near);
    bool close = false;
    for (uint32_t o : near) {
      if (o == s) continue;
      const int32_t j = o < rank_of_slot_.size() ? rank_of_slot_[o] : -1;
      if (j >= 0) {
        const Body& other = body_[j];
        if (other.bottom >= z1 || z0 >= other.top) continue;
        const double rr = r + other.radius;
        const Vec2 p = blocked_[j] ? Vec2(other.position) : candidate_[j];
        if ((p - c).squaredNorm() < rr * rr) return true;
        close = close || (other.position - c).squaredNorm() < rr * rr;
      } else {
        // Another engine's movables may be moving right now: not ours to see.
        // What a robot carries blocks nothing.
        if ((space.movable(o) && !Owns(o)) || carried(o)) continue;
        const Pose& other = space.pose(o);
        const Geometry& og = space.geometry(o);
        if (other.position.z() >= z1 || z0 >= other.position.z() + og.height()) continue;
        if (CircleOverlapsFootprint(c, r, other, og)) return true;
      }
    }
    if (sensitive) *sensitive = close ? 1 : 0;
    return false;
  }

  // By robot index (the order robots were added):
  std::vector<uint32_t> robots_;  // space slots of the wheeled robots
  std::vector<uint32_t> rank_;    // spatial rank of each robot
  std::vector<Heading> heading_;
  // By spatial rank:
  std::vector<uint32_t> slot_at_;  // space slot of the robot of each rank
  std::vector<Body> body_;
  std::vector<Vec2> candidate_;  // proposed position
  std::vector<uint8_t> blocked_, first_, sensitive_;
  // By space slot:
  std::vector<int32_t> robot_index_;   // index in robots_, or -1
  std::vector<int32_t> rank_of_slot_;  // rank, or -1
  // Scratch.
  std::vector<uint32_t> retest_, newly_, near_;
  // The models of the entities it holds, in the order they came (for their hooks).
  std::vector<Kinematics2dModel*> models_;
};

COLONY_REGISTER_ENGINE(Kinematics2dEngine, "kinematics2d",
                       "velocity-driven 2D engine for very large swarms: no forces; robots stop at "
                       "obstacles and never overlap; objects are fixed obstacles",
                       {});

}  // namespace
}  // namespace colony
