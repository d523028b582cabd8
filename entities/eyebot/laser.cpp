// The eye-bot's laser pointer: where its beam first meets the ground (the
// floor, or a ditch's bottom or wall) or a solid entity. Read only, so the
// LED medium, cameras and renderers may call it from several threads.
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/geometry3d.h"
#include "core/space.h"
#include "entities/eyebot/eyebot.h"

namespace colony {
namespace {

// Distance along the ray o + t d (unit d) at which it leaves the rectangle
// of `ditch` horizontally (kNoHit if it never does: a vertical ray).
double LeavesDitch(const Ditch& ditch, const Vec3& o, const Vec3& d) {
  double t = kNoHit;
  if (d.x() > 0) t = std::min(t, (ditch.max_x - o.x()) / d.x());
  if (d.x() < 0) t = std::min(t, (ditch.min_x - o.x()) / d.x());
  if (d.y() > 0) t = std::min(t, (ditch.max_y - o.y()) / d.y());
  if (d.y() < 0) t = std::min(t, (ditch.min_y - o.y()) / d.y());
  return std::max(t, 0.0);
}

// Distance along the ray o + t d (unit d) to the ground: the floor at height
// z0, or, where it falls into a ditch, the ditch's bottom or the wall where
// it leaves the ditch (on into a neighbouring ditch). kNoHit if it misses.
double GroundHit(const Floor& floor, double z0, const Vec3& o, const Vec3& d) {
  const Ditch* ditch = nullptr;
  if (o.z() >= z0) {
    const double t = RayPlaneZ(o, d, z0);
    if (t == kNoHit) return kNoHit;
    const Vec3 p = o + t * d;
    ditch = floor.DitchAt(p.x(), p.y());
    if (!ditch) return t;
  } else {
    ditch = floor.DitchAt(o.x(), o.y());
    if (!ditch) return 0;  // under solid ground
  }
  // Inside a ditch (below the floor): its bottom, or where the ray leaves it.
  for (size_t k = 0; k < floor.ditches().size(); ++k) {
    const double bottom = RayPlaneZ(o, d, z0 - ditch->depth);
    const double wall = LeavesDitch(*ditch, o, d);
    const double top = d.z() > 0 ? RayPlaneZ(o, d, z0) : kNoHit;  // climbs out of it
    if (top < wall && top < bottom) return kNoHit;
    if (bottom <= wall) return bottom;
    const Vec3 beyond = o + (wall + 1e-9) * d;
    const Ditch* next = floor.DitchAt(beyond.x(), beyond.y());
    if (!next || next == ditch) return wall;
    ditch = next;
  }
  return kNoHit;
}

}  // namespace

std::optional<LaserSpot> CastLaser(const Space& space, uint32_t slot) {
  const PanTiltState* unit = space.Get<PanTiltState>(slot);
  if (!unit || !unit->laser_on) return std::nullopt;
  const Pose head = PanTiltFrame(space.pose(slot), *unit);
  const Vec3& o = head.position;
  const Vec3 d = head.orientation * Vec3::UnitX();
  LaserSpot spot;
  double best = GroundHit(space.floor(), space.arena_min().z(), o, d);
  // The solid entities near the beam, up to the ground or the range.
  const double reach = std::min(best, unit->laser_range);
  const Vec3 end = o + reach * d;
  static thread_local std::vector<uint32_t> near;
  near.clear();
  space.Gather(std::min(o.x(), end.x()), std::min(o.y(), end.y()), std::max(o.x(), end.x()),
               std::max(o.y(), end.y()), near);
  for (uint32_t e : near) {
    if (e == slot) continue;
    const double t = RayFootprint3d(o, d, space.pose(e), space.geometry(e));
    if (t < best) {
      best = t;
      spot.entity = e;
    }
  }
  if (best > unit->laser_range) return std::nullopt;
  spot.point = o + best * d;
  spot.distance = best;
  return spot;
}

}  // namespace colony
