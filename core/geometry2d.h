// Planar intersection tests used by the 2D engines and by ray sensors. The
// caller checks the height ranges; these work on the footprints.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/space.h"

namespace colony {

inline constexpr double kNoHit = std::numeric_limits<double>::infinity();

// Distance along the ray o + t d (d of unit length) to the circle (c, r):
// 0 when o is inside, kNoHit when missed.
inline double RayCircle(const Vec2& o, const Vec2& d, const Vec2& c, double r) {
  const Vec2 oc = o - c;
  const double cc = oc.squaredNorm() - r * r;
  if (cc <= 0) return 0;
  const double b = oc.dot(d);
  if (b >= 0) return kNoHit;
  const double disc = b * b - cc;
  if (disc < 0) return kNoHit;
  return -b - std::sqrt(disc);
}

// An oriented rectangle: centre, half extents, and the cosine/sine of its yaw.
struct Rect {
  Vec2 center;
  Vec2 half;
  double cos_yaw = 1, sin_yaw = 0;
  Vec2 ToLocal(const Vec2& p) const {
    const Vec2 q = p - center;
    return Vec2(cos_yaw * q.x() + sin_yaw * q.y(), -sin_yaw * q.x() + cos_yaw * q.y());
  }
  Vec2 DirToLocal(const Vec2& d) const {
    return Vec2(cos_yaw * d.x() + sin_yaw * d.y(), -sin_yaw * d.x() + cos_yaw * d.y());
  }
};

// Distance along the ray to the rectangle (slab test): 0 inside, kNoHit missed.
inline double RayRect(const Vec2& o, const Vec2& d, const Rect& r) {
  const Vec2 lo = r.ToLocal(o);
  const Vec2 ld = r.DirToLocal(d);
  double t0 = 0, t1 = kNoHit;
  for (int k = 0; k < 2; ++k) {
    if (std::abs(ld[k]) < 1e-15) {
      if (lo[k] < -r.half[k] || lo[k] > r.half[k]) return kNoHit;
      continue;
    }
    double a = (-r.half[k] - lo[k]) / ld[k];
    double b = (r.half[k] - lo[k]) / ld[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
    if (t0 > t1) return kNoHit;
  }
  return t0;
}

// Whether a circle overlaps the rectangle (touching is not overlapping).
inline bool CircleOverlapsRect(const Vec2& p, double radius, const Rect& r) {
  const Vec2 lp = r.ToLocal(p);
  const Vec2 nearest(std::clamp(lp.x(), -r.half.x(), r.half.x()),
                     std::clamp(lp.y(), -r.half.y(), r.half.y()));
  return (lp - nearest).squaredNorm() < radius * radius;
}

inline Rect RectOf(const Pose& pose, const Geometry& g) {
  const double yaw = YawOf(pose.orientation);
  return Rect{pose.position.head<2>(), 0.5 * g.size.head<2>(), std::cos(yaw), std::sin(yaw)};
}

// The footprint of an entity made ready for rays: a box's rectangle (its
// yaw's atan2, cosine and sine) is made once, for a sensor that casts many
// rays at it.
struct Footprint {
  ShapeKind shape = ShapeKind::kNone;
  Rect rect;          // a box's; for a cylinder only rect.center
  double radius = 0;  // a cylinder's

  static Footprint Of(const Pose& pose, const Geometry& g) {
    Footprint f;
    f.shape = g.shape;
    if (g.shape == ShapeKind::kBox) {
      f.rect = RectOf(pose, g);
    } else {
      f.rect.center = pose.position.head<2>();
      f.radius = g.radius;
    }
    return f;
  }
  // Distance along the ray o + t d (d of unit length): 0 when o is inside,
  // kNoHit when missed.
  double Ray(const Vec2& o, const Vec2& d) const {
    if (shape == ShapeKind::kBox) return RayRect(o, d, rect);
    if (shape == ShapeKind::kCylinder) return RayCircle(o, d, rect.center, radius);
    return kNoHit;
  }
};

// Distance along a horizontal ray to the footprint of an entity.
inline double RayFootprint(const Vec2& o, const Vec2& d, const Pose& pose, const Geometry& g) {
  return Footprint::Of(pose, g).Ray(o, d);
}

// Whether a circle at p overlaps the footprint of an entity.
inline bool CircleOverlapsFootprint(const Vec2& p, double radius, const Pose& pose,
                                    const Geometry& g) {
  if (g.shape == ShapeKind::kBox) return CircleOverlapsRect(p, radius, RectOf(pose, g));
  if (g.shape == ShapeKind::kCylinder) {
    const double rr = radius + g.radius;
    return (p - pose.position.head<2>()).squaredNorm() < rr * rr;
  }
  return false;
}

}  // namespace colony
