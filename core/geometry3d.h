// Rays against the solid footprints of the space in 3D: an entity's
// footprint is its shape (box or vertical cylinder) turned about z by its
// yaw and extruded from its base up its height (as the 2D tests of
// core/geometry2d.h, with heights). Sensors that look up or down (a
// hand-bot's grippers) use these.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/geometry2d.h"
#include "core/space.h"

namespace colony {

// Distance along the ray o + t d (d of unit length, t >= 0) to the footprint
// of an entity at `pose` with geometry `g`: 0 when o is inside, kNoHit when
// missed. Entities without a shape are never hit.
inline double RayFootprint3d(const Vec3& o, const Vec3& d, const Pose& pose, const Geometry& g) {
  double t0 = 0, t1 = kNoHit;
  // Between the footprint's bottom and top.
  const double z0 = pose.position.z(), z1 = z0 + g.height();
  if (std::abs(d.z()) < 1e-15) {
    if (o.z() < z0 || o.z() > z1) return kNoHit;
  } else {
    double a = (z0 - o.z()) / d.z(), b = (z1 - o.z()) / d.z();
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
    if (t0 > t1) return kNoHit;
  }
  const Vec2 o2 = o.head<2>(), d2 = d.head<2>();
  if (g.shape == ShapeKind::kBox) {
    const Rect r = RectOf(pose, g);
    const Vec2 lo = r.ToLocal(o2), ld = r.DirToLocal(d2);
    for (int k = 0; k < 2; ++k) {
      if (std::abs(ld[k]) < 1e-15) {
        if (lo[k] < -r.half[k] || lo[k] > r.half[k]) return kNoHit;
        continue;
      }
      double a = (-r.half[k] - lo[k]) / ld[k], b = (r.half[k] - lo[k]) / ld[k];
      if (a > b) std::swap(a, b);
      t0 = std::max(t0, a);
      t1 = std::min(t1, b);
      if (t0 > t1) return kNoHit;
    }
    return t0;
  }
  if (g.shape == ShapeKind::kCylinder) {
    // |o2 + t d2 - c|^2 <= r^2: a t-interval.
    const Vec2 oc = o2 - pose.position.head<2>();
    const double a = d2.squaredNorm(), b = oc.dot(d2), c = oc.squaredNorm() - g.radius * g.radius;
    if (a < 1e-30) {
      if (c > 0) return kNoHit;
    } else {
      const double disc = b * b - a * c;
      if (disc < 0) return kNoHit;
      const double root = std::sqrt(disc);
      t0 = std::max(t0, (-b - root) / a);
      t1 = std::min(t1, (-b + root) / a);
      if (t0 > t1) return kNoHit;
    }
    return t0;
  }
  return kNoHit;
}

// Distance along the ray to the horizontal plane at height z, from either
// side; kNoHit if the ray runs parallel to it or away from it.
inline double RayPlaneZ(const Vec3& o, const Vec3& d, double z) {
  if (std::abs(d.z()) < 1e-15) return kNoHit;
  const double t = (z - o.z()) / d.z();
  return t >= 0 ? t : kNoHit;
}

}  // namespace colony
