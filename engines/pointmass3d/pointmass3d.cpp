// pointmass3d: flying robots as point masses, cheap enough for thousands.
// It knows no robot type: an entity type's model (pointmass3d.h; e.g.
// entities/eyebot/pointmass3d_model.cpp) says whether its entities fly or
// are obstacles. A flyer is a point mass at its base with an upright
// cylinder of its geometry around it for collisions; its orientation stays
// level (only the yaw turns).
//
// A tick, in four phases:
//   1. Fly (in parallel, each flyer alone): the ceiling attachment (an
//      attached flyer keeps its pose, stopped, rotors off); otherwise the
//      flight computer (entities/eyebot/flight.h) gives the rotors' force and
//      yaw rate, integrated semi-implicitly with gravity
//      (v += (F/m - g) h; p += v h); then the flyer is pushed out of the
//      fixed obstacles (least penetration), the arena's sides, floor and
//      ceiling, losing the velocity into what it met.
//   2. Separate (a few rounds, each from a snapshot of the positions): two
//      flyers that overlap are pushed apart along their least penetration,
//      half each, or all of it by one when the other cannot give way
//      (attached, or pressed into what holds it).
//   3. Hold back: a flyer that still overlaps another by more than 2 cm
//      (kHeldBackDepth) keeps its horizontal position of the start of the
//      tick (it still climbs or descends, as in a jammed crowd); if it
//      still does, its whole pose, stopped. That repeats until no overlap
//      is deeper; the poses of the start of the tick had none, so it ends,
//      and flyers never sink more than 2 cm into each other. Shallower
//      overlaps are pushed apart over the next ticks.
//      Holding back only grows and each round reads the last round's
//      result, so the outcome does not depend on order.
//   4. Commit (in parallel): pose, velocity, yaw rate into the space.
// Every phase writes only per-flyer data, so runs are identical whatever the
// number of threads.
//
// Engines step in parallel with each other, so this one never reads another
// engine's movable entities (a foot-bot below in kinematics2d): only its own
// flyers, and the obstacles that nobody moves (fixed ones, and movable ones
// this engine owns: it never moves them).
#include "engines/pointmass3d/pointmass3d.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/geometry2d.h"
#include "core/simulation.h"
#include "entities/eyebot/eyebot.h"
#include "entities/eyebot/flight.h"

namespace colony {
namespace {

using eyebot::kGravity;

// Overlaps deeper than this (m) count: positions pushed apart to touch
// exactly are apart up to rounding.
constexpr double kSlop = 1e-9;
// Flyers per chunk of the parallel phases; each chunk has its own scratch.
constexpr size_t kChunk = 256;
// Passes against the fixed obstacles (a flyer in a corner needs two).
constexpr int kObstaclePasses = 3;
// Rounds of pushing overlapping flyers apart before blocking what remains.
constexpr int kSeparationRounds = 3;
// Overlap between flyers (m) left after those rounds for the next ticks to
// push apart; deeper ones are held back. Holding back every overlap left,
// however shallow, locked crowds of flyers with crossing goals into jams
// that never broke up (each held back every tick, nobody sliding past).
constexpr double kHeldBackDepth = 0.02;

// Memory layout. A step sweeps the flyers in the order they were added, each
// chunk of kChunk reading and writing its own flyers' Body records (one
// 112-byte hot record each, everything the phases need), so the parallel
// phases share no cache line but at chunk ends. Flyer-flyer collisions look
// up neighbours in a uniform grid over the arena rebuilt each tick by a
// counting sort (O(n), no allocation once the arrays have grown): at most
// about four cells per flyer, each at least a flyer's diameter wide, so a
// flyer meets only those within a few cells of it.
class Pointmass3dEngine : public PhysicsEngine {
 public:
  bool Is3D() const override { return true; }

  void AddEntity(EntityHandle entity, PhysicsModel& model) override {
    const Space& space = sim().space();
    const uint32_t s = entity.index;
    const auto* m = dynamic_cast<const Pointmass3dModel*>(&model);
    if (!m)
      throw RuntimeFailure("the pointmass3d model of '" + space.TypeLabel(space.type(s)) +
                           "' is not a Pointmass3dModel (engines/pointmass3d/pointmass3d.h)");
    if (!m->flyer()) return;  // obstacles are read from the space
    if (!space.Get<QuadrotorState>(s) || !(space.mass(s) > 0))
      throw RuntimeFailure("pointmass3d flies '" + space.TypeLabel(space.type(s)) +
                           "', but entity '" + space.id(s) +
                           "' has no quadrotor component or no mass");
    if (flyer_of_.size() <= s) flyer_of_.resize(s + 1, -1);
    flyer_of_[s] = static_cast<int32_t>(slots_.size());
    slots_.push_back(s);
    headings_.emplace_back();
    max_radius_ = std::max(max_radius_, space.geometry(s).BoundingRadius());
    if (sim().tick() == 0) WarnIfHeldAwayFromCeiling(space, s);
  }

  void RemoveEntity(EntityHandle entity) override {
    const uint32_t s = entity.index;
    if (s >= flyer_of_.size() || flyer_of_[s] < 0) return;
    const size_t i = static_cast<size_t>(flyer_of_[s]);
    slots_.erase(slots_.begin() + static_cast<ptrdiff_t>(i));
    headings_.erase(headings_.begin() + static_cast<ptrdiff_t>(i));
    flyer_of_.assign(flyer_of_.size(), -1);
    for (size_t k = 0; k < slots_.size(); ++k) flyer_of_[slots_[k]] = static_cast<int32_t>(k);
  }

  void Step(double dt) override {
    const size_t n = slots_.size();
    if (n == 0) return;
    dt_ = dt;
    // The velocity loop's gain times the integration step must stay well
    // under 1 for the flight computer to be stable: at 10 ticks per second,
    // one step per tick.
    substeps_ = std::max(1, static_cast<int>(std::ceil(dt * eyebot::kVelocityGain / 0.5)));
    bodies_.resize(n);
    delta_.resize(n);
    grid_position_.resize(n);
    held_.assign(n, 0);
    test_.resize(n);
    mark_.assign(n, 0);
    const size_t chunks = (n + kChunk - 1) / kChunk;
    if (scratch_.size() < chunks) scratch_.resize(chunks);

    // 1. Fly, and keep out of the fixed world.
    RunPhase(Phase::kFly);
    // 2. Push overlapping flyers apart.
    BuildGrid();
    for (int round = 0; round < kSeparationRounds; ++round) {
      drift_ = MaxDrift(false);
      overlaps_.store(false, std::memory_order_relaxed);
      RunPhase(Phase::kSeparate);
      if (!overlaps_.load(std::memory_order_relaxed)) break;
      RunPhase(Phase::kApply);
    }
    // 3. Hold back what still overlaps. The first round tests every flyer;
    // later ones only those held back in the round before and their
    // neighbours.
    drift_ = MaxDrift(true);
    RunPhase(Phase::kBlock);
    newly_.clear();
    for (uint32_t i = 0; i < n; ++i) {
      if (test_[i]) newly_.push_back(i);
    }
    while (!newly_.empty()) {
      for (uint32_t i : newly_) HoldBack(i);
      retest_.clear();
      for (uint32_t k : newly_) {
        const Body& b = bodies_[k];
        ForNear(b.position.head<2>(), b.radius + max_radius_ + drift_, [&](uint32_t j) {
          if (held_[j] == 2 || mark_[j]) return;
          mark_[j] = 1;
          retest_.push_back(j);
        });
      }
      newly_.clear();
      for (uint32_t j : retest_) {
        mark_[j] = 0;
        if (OverlapsAnother(j)) newly_.push_back(j);
      }
    }
    // 4. Commit.
    RunPhase(Phase::kCommit);
  }

 private:
  // What the phases of a tick know of one flyer.
  struct Body {
    Vec3 start;     // where it was when the tick began
    Vec3 position;  // where it goes
    Vec3 velocity;  // m/s, world frame
    double radius, height;
    double yaw, yaw_rate;  // heading at the end of the tick (rad), and the tick's turn rate
    uint8_t fixed;         // attached to the ceiling: it does not move
    uint8_t supported;     // resting on the floor or an obstacle's top: cannot be pushed down
    uint8_t capped;        // pressed against the ceiling: cannot be pushed up
    uint8_t contact;       // met an obstacle, the arena's side, the ceiling or a flyer
  };

  // How flyer a must move to clear flyer b: a unit direction and a depth
  // (<= 0: they do not overlap).
  struct Push {
    Vec3 direction = Vec3::Zero();
    double depth = 0;
  };

  // The heading of a flyer as last written, so that reading it back costs no
  // atan2: compared bit for bit with the space's orientation, which a loop
  // function may have changed.
  struct Heading {
    Quat written = Quat(std::nan(""), 0, 0, 0);
    double yaw = 0;
    bool Same(const Quat& q) const {
      return std::bit_cast<uint64_t>(q.w()) == std::bit_cast<uint64_t>(written.w()) &&
             std::bit_cast<uint64_t>(q.x()) == std::bit_cast<uint64_t>(written.x()) &&
             std::bit_cast<uint64_t>(q.y()) == std::bit_cast<uint64_t>(written.y()) &&
             std::bit_cast<uint64_t>(q.z()) == std::bit_cast<uint64_t>(written.z());
    }
  };

  enum class Phase { kFly, kSeparate, kApply, kBlock, kCommit };

  // Runs `phase` over all flyers in parallel chunks of kChunk. The job
  // captures only `this`, so handing it to the pool allocates nothing.
  void RunPhase(Phase phase) {
    phase_ = phase;
    const size_t chunks = (slots_.size() + kChunk - 1) / kChunk;
    sim().pool().ParallelFor(chunks, 1, [this](size_t b, size_t e) {
      for (size_t c = b; c < e; ++c) RunChunk(c);
    });
  }

  void RunChunk(size_t c) {
    const size_t begin = c * kChunk, end = std::min(slots_.size(), begin + kChunk);
    std::vector<uint32_t>& near = scratch_[c];
    Space& space = sim().space();
    for (size_t i = begin; i < end; ++i) {
      switch (phase_) {
        case Phase::kFly:
          Fly(space, i, near);
          break;
        case Phase::kSeparate:
          Separate(i);
          break;
        case Phase::kApply:
          if (!delta_[i].isZero()) {
            bodies_[i].position += delta_[i];
            KeepOutOfTheWorld(space, i, near);
          }
          break;
        case Phase::kBlock:
          test_[i] = OverlapsAnother(i) ? 1 : 0;
          break;
        case Phase::kCommit:
          Commit(space, i);
          break;
      }
    }
  }

  // Phase 1 for flyer i.
  void Fly(Space& space, size_t i, std::vector<uint32_t>& near) {
    const uint32_t s = slots_[i];
    const Pose& pose = space.pose(s);
    const Geometry& g = space.geometry(s);
    Body& b = bodies_[i];
    b = Body{pose.position,
             pose.position,
             space.twist(s).linear,
             g.BoundingRadius(),
             g.height(),
             0,
             0,
             0,
             0,
             0,
             0};
    Heading& heading = headings_[i];
    const double yaw0 = heading.Same(pose.orientation) ? heading.yaw : YawOf(pose.orientation);
    b.yaw = yaw0;
    QuadrotorState& rotors = *space.Get<QuadrotorState>(s);
    if (Attached(space, s, b)) {
      b.velocity.setZero();
      b.fixed = 1;
      rotors.thrust = 0;
      return;
    }
    const double mass = space.mass(s);
    const double h = dt_ / substeps_;
    eyebot::FlightOutput out;
    for (int k = 0; k < substeps_; ++k) {
      out = eyebot::Fly(rotors, b.position, b.velocity, b.yaw, mass);
      b.velocity += (out.force / mass - Vec3(0, 0, kGravity)) * h;
      b.position += b.velocity * h;
      b.yaw += out.yaw_rate * h;
    }
    rotors.thrust = out.thrust;
    KeepOutOfTheWorld(space, i, near);
    // Resting on what is under it with less lift than its weight: friction
    // holds it (no sliding, no turning).
    if (b.supported && out.force.z() < mass * kGravity) {
      b.position.head<2>() = b.start.head<2>();
      b.velocity.head<2>().setZero();
      b.yaw = yaw0;
    }
    b.yaw_rate = (b.yaw - yaw0) / dt_;
  }

  // The ceiling attachment of flyer s (if it has one): it lets go when not
  // asked to hold, and takes hold when asked and its top is at the ceiling.
  static bool Attached(Space& space, uint32_t s, const Body& b) {
    CeilingAttachmentState* c = space.Get<CeilingAttachmentState>(s);
    if (!c) return false;
    if (!c->attach) {
      c->attached = false;
    } else if (!c->attached) {
      const auto& ceiling = space.ceiling();
      c->attached =
          ceiling && std::abs(ceiling->z - (b.position.z() + b.height)) <= eyebot::kAttachDistance;
    }
    return c->attached;
  }

  // Pushes flyer i out of the obstacles (each along its least penetration),
  // then into the arena, above the floor and below the ceiling; removes the
  // velocity into what it met.
  void KeepOutOfTheWorld(const Space& space, size_t i, std::vector<uint32_t>& near) {
    Body& b = bodies_[i];
    const uint32_t self = slots_[i];
    const double r = b.radius;
    Vec3& p = b.position;
    Vec3& v = b.velocity;
    near.clear();
    const double reach = 2 * r;
    space.Gather(p.x() - reach, p.y() - reach, p.x() + reach, p.y() + reach, near);
    for (int pass = 0; pass < kObstaclePasses; ++pass) {
      bool moved = false;
      for (uint32_t o : near) {
        if (!IsObstacle(space, self, o)) continue;
        const Pose& op = space.pose(o);
        const Geometry& og = space.geometry(o);
        const double bottom = op.position.z(), top = bottom + og.height();
        if (p.z() >= top || p.z() + b.height <= bottom) continue;
        Vec2 normal;
        const double side = FootprintPenetration(p.head<2>(), r, op, og, normal);
        if (side <= kSlop) continue;
        const double up = top - p.z(), down = p.z() + b.height - bottom;
        if (side <= up && side <= down) {
          p.head<2>() += side * normal;
          const double into = v.head<2>().dot(normal);
          if (into < 0) v.head<2>() -= into * normal;
        } else if (up <= down) {
          p.z() = top;
          v.z() = std::max(v.z(), 0.0);
          b.supported = 1;
        } else {
          p.z() = bottom - b.height;
          v.z() = std::min(v.z(), 0.0);
          b.capped = 1;
        }
        b.contact = 1;
        moved = true;
      }
      if (!moved) break;
    }
    // The arena's sides.
    const Vec3& lo = space.arena_min();
    const Vec3& hi = space.arena_max();
    for (int k = 0; k < 2; ++k) {
      if (p[k] - r < lo[k]) {
        p[k] = lo[k] + r;
        v[k] = std::max(v[k], 0.0);
        b.contact = 1;
      } else if (p[k] + r > hi[k]) {
        p[k] = hi[k] - r;
        v[k] = std::min(v[k], 0.0);
        b.contact = 1;
      }
    }
    // The ceiling, or else the arena's top.
    const auto& ceiling = space.ceiling();
    const double limit = ceiling ? std::min(ceiling->z, hi.z()) : hi.z();
    if (p.z() + b.height > limit) {
      p.z() = limit - b.height;
      v.z() = std::min(v.z(), 0.0);
      b.capped = 1;
      b.contact = 1;
    }
    // The floor (landing is not a collision).
    if (p.z() <= lo.z()) {
      p.z() = lo.z();
      v.z() = std::max(v.z(), 0.0);
      b.supported = 1;
    }
  }

  // How deep a circle (p, r) reaches into the footprint of an entity at
  // `pose`, and the unit direction (`normal`) that takes it out fastest; <= 0
  // when apart.
  static double FootprintPenetration(const Vec2& p, double r, const Pose& pose, const Geometry& g,
                                     Vec2& normal) {
    if (g.shape == ShapeKind::kCylinder) {
      const Vec2 d = p - pose.position.head<2>();
      const double dist = d.norm();
      normal = dist > 1e-12 ? Vec2(d / dist) : Vec2(1, 0);
      return r + g.radius - dist;
    }
    if (g.shape != ShapeKind::kBox) return 0;
    const Rect rect = RectOf(pose, g);
    const Vec2 local = rect.ToLocal(p);
    const Vec2 nearest(std::clamp(local.x(), -rect.half.x(), rect.half.x()),
                       std::clamp(local.y(), -rect.half.y(), rect.half.y()));
    Vec2 n_local;
    double depth;
    if (nearest != local) {
      const Vec2 d = local - nearest;
      const double dist = d.norm();
      n_local = d / dist;
      depth = r - dist;
    } else {
      // The centre is inside: out through the nearest side.
      const double dx = rect.half.x() - std::abs(local.x()),
                   dy = rect.half.y() - std::abs(local.y());
      n_local = dx <= dy ? Vec2(local.x() < 0 ? -1 : 1, 0) : Vec2(0, local.y() < 0 ? -1 : 1);
      depth = r + std::min(dx, dy);
    }
    normal = Vec2(rect.cos_yaw * n_local.x() - rect.sin_yaw * n_local.y(),
                  rect.sin_yaw * n_local.x() + rect.cos_yaw * n_local.y());
    return depth;
  }

  // How flyer a (index ia, at pa) must move to clear flyer b (at pb), both
  // upright cylinders: sideways, up onto it or down under it, whichever is
  // shortest. Antisymmetric: b's push from a is the opposite one.
  static Push Separation(const Body& a, const Vec3& pa, size_t ia, const Body& b, const Vec3& pb,
                         size_t ib) {
    Push push;
    const double up = pb.z() + b.height - pa.z(), down = pa.z() + a.height - pb.z();
    if (up <= 0 || down <= 0) return push;
    const Vec2 d = pa.head<2>() - pb.head<2>();
    const double dist = d.norm();
    const double side = a.radius + b.radius - dist;
    if (side <= 0) return push;
    // a goes up if its centre is higher (then `up` is the shorter way).
    const double ca = pa.z() + 0.5 * a.height, cb = pb.z() + 0.5 * b.height;
    const bool goes_up = ca > cb || (ca == cb && ia > ib);
    const double vertical = goes_up ? up : down;
    if (side <= vertical) {
      const Vec2 n = dist > 1e-12 ? Vec2(d / dist) : Vec2(ia < ib ? -1.0 : 1.0, 0.0);
      push.direction = Vec3(n.x(), n.y(), 0);
      push.depth = side;
    } else {
      push.direction = Vec3(0, 0, goes_up ? 1 : -1);
      push.depth = vertical;
    }
    return push;
  }

  // Whether flyer i cannot give way along `direction`.
  bool Stuck(size_t i, const Vec3& direction) const {
    const Body& b = bodies_[i];
    return b.fixed || (direction.z() < 0 && b.supported) || (direction.z() > 0 && b.capped);
  }

  // Phase 2 for flyer i: how far the flyers it overlaps push it (delta_),
  // from the positions every flyer had at the start of the round.
  void Separate(size_t i) {
    Body& b = bodies_[i];
    Vec3 move = Vec3::Zero();
    Vec3 v = b.velocity;
    bool met = false;
    ForNear(b.position.head<2>(), b.radius + max_radius_ + drift_, [&](uint32_t j) {
      if (j == i) return;
      const Body& other = bodies_[j];
      const Push push = Separation(b, b.position, i, other, other.position, j);
      if (push.depth <= kSlop) return;
      met = true;
      const double share = Stuck(i, push.direction) ? 0.0 : Stuck(j, -push.direction) ? 1.0 : 0.5;
      move += share * push.depth * push.direction;
      const double into = v.dot(push.direction);
      if (into < 0) v -= into * push.direction;
    });
    delta_[i] = move;
    if (!met) return;
    overlaps_.store(true, std::memory_order_relaxed);
    b.contact = 1;
    if (!b.fixed) b.velocity = v;
  }

  // Whether flyer i, where it goes, overlaps another flyer where that one
  // goes by more than kHeldBackDepth.
  bool OverlapsAnother(size_t i) const {
    const Body& b = bodies_[i];
    bool overlaps = false;
    ForNear(b.position.head<2>(), b.radius + max_radius_ + drift_, [&](uint32_t j) {
      if (j == i || overlaps) return;
      const Body& other = bodies_[j];
      overlaps = Separation(b, b.position, i, other, other.position, j).depth > kHeldBackDepth;
    });
    return overlaps;
  }

  // Phase 3 for flyer i, which overlaps another: first it only keeps its
  // horizontal position (still climbing or descending, as a jammed crowd
  // does) if that is clear of obstacles; then, if it still overlaps, it
  // stays where it started the tick, which overlapped nothing.
  void HoldBack(size_t i) {
    Body& b = bodies_[i];
    b.contact = 1;
    if (held_[i] == 0) {
      held_[i] = 1;
      const Vec3 upright(b.start.x(), b.start.y(), b.position.z());
      if (!InObstacle(sim().space(), i, upright, near_)) {
        b.position = upright;
        b.velocity.head<2>().setZero();
        return;
      }
    }
    held_[i] = 2;
    b.position = b.start;
    b.velocity.setZero();
  }

  // Whether flyer i at p overlaps an obstacle.
  bool InObstacle(const Space& space, size_t i, const Vec3& p, std::vector<uint32_t>& near) const {
    const Body& b = bodies_[i];
    near.clear();
    space.Gather(p.x() - b.radius, p.y() - b.radius, p.x() + b.radius, p.y() + b.radius, near);
    for (uint32_t o : near) {
      if (!IsObstacle(space, slots_[i], o)) continue;
      const Pose& op = space.pose(o);
      const Geometry& og = space.geometry(o);
      if (p.z() >= op.position.z() + og.height() || p.z() + b.height <= op.position.z()) continue;
      Vec2 normal;
      if (FootprintPenetration(p.head<2>(), b.radius, op, og, normal) > kSlop) return true;
    }
    return false;
  }

  // Whether entity o is an obstacle to flyer `self`: not itself nor another
  // flyer of this engine, and not moved by another engine (which may be
  // moving it right now: not ours to see).
  bool IsObstacle(const Space& space, uint32_t self, uint32_t o) const {
    if (o == self || (o < flyer_of_.size() && flyer_of_[o] >= 0)) return false;
    return !space.movable(o) || Owns(o);
  }

  // Phase 4 for flyer i.
  void Commit(Space& space, size_t i) {
    const uint32_t s = slots_[i];
    const Body& b = bodies_[i];
    Pose& pose = space.pose(s);
    Twist& twist = space.twist(s);
    pose.position = b.position;
    twist.linear = b.velocity;
    Heading& heading = headings_[i];
    heading.yaw = WrapAngle(b.yaw);
    heading.written = FromYaw(heading.yaw);
    pose.orientation = heading.written;
    twist.angular = Vec3(0, 0, b.yaw_rate);
    space.set_in_contact(s, b.contact);
  }

  // The uniform grid over the arena's floor plan, on the flyers' positions
  // after phase 1 (grid_position_).
  void BuildGrid() {
    const Space& space = sim().space();
    const size_t n = slots_.size();
    const Vec3& lo = space.arena_min();
    const Vec3& hi = space.arena_max();
    const double wx = std::max(hi.x() - lo.x(), 1e-3), wy = std::max(hi.y() - lo.y(), 1e-3);
    double cell = std::max(2 * max_radius_, 1e-3);
    const double most = 4.0 * static_cast<double>(n) + 64;
    while (std::ceil(wx / cell) * std::ceil(wy / cell) > most) cell *= 1.5;
    nx_ = static_cast<int>(std::ceil(wx / cell));
    ny_ = static_cast<int>(std::ceil(wy / cell));
    inv_cell_ = 1.0 / cell;
    origin_ = lo.head<2>();
    cell_start_.assign(static_cast<size_t>(nx_) * ny_ + 1, 0);
    cell_of_.resize(n);
    cell_items_.resize(n);
    for (size_t i = 0; i < n; ++i) {
      const Vec2 p = bodies_[i].position.head<2>();
      grid_position_[i] = p;
      cell_of_[i] = static_cast<uint32_t>(CellY(p.y())) * nx_ + CellX(p.x());
      ++cell_start_[cell_of_[i] + 1];
    }
    for (size_t c = 1; c < cell_start_.size(); ++c) cell_start_[c] += cell_start_[c - 1];
    cell_cursor_.assign(cell_start_.begin(), cell_start_.end() - 1);
    for (size_t i = 0; i < n; ++i)
      cell_items_[cell_cursor_[cell_of_[i]]++] = static_cast<uint32_t>(i);
  }

  int CellX(double x) const { return ClampedCellIndex((x - origin_.x()) * inv_cell_, nx_); }
  int CellY(double y) const { return ClampedCellIndex((y - origin_.y()) * inv_cell_, ny_); }

  // Calls f(j) for every flyer j whose grid position is in a cell within
  // `reach` of p, in a fixed order (cells row by row, flyers by index).
  template <class F>
  void ForNear(const Vec2& p, double reach, F&& f) const {
    const int x0 = CellX(p.x() - reach), x1 = CellX(p.x() + reach);
    const int y0 = CellY(p.y() - reach), y1 = CellY(p.y() + reach);
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const size_t c = static_cast<size_t>(y) * nx_ + x;
        for (uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) f(cell_items_[k]);
      }
    }
  }

  // How far (horizontally) any flyer is from where the grid holds it: where
  // it goes, and with `with_start` where it started.
  double MaxDrift(bool with_start) const {
    double most = 0;
    for (size_t i = 0; i < slots_.size(); ++i) {
      const Body& b = bodies_[i];
      most = std::max(most, (b.position.head<2>() - grid_position_[i]).norm());
      if (with_start) most = std::max(most, (b.start.head<2>() - grid_position_[i]).norm());
    }
    return most;
  }

  // By flyer index (the order flyers were added):
  std::vector<uint32_t> slots_;  // space slot
  std::vector<Heading> headings_;
  std::vector<Body> bodies_;
  std::vector<Vec3> delta_;          // phase 2: this round's push
  std::vector<Vec2> grid_position_;  // where the grid holds it
  std::vector<uint32_t> cell_of_;
  std::vector<uint8_t> test_, mark_;
  std::vector<uint8_t> held_;  // phase 3: 0 free, 1 kept its horizontal position, 2 its start
  // By space slot: flyer index, or -1.
  std::vector<int32_t> flyer_of_;
  // The grid: flyer indices by cell, cells row by row.
  std::vector<uint32_t> cell_start_, cell_cursor_, cell_items_;
  int nx_ = 1, ny_ = 1;
  double inv_cell_ = 1;
  Vec2 origin_ = Vec2::Zero();
  // Per chunk: the obstacles near a flyer.
  std::vector<std::vector<uint32_t>> scratch_;
  std::vector<uint32_t> newly_, retest_, near_;
  double max_radius_ = 0;  // of all flyers ever added (m)
  double drift_ = 0;       // MaxDrift for the current phase
  double dt_ = 0.1;
  int substeps_ = 1;
  Phase phase_ = Phase::kFly;
  std::atomic<bool> overlaps_{false};
};

COLONY_REGISTER_ENGINE(Pointmass3dEngine, "pointmass3d",
                       "flying robots (eye-bots) as point masses, cheap enough for thousands: "
                       "flight computer, gravity, ceiling attachment; they land on the floor and "
                       "objects, stop at walls and never overlap one another",
                       {});

}  // namespace
}  // namespace colony
