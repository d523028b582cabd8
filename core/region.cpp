#include "core/region.h"

#include <algorithm>
#include <sstream>

namespace colony {

namespace {

double Cross(const Vec2& a, const Vec2& b, const Vec2& c) {
  return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
}

// Whether segments ab and cd cross at a point inside both (touching or
// overlapping collinear segments do not count).
bool ProperlyCross(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const double d1 = Cross(c, d, a), d2 = Cross(c, d, b), d3 = Cross(a, b, c), d4 = Cross(a, b, d);
  return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
}

bool OnSegment(const Vec2& p, const Vec2& a, const Vec2& b) {
  return std::abs(Cross(a, b, p)) < 1e-12 && p.x() >= std::min(a.x(), b.x()) - 1e-12 &&
         p.x() <= std::max(a.x(), b.x()) + 1e-12 && p.y() >= std::min(a.y(), b.y()) - 1e-12 &&
         p.y() <= std::max(a.y(), b.y()) + 1e-12;
}

bool Inside2d(const std::vector<Vec2>& v, const Vec2& p) {
  bool inside = false;
  for (size_t i = 0, j = v.size() - 1; i < v.size(); j = i++) {
    if ((v[i].y() > p.y()) != (v[j].y() > p.y()) &&
        p.x() < (v[j].x() - v[i].x()) * (p.y() - v[i].y()) / (v[j].y() - v[i].y()) + v[i].x()) {
      inside = !inside;
    }
  }
  return inside;
}

// Strictly inside: inside and not on any side.
bool StrictlyInside(const std::vector<Vec2>& v, const Vec2& p) {
  for (size_t i = 0, j = v.size() - 1; i < v.size(); j = i++)
    if (OnSegment(p, v[j], v[i])) return false;
  return Inside2d(v, p);
}

}  // namespace

bool Region::Contains(const Vec3& p) const {
  return p.z() >= bottom && p.z() < top && Inside2d(vertices, p.head<2>());
}

bool Region::AxisAlignedBox(Vec2& lo, Vec2& hi) const {
  if (vertices.size() != 4) return false;
  lo = hi = vertices[0];
  for (const Vec2& v : vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  if (!(lo.x() < hi.x() && lo.y() < hi.y())) return false;
  // Every vertex a corner, every side along an axis (so not a bow tie).
  for (size_t i = 0, j = 3; i < 4; j = i++) {
    const Vec2& a = vertices[j];
    const Vec2& b = vertices[i];
    if ((a.x() != lo.x() && a.x() != hi.x()) || (a.y() != lo.y() && a.y() != hi.y())) return false;
    if ((a.x() == b.x()) == (a.y() == b.y())) return false;
  }
  return true;
}

bool Region::Touches(const Vec2& center, const Vec2& half, double z0, double z1) const {
  if (z1 < bottom || z0 >= top) return false;
  const Vec2 lo = center - half, hi = center + half;
  const Vec2 corners[4] = {lo, {hi.x(), lo.y()}, hi, {lo.x(), hi.y()}};
  for (const Vec2& c : corners)
    if (Inside2d(vertices, c)) return true;
  for (const Vec2& v : vertices)
    if (v.x() >= lo.x() && v.x() <= hi.x() && v.y() >= lo.y() && v.y() <= hi.y()) return true;
  for (size_t i = 0, j = vertices.size() - 1; i < vertices.size(); j = i++)
    for (int k = 0; k < 4; ++k)
      if (ProperlyCross(vertices[j], vertices[i], corners[k], corners[(k + 1) % 4])) return true;
  return false;
}

double Region::SignedArea2() const {
  double a = 0;
  for (size_t i = 0, j = vertices.size() - 1; i < vertices.size(); j = i++) {
    a += vertices[j].x() * vertices[i].y() - vertices[i].x() * vertices[j].y();
  }
  return a;
}

std::string Region::Problem() const {
  const size_t n = vertices.size();
  if (n < 3) return "a region needs at least 3 vertices, got " + std::to_string(n);
  // Simple: no two sides meet except neighbours at their shared vertex.
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = i + 1; j < n; ++j) {
      const bool neighbours = j == i + 1 || (i == 0 && j == n - 1);
      const Vec2 &a = vertices[i], &b = vertices[(i + 1) % n], &c = vertices[j],
                 &d = vertices[(j + 1) % n];
      const bool meet =
          ProperlyCross(a, b, c, d) || (!neighbours && (OnSegment(a, c, d) || OnSegment(b, c, d) ||
                                                        OnSegment(c, a, b) || OnSegment(d, a, b)));
      if (meet) {
        std::ostringstream s;
        s << "the polygon is not simple: side " << i + 1 << " and side " << j + 1
          << " cross or touch";
        return s.str();
      }
    }
  }
  const double area2 = SignedArea2();
  if (area2 == 0) return "the polygon has no area";
  if (area2 < 0) return "the vertices are listed clockwise; list them counter-clockwise";
  return "";
}

bool Region::Overlaps(const Region& other) const {
  if (top <= other.bottom || other.top <= bottom) return false;
  const auto& a = vertices;
  const auto& b = other.vertices;
  // If the interiors share area, the shared part has a corner at a vertex of
  // either polygon or where two sides cross; just beside that corner lie
  // points strictly inside both. Probe around every such candidate.
  std::vector<Vec2> corners(a.begin(), a.end());
  corners.insert(corners.end(), b.begin(), b.end());
  for (size_t i = 0, j = a.size() - 1; i < a.size(); j = i++) {
    for (size_t k = 0, l = b.size() - 1; k < b.size(); l = k++) {
      const Vec2 r = a[i] - a[j], q = b[k] - b[l];
      const double denom = r.x() * q.y() - r.y() * q.x();
      if (denom == 0) continue;
      const Vec2 d = b[l] - a[j];
      const double t = (d.x() * q.y() - d.y() * q.x()) / denom;
      const double u = (d.x() * r.y() - d.y() * r.x()) / denom;
      if (t >= 0 && t <= 1 && u >= 0 && u <= 1) corners.push_back(a[j] + t * r);
    }
  }
  double scale = 0;
  for (const Vec2& p : corners) scale = std::max(scale, p.cwiseAbs().maxCoeff());
  const double eps = 1e-7 * std::max(scale, 1.0);
  constexpr int kDirections = 32;
  for (const Vec2& p : corners) {
    for (int k = 0; k < kDirections; ++k) {
      const double angle = 2 * M_PI * (k + 0.5) / kDirections;
      const Vec2 probe = p + eps * Vec2(std::cos(angle), std::sin(angle));
      if (StrictlyInside(a, probe) && StrictlyInside(b, probe)) return true;
    }
  }
  return false;
}

}  // namespace colony
