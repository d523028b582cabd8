// What researchers ask to see over a frame: recent paths (trails), the rays
// of proximity sensors, robot ids.
#pragma once

#include <cstdint>
#include <deque>
#include <vector>

#include "core/drawing.h"
#include "core/math.h"
#include "render/osmesa/image.h"
#include "render/osmesa/scene.h"
#include "render/osmesa/view.h"

namespace colony {
class Simulation;
}

namespace colony::render {

// The last `length` positions of every movable entity, recorded each tick.
class Trails {
 public:
  explicit Trails(int length) : length_(length) {}
  void Record(const Space& space);
  // Lines on the floor, fading out towards the oldest position.
  void AddTo(const Space& space, SceneBatch& batch) const;

 private:
  struct Trail {
    uint32_t generation = 0;
    std::deque<Eigen::Vector2f> points;
  };
  int length_;
  std::vector<Trail> trails_;  // by space slot
};

// One line per proximity sensor of the robot in `slot` (if it has a
// proximity ring): to the nearest hit within the ring's nominal range, or
// over the whole range when nothing is in it.
void AddProximityRays(const Simulation& sim, uint32_t slot, SceneBatch& batch);

// What loop functions drew (core/drawing.h): lines and circles into the
// batch (a circle as 64 sides), raised 1 mm so that shapes on the floor
// stay above it.
void AddDrawing(const DrawList& drawing, SceneBatch& batch);
// Points (squares of their size) and text, over the finished image where
// `view` sees them.
void DrawPointsAndText(const DrawList& drawing, const View& view, Image& image);

// Writes each robot's id above it.
void DrawRobotIds(const Space& space, const View& view, Image& image);

}  // namespace colony::render
