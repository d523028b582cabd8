// The uniform grid a medium indexes its points with: cells over the arena's
// floor, and the points kept in one flat array sorted by cell (counting
// sort, stable), so that a query reads a few contiguous runs per grid row.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/space.h"

namespace colony {

class CellGrid {
 public:
  // Cells at least `cell` wide over the arena, widened until the table
  // holds no more than max(4096, 4 x count) cells.
  void Configure(const Space& space, double cell, size_t count) {
    const Vec3& lo = space.arena_min();
    const Vec3& hi = space.arena_max();
    const double wx = std::max(hi.x() - lo.x(), 1e-9), wy = std::max(hi.y() - lo.y(), 1e-9);
    const double limit = std::max<double>(4096, 4.0 * count);
    while (std::ceil(wx / cell) * std::ceil(wy / cell) > limit) cell *= 1.25;
    const int nx = static_cast<int>(std::ceil(wx / cell)),
              ny = static_cast<int>(std::ceil(wy / cell));
    if (nx == nx_ && ny == ny_ && cell == cell_ && min_x_ == lo.x() && min_y_ == lo.y()) return;
    cell_ = cell;
    inv_cell_ = 1.0 / cell;
    min_x_ = lo.x();
    min_y_ = lo.y();
    nx_ = nx;
    ny_ = ny;
    start_.assign(static_cast<size_t>(nx_) * ny_ + 1, 0);
  }
  double cell_size() const { return cell_; }
  // The cell of (x, y); positions outside the arena are in its edge cells.
  uint32_t CellOf(double x, double y) const {
    return static_cast<uint32_t>(CellY(y)) * nx_ + CellX(x);
  }

  // Sorts `unsorted` into `sorted` by the cells in `cell_of` (same order
  // within a cell).
  template <class T>
  void Sort(const std::vector<T>& unsorted, const std::vector<uint32_t>& cell_of, size_t n,
            std::vector<T>& sorted) {
    std::fill(start_.begin(), start_.end(), 0u);
    for (size_t k = 0; k < n; ++k) ++start_[cell_of[k] + 1];
    for (size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    cursor_.assign(start_.begin(), start_.end() - 1);
    sorted.resize(n);
    for (size_t k = 0; k < n; ++k) sorted[cursor_[cell_of[k]]++] = unsorted[k];
  }

  // Calls visit(begin, end) for the runs [begin, end) of sorted indices that
  // together hold every point within `reach` horizontally of (x, y) (and
  // others near it), grid row by grid row.
  template <class Visit>
  void ForEachRun(double x, double y, double reach, Visit&& visit) const {
    const int cx0 = CellX(x - reach), cx1 = CellX(x + reach);
    const int cy0 = CellY(y - reach), cy1 = CellY(y + reach);
    for (int cy = cy0; cy <= cy1; ++cy) {
      const size_t row = static_cast<size_t>(cy) * nx_;
      const uint32_t begin = start_[row + cx0], end = start_[row + cx1 + 1];
      if (begin < end) visit(begin, end);
    }
  }

 private:
  int CellX(double x) const { return ClampedCellIndex((x - min_x_) * inv_cell_, nx_); }
  int CellY(double y) const { return ClampedCellIndex((y - min_y_) * inv_cell_, ny_); }

  double cell_ = 0, inv_cell_ = 0, min_x_ = 0, min_y_ = 0;
  int nx_ = 0, ny_ = 0;
  std::vector<uint32_t> start_;   // nx * ny + 1
  std::vector<uint32_t> cursor_;  // scratch of Sort
};

}  // namespace colony
