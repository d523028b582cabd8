#include "core/drawing.h"

#include <algorithm>
#include <cmath>
#include <exception>

#include "core/entity_type.h"
#include "core/error.h"
#include "core/geometry2d.h"
#include "core/simulation.h"

namespace colony {

void DrawList::AddPolyline(std::span<const Vec3> points, Color color, bool closed) {
  if (points.size() < 2) return;
  lines_.push_back({static_cast<uint32_t>(line_points_.size()),
                    static_cast<uint32_t>(points.size()), color, closed});
  line_points_.insert(line_points_.end(), points.begin(), points.end());
}

void CastProximityRays(const Simulation& sim, uint32_t slot, std::vector<ProximityRay>& rays) {
  rays.clear();
  const Space& space = sim.space();
  const RingMount* ring = sim.MountsOf(space.HandleOf(slot)).Ring("proximity");
  if (!ring) return;
  const Pose& pose = space.pose(slot);
  const Vec2 c = pose.position.head<2>();
  const double z = pose.position.z() + ring->elevation, reach = ring->radius + ring->range;
  std::vector<uint32_t> near;
  space.Gather(c.x() - reach, c.y() - reach, c.x() + reach, c.y() + reach, near);
  std::erase_if(near, [&](uint32_t o) {
    const double bottom = space.pose(o).position.z();
    return o == slot || !(z >= bottom && z < bottom + space.geometry(o).height());
  });
  const double yaw = YawOf(pose.orientation);
  for (int i = 0; i < ring->count; ++i) {
    const double a = yaw + ring->AngleOf(i);
    const Vec2 dir(std::cos(a), std::sin(a));
    const Vec2 origin = c + ring->radius * dir;
    double best = kNoHit;
    for (uint32_t o : near)
      best = std::min(best, RayFootprint(origin, dir, space.pose(o), space.geometry(o)));
    const Vec2 end = origin + std::min(best, ring->range) * dir;
    rays.push_back(
        {Vec3(origin.x(), origin.y(), z), Vec3(end.x(), end.y(), z), best <= ring->range});
  }
}

void DrawLoopFunctions(const Simulation& sim, DrawList& list) {
  list.Clear();
  for (size_t i = 0; i < sim.loop_functions_count(); ++i) {
    try {
      sim.loop_functions(i).Draw(list);
    } catch (const std::exception& e) {
      throw RuntimeFailure("loop functions '" + sim.loop_functions_info(i).label +
                           "' failed in Draw at tick " + std::to_string(sim.tick()) + ": " +
                           e.what());
    }
  }
}

}  // namespace colony
