// Groups of robots for swarm metrics (flocking_metrics, aggregation_metrics):
// the connected components of the graph that links two robots whose centres
// are closer than a link distance, found with the space's grid (a query
// costs what is near) and a union-find. Also each robot's nearest neighbour.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/space.h"

namespace colony::swarm {

struct GroupStats {
  size_t robots = 0;
  size_t groups = 0;        // components of >= min_size robots
  size_t largest = 0;       // robots in the largest component
  size_t grouped = 0;       // robots in components of >= min_size robots
  double mean_nearest = 0;  // mean distance to the nearest other robot (m); 0 with < 2 robots
};

class GroupFinder {
 public:
  // Robots (entities flagged kRobot) of `space` as of its last index update.
  // With `nearest`, also the mean nearest-neighbour distance.
  GroupStats Find(const Space& space, double link, size_t min_size, bool nearest) {
    robots_.clear();
    rank_.assign(space.slots(), kNone);
    for (uint32_t i = 0; i < space.slots(); ++i) {
      if (!space.alive(i) || !(space.flags(i) & kRobot)) continue;
      rank_[i] = static_cast<uint32_t>(robots_.size());
      robots_.push_back(i);
    }
    GroupStats stats;
    stats.robots = robots_.size();
    parent_.resize(robots_.size());
    for (uint32_t k = 0; k < parent_.size(); ++k) parent_[k] = k;

    // Link every pair closer than `link`.
    for (uint32_t k = 0; k < robots_.size(); ++k) {
      const Vec3& p = space.pose(robots_[k]).position;
      near_.clear();
      space.Gather(p.x() - link, p.y() - link, p.x() + link, p.y() + link, near_);
      for (uint32_t j : near_) {
        if (rank_[j] == kNone || rank_[j] <= k) continue;
        if ((space.pose(j).position - p).head<2>().squaredNorm() < link * link) Union(k, rank_[j]);
      }
    }
    size_.assign(robots_.size(), 0);
    for (uint32_t k = 0; k < robots_.size(); ++k) ++size_[Root(k)];
    for (uint32_t k = 0; k < robots_.size(); ++k) {
      if (size_[k] < std::max<size_t>(min_size, 1)) continue;
      ++stats.groups;
      stats.grouped += size_[k];
      stats.largest = std::max<size_t>(stats.largest, size_[k]);
    }

    if (nearest && robots_.size() >= 2) {
      const Vec3 extent = space.arena_max() - space.arena_min();
      const double farthest = extent.head<2>().norm();
      double sum = 0;
      for (uint32_t k = 0; k < robots_.size(); ++k) sum += Nearest(space, k, link, farthest);
      stats.mean_nearest = sum / static_cast<double>(robots_.size());
    }
    return stats;
  }

 private:
  static constexpr uint32_t kNone = 0xFFFFFFFFu;

  // Distance from robot k to the nearest other robot: searched in a square
  // of half-side r, doubled until one is found within r.
  double Nearest(const Space& space, uint32_t k, double r, double farthest) {
    const Vec3& p = space.pose(robots_[k]).position;
    for (r = std::max(r, 0.1);; r *= 2) {
      near_.clear();
      space.Gather(p.x() - r, p.y() - r, p.x() + r, p.y() + r, near_);
      double best = r * r;
      bool found = false;
      for (uint32_t j : near_) {
        if (rank_[j] == kNone || rank_[j] == k) continue;
        const double d2 = (space.pose(j).position - p).head<2>().squaredNorm();
        if (d2 <= best) {
          best = d2;
          found = true;
        }
      }
      if (found || r > farthest) return found ? std::sqrt(best) : 0.0;
    }
  }
  uint32_t Root(uint32_t k) {
    while (parent_[k] != k) k = parent_[k] = parent_[parent_[k]];
    return k;
  }
  void Union(uint32_t a, uint32_t b) {
    a = Root(a);
    b = Root(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

  std::vector<uint32_t> robots_, rank_, parent_, near_;
  std::vector<size_t> size_;
};

}  // namespace colony::swarm
