#include "media/occlusion.h"

namespace colony {

void OccluderGrid::Build(const Space& space, double cell) {
  // The bodies, in slot order.
  bodies_.clear();
  extents_.clear();
  for (uint32_t s = 0; s < space.slots(); ++s) {
    if (!space.alive(s) || !(space.flags(s) & kSolid)) continue;
    const Geometry& g = space.geometry(s);
    if (g.shape == ShapeKind::kNone) continue;
    const Pose& p = space.pose(s);
    Occluder o{};
    o.x = p.position.x();
    o.y = p.position.y();
    o.bound = static_cast<float>(g.BoundingRadius());
    o.bottom = static_cast<float>(p.position.z());
    o.top = static_cast<float>(p.position.z() + g.height());
    o.slot = s;
    if (g.shape == ShapeKind::kBox) {
      const double yaw = YawOf(p.orientation);
      o.half_x = static_cast<float>(0.5 * g.size.x());
      o.half_y = static_cast<float>(0.5 * g.size.y());
      o.cos_yaw = static_cast<float>(std::cos(yaw));
      o.sin_yaw = static_cast<float>(std::sin(yaw));
    } else {
      o.half_x = static_cast<float>(g.radius);
      o.half_y = 0;
      o.cos_yaw = 1;
      o.sin_yaw = 0;
    }
    bodies_.push_back(o);
    const Vec2 half = FootprintHalfExtents(g, p.orientation);
    extents_.push_back({static_cast<float>(half.x()), static_cast<float>(half.y())});
  }

  // The grid over the arena; cells grow when there would be too many, or
  // more than 65536 along a side (first_cell_ packs a cell in 16 + 16 bits).
  const Vec3& lo = space.arena_min();
  const Vec3& hi = space.arena_max();
  const double wx = std::max(hi.x() - lo.x(), 1e-9), wy = std::max(hi.y() - lo.y(), 1e-9);
  const double limit = std::max<double>(4096, 4.0 * bodies_.size());
  constexpr double kMaxSide = 65536;
  while (std::ceil(wx / cell) * std::ceil(wy / cell) > limit || std::ceil(wx / cell) > kMaxSide ||
         std::ceil(wy / cell) > kMaxSide) {
    cell *= 1.25;
  }
  nx_ = static_cast<int>(std::ceil(wx / cell));
  ny_ = static_cast<int>(std::ceil(wy / cell));
  inv_cell_ = 1.0 / cell;
  min_x_ = lo.x();
  min_y_ = lo.y();
  cell_start_.assign(static_cast<size_t>(nx_) * ny_ + 1, 0);

  // Counting sort: each body in every cell its footprint's bounding box
  // touches, remembering the box's first cell (see Gather).
  auto for_each_cell = [&](size_t b, auto&& f) {
    const Occluder& o = bodies_[b];
    const int x0 = CellX(o.x - extents_[b].first), x1 = CellX(o.x + extents_[b].first);
    const int y0 = CellY(o.y - extents_[b].second), y1 = CellY(o.y + extents_[b].second);
    const uint32_t first = static_cast<uint32_t>(x0) | static_cast<uint32_t>(y0) << 16;
    for (int cy = y0; cy <= y1; ++cy) {
      for (int cx = x0; cx <= x1; ++cx) f(static_cast<size_t>(cy) * nx_ + cx, first);
    }
  };
  for (size_t b = 0; b < bodies_.size(); ++b)
    for_each_cell(b, [&](size_t c, uint32_t) { ++cell_start_[c + 1]; });
  for (size_t c = 1; c < cell_start_.size(); ++c) cell_start_[c] += cell_start_[c - 1];
  cursor_.assign(cell_start_.begin(), cell_start_.end() - 1);
  records_.resize(cell_start_.back());
  first_cell_.resize(cell_start_.back());
  for (size_t b = 0; b < bodies_.size(); ++b) {
    for_each_cell(b, [&](size_t c, uint32_t first) {
      const uint32_t at = cursor_[c]++;
      records_[at] = bodies_[b];
      first_cell_[at] = first;
    });
  }
}

}  // namespace colony
