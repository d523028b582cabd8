// What loop functions draw in the world for people watching a run
// (LoopFunctions::Draw): points, lines, circles and text at world
// coordinates, each with a colour. The live viewer sends them with each
// frame and the off-screen renderer draws them into its frames. Drawing is
// asked for only when something shows it, so a run that nobody watches or
// renders pays nothing for it.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/color.h"
#include "core/math.h"

namespace colony {

class Simulation;

// One call's shapes, kept as flat arrays (a list is reused from frame to
// frame, so drawing allocates only when it grows). Positions in metres,
// world frame; colours RGBA (alpha < 255 blends where the backend can).
class DrawList {
 public:
  struct Point {
    Vec3 position;
    Color color;
    float size;  // diameter in pixels on screen, whatever the distance
  };
  // A polyline: points [first, first + count) of line_points().
  struct Line {
    uint32_t first, count;
    Color color;
    bool closed;  // the last point joins the first
  };
  // A circle in the horizontal plane through its centre.
  struct Circle {
    Vec3 center;
    double radius;  // m
    Color color;
    bool filled;  // a disc; else the outline
  };
  // Text centred above `position` (the point is its bottom middle), a few
  // pixels high whatever the distance.
  struct Text {
    Vec3 position;
    std::string text;
    Color color;
  };

  // The longest text kept (bytes); longer is cut.
  static constexpr size_t kMaxTextBytes = 200;

  void AddPoint(const Vec3& position, Color color, float size = 8) {
    points_.push_back({position, color, size});
  }
  void AddSegment(const Vec3& from, const Vec3& to, Color color) {
    const Vec3 ends[2] = {from, to};
    AddPolyline(ends, color);
  }
  // Nothing is drawn for fewer than two points.
  void AddPolyline(std::span<const Vec3> points, Color color, bool closed = false);
  void AddCircle(const Vec3& center, double radius, Color color, bool filled = false) {
    circles_.push_back({center, radius, color, filled});
  }
  void AddText(const Vec3& position, std::string_view text, Color color = Color::White()) {
    texts_.push_back({position, std::string(text.substr(0, kMaxTextBytes)), color});
  }

  void Clear() {
    points_.clear();
    line_points_.clear();
    lines_.clear();
    circles_.clear();
    texts_.clear();
  }
  bool empty() const {
    return points_.empty() && lines_.empty() && circles_.empty() && texts_.empty();
  }

  const std::vector<Point>& points() const { return points_; }
  const std::vector<Vec3>& line_points() const { return line_points_; }
  const std::vector<Line>& lines() const { return lines_; }
  const std::vector<Circle>& circles() const { return circles_; }
  const std::vector<Text>& texts() const { return texts_; }

 private:
  std::vector<Point> points_;
  std::vector<Vec3> line_points_;
  std::vector<Line> lines_;
  std::vector<Circle> circles_;
  std::vector<Text> texts_;
};

// A sensor that sees a region of the world (a camera): it draws that region
// as it is now (world frame), for the viewer's field-of-view overlay. The
// simulated sensors implement it beside their control interface; viewers
// find it with dynamic_cast from the Sensor.
class FieldOfView {
 public:
  virtual void DrawFieldOfView(const Simulation& sim, DrawList& list) const = 0;

 protected:
  ~FieldOfView() = default;
};

// One ray of a proximity ring, for overlays (world frame, m): from the
// ring to what it hits, or to the end of its range.
struct ProximityRay {
  Vec3 from, to;
  bool hit;
};
// Replaces `rays` with the rays of the proximity ring of robot `slot` (none
// without a ring), cast as the proximity sensor casts them (sensors/
// proximity/proximity_sim.cpp): in the ring's plane, against every solid
// entity (Space::Gather's) but the robot whose height spans that plane, over
// the ring's nominal range. The viewer and the osmesa renderer draw these.
void CastProximityRays(const Simulation& sim, uint32_t slot, std::vector<ProximityRay>& rays);

// Clears `list` and fills it with what every loop functions of `sim` draws
// now (LoopFunctions::Draw, in their order). Throws RuntimeFailure naming
// the loop functions when one throws.
void DrawLoopFunctions(const Simulation& sim, DrawList& list);

}  // namespace colony
