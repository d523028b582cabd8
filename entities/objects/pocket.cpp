// The heap model of pockets (pocket.h; entities/objects/README.md,
// "Pockets"). A pocket put down rests level on the highest pocket its
// footprint overlaps (or the floor); occlusion is sampled on its top. Both
// run only when a pocket is put down or picked up, never per tick, so they
// scan every pocket plainly: a structure holds about a hundred.
#include "entities/objects/pocket.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "core/geometry2d.h"
#include "core/placement.h"

namespace colony {
namespace {

// Pockets whose footprints touch without overlapping do not stack.
constexpr double kHeightTolerance = 1e-9;  // m

bool Resting(const Space& space, const ComponentPool<PocketState>& pool, uint32_t k) {
  const uint32_t owner = pool.owner(k);
  return owner != ComponentPoolBase::kNoOwner && space.alive(owner) &&
         pool[k].holder == PocketState::kNobody;
}

// Whether the footprints of pockets a and b overlap, whatever their heights.
bool FootprintsCross(const Space& space, uint32_t a, uint32_t b) {
  Pose pa = space.pose(a), pb = space.pose(b);
  const double reach = space.geometry(a).BoundingRadius() + space.geometry(b).BoundingRadius();
  if ((pa.position.head<2>() - pb.position.head<2>()).squaredNorm() >= reach * reach) return false;
  pa.position.z() = pb.position.z() = 0;
  return FootprintsOverlap(pa, space.geometry(a), pb, space.geometry(b));
}

// Puts pocket `slot` down level on the highest settled resting pocket its
// footprint overlaps, or on the floor; returns its bottom's height.
double PutDown(Space& space, uint32_t slot) {
  const ComponentPool<PocketState>& pool = space.Pool<PocketState>();
  const double floor = space.arena_min().z();
  double bottom = floor;
  for (uint32_t k = 0; k < pool.size(); ++k) {
    const uint32_t other = pool.owner(k);
    if (other == slot || !Resting(space, pool, k) || !pool[k].settled) continue;
    if (!FootprintsCross(space, slot, other)) continue;
    bottom = std::max(bottom, space.pose(other).position.z() + space.geometry(other).height());
  }
  Pose& pose = space.pose(slot);
  pose.orientation = FromYaw(YawOf(pose.orientation));
  pose.position.z() = bottom;
  space.twist(slot) = Twist{};
  space.Get<PocketState>(slot)->settled = true;
  return bottom - floor;
}

// Whether the point `local` (in the frame of the pocket of footprint `rect`)
// lies under one of the footprints `above`.
bool Covered(const Rect& rect, const Vec2& local, const std::vector<Rect>& above) {
  const Vec2 p = rect.center + Vec2(rect.cos_yaw * local.x() - rect.sin_yaw * local.y(),
                                    rect.sin_yaw * local.x() + rect.cos_yaw * local.y());
  return std::any_of(above.begin(), above.end(), [&](const Rect& r) {
    const Vec2 q = r.ToLocal(p);
    return std::abs(q.x()) < r.half.x() && std::abs(q.y()) < r.half.y();
  });
}

}  // namespace

double SettlePocket(Space& space, uint32_t slot) {
  // Pockets added since the last tick lie under it first.
  SettlePendingPockets(space);
  const double height = PutDown(space, slot);
  UpdatePocketOcclusion(space);
  return height;
}

void UpdatePocketOcclusion(Space& space) {
  ComponentPool<PocketState>& pool = space.Pool<PocketState>();
  constexpr int kSamples = pocket::kSamplesX * pocket::kSamplesY;
  std::vector<Rect> above;
  for (uint32_t k = 0; k < pool.size(); ++k) {
    if (pool.owner(k) == ComponentPoolBase::kNoOwner) continue;
    PocketState& state = pool[k];
    state.occlusion = state.seen_x = state.seen_y = 0;
    if (!Resting(space, pool, k)) continue;
    const uint32_t s = pool.owner(k);
    const Pose& pose = space.pose(s);
    const Geometry& g = space.geometry(s);
    const double top = pose.position.z() + g.height();
    const Rect rect = RectOf(pose, g);
    // The pockets above its top whose footprints cross its own.
    above.clear();
    for (uint32_t j = 0; j < pool.size(); ++j) {
      const uint32_t o = pool.owner(j);
      if (o == s || !Resting(space, pool, j)) continue;
      if (space.pose(o).position.z() < top - kHeightTolerance) continue;
      if (FootprintsCross(space, s, o)) above.push_back(RectOf(space.pose(o), space.geometry(o)));
    }
    if (above.empty()) continue;
    // The sample points: centres of a kSamplesX x kSamplesY grid on its top
    // (local x, y); the uncovered ones are kept in `open`.
    std::array<Vec2, kSamples> open;
    int open_count = 0;
    Vec2 centroid = Vec2::Zero();
    for (int i = 0; i < pocket::kSamplesX; ++i) {
      for (int j = 0; j < pocket::kSamplesY; ++j) {
        const Vec2 local(((i + 0.5) / pocket::kSamplesX - 0.5) * g.size.x(),
                         ((j + 0.5) / pocket::kSamplesY - 0.5) * g.size.y());
        if (Covered(rect, local, above)) continue;
        open[open_count++] = local;
        centroid += local;
      }
    }
    state.occlusion = static_cast<double>(kSamples - open_count) / kSamples;
    if (open_count == 0) continue;
    // Where a camera sees it: the centroid of the uncovered part, or, when
    // that lies under a pocket (a pocket across its middle), the uncovered
    // sample nearest to it.
    centroid /= open_count;
    Vec2 seen = centroid;
    if (Covered(rect, centroid, above)) {
      seen = *std::min_element(open.begin(), open.begin() + open_count,
                               [&](const Vec2& a, const Vec2& b) {
                                 return (a - centroid).squaredNorm() < (b - centroid).squaredNorm();
                               });
    }
    state.seen_x = seen.x();
    state.seen_y = seen.y();
  }
}

int SettlePendingPockets(Space& space) {
  ComponentPool<PocketState>& pool = space.Pool<PocketState>();
  std::vector<uint32_t> pending;
  for (uint32_t k = 0; k < pool.size(); ++k) {
    if (!pool[k].settled && Resting(space, pool, k)) pending.push_back(pool.owner(k));
  }
  if (pending.empty()) return 0;
  // Lowest first, so that a pocket declared over another rests on it
  // whatever the order of the file.
  std::sort(pending.begin(), pending.end(), [&](uint32_t a, uint32_t b) {
    const double za = space.pose(a).position.z(), zb = space.pose(b).position.z();
    return za != zb ? za < zb : a < b;
  });
  for (uint32_t s : pending) PutDown(space, s);
  UpdatePocketOcclusion(space);
  return static_cast<int>(pending.size());
}

}  // namespace colony
