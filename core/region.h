// The part of the space an engine simulates: a vertical prism over a simple
// polygon whose sides are given counter-clockwise, between two heights.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "core/math.h"

namespace colony {

struct Region {
  std::vector<Vec2> vertices;  // counter-clockwise, at least 3
  double bottom = -std::numeric_limits<double>::infinity();
  double top = std::numeric_limits<double>::infinity();

  // Whether p is inside (crossing-number rule: a point on a side shared by
  // two regions belongs to exactly one of them).
  bool Contains(const Vec3& p) const;
  // Whether the axis-aligned rectangle center +- half, spanning heights
  // [z0, z1], overlaps the region.
  bool Touches(const Vec2& center, const Vec2& half, double z0, double z1) const;
  // Twice the signed area: > 0 when the vertices are counter-clockwise.
  double SignedArea2() const;
  // An empty string when the polygon is simple and counter-clockwise,
  // otherwise what is wrong with it.
  std::string Problem() const;
  // Whether two regions share interior (sharing sides does not count).
  bool Overlaps(const Region& other) const;
  // Whether the polygon is a rectangle with sides along the axes, and then
  // its corners: Contains is then exactly lo <= p < hi in x and y (and the
  // heights), which is what the crossing-number rule gives for it.
  bool AxisAlignedBox(Vec2& lo, Vec2& hi) const;
  // Contains for such a rectangle, with the corners AxisAlignedBox gave.
  bool BoxContains(const Vec2& lo, const Vec2& hi, const Vec3& p) const {
    return p.z() >= bottom && p.z() < top && p.x() >= lo.x() && p.x() < hi.x() && p.y() >= lo.y() &&
           p.y() < hi.y();
  }
};

}  // namespace colony
