// Occlusion tests for the media's sensors: is the straight segment between
// two points (a camera and an LED, a receiver and a sender) blocked by a
// solid body? A medium that needs them keeps an OccluderGrid: every solid
// body's footprint and height span in flat records, filed in a uniform grid
// rebuilt once per tick. A query copies the records around the observer
// into an Occluders list once, then tests any number of segments against
// that short list without touching the space again (reading each
// neighbour's pose and shape from the space cost a cache miss apiece).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/space.h"

namespace colony {

// A solid body as occlusion tests see it. 48 bytes.
struct Occluder {
  double x, y;           // centre of the footprint
  float bound;           // radius of a circle around the centre holding the footprint
  float bottom, top;     // height span (m)
  float half_x, half_y;  // box: half extents in its own frame; cylinder: radius, 0
  float cos_yaw, sin_yaw;
  uint32_t slot;  // the body's slot in the space; boxes have half_y > 0

  // The part [t_in, t_out] of the horizontal ray (ox, oy) + t (dx, dy) (unit
  // direction, t >= 0) inside the footprint; false when missed or grazed.
  bool Crossing(double ox, double oy, double dx, double dy, double& t_in, double& t_out) const {
    const double px = ox - x, py = oy - y;
    if (half_y <= 0) {  // cylinder
      const double b = px * dx + py * dy;
      const double disc = b * b - (px * px + py * py - static_cast<double>(half_x) * half_x);
      if (disc <= 0) return false;
      const double s = std::sqrt(disc);
      t_in = std::max(0.0, -b - s);
      t_out = -b + s;
      return t_out > t_in;
    }
    // Box: slab test in its own frame.
    const double c = cos_yaw, s = sin_yaw;
    const double lo[2] = {c * px + s * py, -s * px + c * py};
    const double ld[2] = {c * dx + s * dy, -s * dx + c * dy};
    const double half[2] = {half_x, half_y};
    double t0 = 0, t1 = 1e300;
    for (int k = 0; k < 2; ++k) {
      if (std::abs(ld[k]) < 1e-15) {
        if (lo[k] <= -half[k] || lo[k] >= half[k]) return false;
        continue;
      }
      double a = (-half[k] - lo[k]) / ld[k];
      double b = (half[k] - lo[k]) / ld[k];
      if (a > b) std::swap(a, b);
      t0 = std::max(t0, a);
      t1 = std::min(t1, b);
      if (t0 >= t1) return false;
    }
    t_in = t0;
    t_out = t1;
    return true;
  }
};

// The solid bodies near one observer (a copy of a few grid cells' records),
// reused from query to query: no allocation once warmed up.
class Occluders {
 public:
  void clear() { items_.clear(); }
  void push_back(const Occluder& o) { items_.push_back(o); }
  size_t size() const { return items_.size(); }
  const Occluder& item(size_t k) const { return items_[k]; }

  // Whether the segment from `a` to `b` passes through a gathered body other
  // than `ignore` (e.g. the LED's owner, the message's sender). A body blocks
  // when, over the stretch where the segment's horizontal projection crosses
  // its footprint, the segment's height range overlaps its [bottom, top].
  bool Blocked(const Vec3& a, const Vec3& b, uint32_t ignore) const {
    double dx = b.x() - a.x(), dy = b.y() - a.y();
    const double length = std::sqrt(dx * dx + dy * dy);
    if (length < 1e-12) return false;
    dx /= length;
    dy /= length;
    const double za = a.z(), slope = (b.z() - za) / length;
    for (const Occluder& o : items_) {
      if (o.slot == ignore) continue;
      // Cheap cull on the bounding circle.
      const double cx = o.x - a.x(), cy = o.y - a.y();
      const double along = cx * dx + cy * dy;
      if (along < -o.bound || along > length + o.bound) continue;
      const double across2 = cx * cx + cy * cy - along * along;
      if (across2 >= static_cast<double>(o.bound) * o.bound) continue;
      double t_in, t_out;
      if (!o.Crossing(a.x(), a.y(), dx, dy, t_in, t_out)) continue;
      t_out = std::min(t_out, length);
      if (t_in >= t_out) continue;
      const double z_in = za + slope * t_in, z_out = za + slope * t_out;
      if (std::max(z_in, z_out) > o.bottom && std::min(z_in, z_out) < o.top) return true;
    }
    return false;
  }

 private:
  std::vector<Occluder> items_;
};

// Every solid body of the space in a uniform grid: each record is filed in
// every cell its footprint's bounding box touches; a query takes it from the
// first of those cells inside the query's box only, so once.
class OccluderGrid {
 public:
  // Rebuilds the grid from the space, with cells of about `cell` metres
  // (enlarged if the arena would need too many).
  void Build(const Space& space, double cell);
  // Appends to `out` the bodies whose footprint may come within `reach` of
  // (x, y) horizontally (their bounding circle does), except `self`.
  void Gather(double x, double y, double reach, uint32_t self, Occluders& out) const {
    if (records_.empty()) return;
    const int cx0 = CellX(x - reach), cx1 = CellX(x + reach);
    const int cy0 = CellY(y - reach), cy1 = CellY(y + reach);
    for (int cy = cy0; cy <= cy1; ++cy) {
      for (int cx = cx0; cx <= cx1; ++cx) {
        const size_t c = static_cast<size_t>(cy) * nx_ + cx;
        for (uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
          // A body in several cells: only in the first one the query covers.
          const int fx = static_cast<int>(first_cell_[k] & 0xFFFF),
                    fy = static_cast<int>(first_cell_[k] >> 16);
          if (cx != std::max(cx0, fx) || cy != std::max(cy0, fy)) continue;
          const Occluder& o = records_[k];
          const double dx = o.x - x, dy = o.y - y, r = reach + o.bound;
          if (o.slot != self && dx * dx + dy * dy < r * r) out.push_back(o);
        }
      }
    }
  }

 private:
  int CellX(double x) const { return ClampedCellIndex((x - min_x_) * inv_cell_, nx_); }
  int CellY(double y) const { return ClampedCellIndex((y - min_y_) * inv_cell_, ny_); }

  std::vector<Occluder> bodies_;  // one per solid body, in slot order
  std::vector<std::pair<float, float>>
      extents_;                       // half extents of each body's footprint's bounding box
  std::vector<Occluder> records_;     // filed by cell, row by row
  std::vector<uint32_t> first_cell_;  // per record: its body's first cell, x | y << 16
  std::vector<uint32_t> cell_start_;  // nx * ny + 1
  std::vector<uint32_t> cursor_;
  double inv_cell_ = 1, min_x_ = 0, min_y_ = 0;
  int nx_ = 0, ny_ = 0;
};

}  // namespace colony
