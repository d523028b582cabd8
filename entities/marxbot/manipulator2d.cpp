// The marXbot's manipulator in the 2D engines (manipulator2d.h).
#include "entities/marxbot/manipulator2d.h"

#include <algorithm>
#include <cmath>

#include "actuators/manipulator/manipulator_state.h"
#include "core/geometry2d.h"
#include "core/log.h"
#include "core/placement.h"
#include "entities/marxbot/marxbot.h"
#include "entities/objects/pocket.h"

namespace colony {
namespace {

constexpr uint32_t kNone = 0xFFFFFFFFu;

// A step of at most `step` from `from` towards `to`.
double Toward(double from, double to, double step) {
  return std::abs(to - from) <= step ? to : from + std::copysign(step, to - from);
}

void HeadPose(const Pose& robot, const ManipulatorState& m, Pose& head) {
  head.position = robot.position + robot.orientation * Vec3(marxbot::kHeadPivotX, 0, m.elevation);
  head.orientation = robot.orientation * FromYaw(m.rotation);
  if (m.tilt != 0)
    head.orientation = head.orientation * Quat(Eigen::AngleAxisd(m.tilt, Vec3::UnitY()));
}

// The magnet face's centre and its outward normal.
void MagnetFace(const Space& space, uint32_t s, const ManipulatorState& m, Vec3& centre,
                Vec3& normal) {
  Pose head;
  HeadPose(space.pose(s), m, head);
  normal = head.orientation * Vec3::UnitX();
  centre = head.position + 0.5 * marxbot::kHeadDepth * normal;
}

// One tick of motion towards the targets at the head's speeds; the rotation
// the shorter way round. The actuator keeps the targets within the ranges.
void MoveHead(ManipulatorState& m, double dt) {
  const double elevation =
      std::clamp(std::isfinite(m.target_elevation) ? m.target_elevation : m.elevation,
                 m.min_elevation, m.max_elevation);
  m.elevation = Toward(m.elevation, elevation, m.elevation_speed * dt);
  if (std::isfinite(m.target_rotation)) {
    const double step = m.rotation_speed * dt;
    const double to_go = WrapAngle(m.target_rotation - m.rotation);
    m.rotation = std::abs(to_go) <= step ? WrapAngle(m.target_rotation)
                                         : WrapAngle(m.rotation + std::copysign(step, to_go));
  }
  if (std::isfinite(m.target_tilt)) {
    m.tilt = Toward(m.tilt, std::clamp(m.target_tilt, m.min_tilt, m.max_tilt), m.tilt_speed * dt);
  }
}

}  // namespace

void Manipulator2d::Add(Space& space, uint32_t s) {
  if (!space.Get<ManipulatorState>(s)) return;
  slots_.insert(std::lower_bound(slots_.begin(), slots_.end(), s), s);
  if (carry_.size() <= s) carry_.resize(s + 1);
  carry_[s] = Carry{};
}

void Manipulator2d::Leaving(Space& space, uint32_t s, const CarriedHook& carried) {
  auto it = std::lower_bound(slots_.begin(), slots_.end(), s);
  if (it != slots_.end() && *it == s) {
    ManipulatorState& m = *space.Get<ManipulatorState>(s);
    if (m.holding()) Drop(space, s, m, carried, true);
    slots_.erase(it);
    return;
  }
  for (uint32_t r : slots_) {
    ManipulatorState& m = *space.Get<ManipulatorState>(r);
    if (m.held != s) continue;
    m.held = kNone;
    carried(s, false);
    if (PocketState* p = space.Get<PocketState>(s)) p->holder = PocketState::kNobody;
  }
}

void Manipulator2d::Step(Space& space, double dt, const CarriedHook& carried) {
  for (uint32_t s : slots_) {
    ManipulatorState& m = *space.Get<ManipulatorState>(s);
    MoveHead(m, dt);
    m.SwitchMagnet(dt);
    if (m.magnet < 1.0) {
      // A pocket that cannot fall clear yet stays on the magnet.
      if (m.holding() && !Drop(space, s, m, carried, false)) CarryAlong(space, s, m, dt);
      continue;
    }
    if (!m.holding()) Grab(space, s, m, carried);
    if (m.holding()) CarryAlong(space, s, m, dt);
  }
}

bool Manipulator2d::Anchor(const Space& space, uint32_t s, std::string_view name, Pose& pose) {
  const ManipulatorState* m = space.Get<ManipulatorState>(s);
  if (name != ManipulatorState::kHeadAnchor || !m) return false;
  HeadPose(space.pose(s), *m, pose);
  return true;
}

// Takes the pocket the magnet face lies on: the face looking down, its centre
// over the pocket's strip and within kMagnetReach of its top; of several,
// the one whose top is nearest the face (then the lowest slot).
void Manipulator2d::Grab(Space& space, uint32_t s, ManipulatorState& m,
                         const CarriedHook& carried) {
  Vec3 face, normal;
  MagnetFace(space, s, m, face, normal);
  if (normal.z() > -std::cos(marxbot::kMagnetMaxSlant)) return;
  const double reach = 0.5 * pocket::kLength + marxbot::kMagnetStripReach;
  near_.clear();
  space.Gather(face.x() - reach, face.y() - reach, face.x() + reach, face.y() + reach, near_);
  uint32_t best = kNone;
  double best_gap = marxbot::kMagnetReach;
  for (uint32_t o : near_) {
    const PocketState* p = space.Get<PocketState>(o);
    // Not held, and nothing resting on it (a pocket under a heap stays).
    if (!p || p->holder != PocketState::kNobody || p->occlusion > 0) continue;
    const Pose& pose = space.pose(o);
    const Geometry& g = space.geometry(o);
    const double gap = std::abs(face.z() - (pose.position.z() + g.height()));
    if (gap > best_gap || (gap == best_gap && best != kNone && o > best)) continue;
    const Vec2 local = RectOf(pose, g).ToLocal(face.head<2>());
    if (std::abs(local.x()) > 0.5 * g.size.x() || std::abs(local.y()) > marxbot::kMagnetStripReach)
      continue;
    best = o;
    best_gap = gap;
  }
  if (best == kNone) return;
  const double robot_yaw = YawOf(space.pose(s).orientation);
  const Pose& pose = space.pose(best);
  Carry& c = carry_[s];
  c.offset = Eigen::Rotation2Dd(-robot_yaw) * (pose.position.head<2>() - face.head<2>());
  c.yaw = WrapAngle(YawOf(pose.orientation) - robot_yaw);
  m.held = best;
  space.Get<PocketState>(best)->holder = s;
  carried(best, true);
  UpdatePocketOcclusion(space);  // it no longer covers anything
}

// Puts the held pocket where the magnet face keeps it: its top against the
// face (the magnet pulls it there).
void Manipulator2d::CarryAlong(Space& space, uint32_t s, const ManipulatorState& m,
                               double dt) const {
  Vec3 face, normal;
  MagnetFace(space, s, m, face, normal);
  const double robot_yaw = YawOf(space.pose(s).orientation);
  const Carry& c = carry_[s];
  Pose& pose = space.pose(m.held);
  const Vec3 before = pose.position;
  pose.position.head<2>() = face.head<2>() + Eigen::Rotation2Dd(robot_yaw) * c.offset;
  pose.position.z() = face.z() - space.geometry(m.held).height();
  pose.orientation = FromYaw(WrapAngle(robot_yaw + c.yaw));
  space.twist(m.held).linear = (pose.position - before) / dt;
  space.twist(m.held).angular = space.twist(s).angular;
}

// Lets the held pocket go where it is (pushed out from the robot's axis until
// clear of its body, if it would overlap it) and settles it on the heap. A
// pocket that would land on another robot, a wall or any solid thing but
// pockets stays on the magnet, which lets it go once the robot has moved
// clear (a warning the first time).
bool Manipulator2d::Drop(Space& space, uint32_t s, ManipulatorState& m, const CarriedHook& carried,
                         bool forced) {
  const uint32_t held = m.held;
  const Pose& robot = space.pose(s);
  const double radius = space.geometry(s).radius;
  const Geometry& g = space.geometry(held);
  Pose pose = space.pose(held);
  Vec2 out = pose.position.head<2>() - robot.position.head<2>();
  out = out.norm() > 1e-9 ? Vec2(out.normalized())
                          : Vec2((robot.orientation * Vec3::UnitX()).head<2>().normalized());
  for (int k = 0; k < 60 && CircleOverlapsFootprint(robot.position.head<2>(), radius, pose, g); ++k)
    pose.position.head<2>() += 0.005 * out;
  if (!forced) {
    const Vec2 half = FootprintHalfExtents(g, pose.orientation);
    const Vec2 c = pose.position.head<2>();
    near_.clear();
    space.Gather(c.x() - half.x(), c.y() - half.y(), c.x() + half.x(), c.y() + half.y(), near_);
    const Vec3& lo = space.arena_min();
    const Vec3& hi = space.arena_max();
    bool blocked = c.x() - half.x() < lo.x() || c.y() - half.y() < lo.y() ||
                   c.x() + half.x() > hi.x() || c.y() + half.y() > hi.y();
    for (uint32_t o : near_) {
      if (blocked) break;
      if (o == held || o == s || space.Get<PocketState>(o)) continue;
      blocked = FootprintsOverlap(pose, g, space.pose(o), space.geometry(o));
    }
    if (blocked) {
      if (!carry_[s].warned) {
        carry_[s].warned = true;
        LogWarning("robot '" + space.id(s) + "': the magnet let go of pocket '" + space.id(held) +
                   "' over something solid that is not a pocket (a robot, a wall, a landmark); "
                   "it stays on the magnet until it can fall clear (said once per robot)");
      }
      return false;
    }
  }
  m.held = kNone;
  carried(held, false);
  space.pose(held) = pose;
  if (PocketState* p = space.Get<PocketState>(held)) p->holder = PocketState::kNobody;
  SettlePocket(space, held);
  return true;
}

}  // namespace colony
