#include "core/drawing.h"

#include <exception>

#include "core/error.h"
#include "core/simulation.h"

namespace colony {

void DrawList::AddPolyline(std::span<const Vec3> points, Color color, bool closed) {
  if (points.size() < 2) return;
  lines_.push_back({static_cast<uint32_t>(line_points_.size()),
                    static_cast<uint32_t>(points.size()), color, closed});
  line_points_.insert(line_points_.end(), points.begin(), points.end());
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
