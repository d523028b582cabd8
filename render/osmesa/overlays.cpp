#include "render/osmesa/overlays.h"

#include <algorithm>
#include <cmath>

#include "core/simulation.h"
#include "render/osmesa/font.h"

namespace colony::render {

void Trails::Record(const Space& space) {
  if (trails_.size() < space.slots()) trails_.resize(space.slots());
  for (uint32_t i = 0; i < space.slots(); ++i) {
    Trail& t = trails_[i];
    const EntityHandle h = space.HandleOf(i);
    if (!space.alive(i) || !space.movable(i)) {
      t.points.clear();
      continue;
    }
    if (t.generation != h.generation) t.points.clear();
    t.generation = h.generation;
    t.points.push_back(space.pose(i).position.head<2>().cast<float>());
    if (static_cast<int>(t.points.size()) > length_) t.points.pop_front();
  }
}

void Trails::AddTo(const Space& space, SceneBatch& batch) const {
  const double z = space.arena_min().z();
  for (const Trail& t : trails_) {
    const size_t n = t.points.size();
    for (size_t k = 1; k < n; ++k) {
      auto color = [n](size_t at) {
        return Color{30, 110, 230, static_cast<uint8_t>(220 * at / (n - 1))};
      };
      const Eigen::Vector2f& a = t.points[k - 1];
      const Eigen::Vector2f& b = t.points[k];
      AddLine(batch.wide_floor_lines, Vec3(a.x(), a.y(), z), Vec3(b.x(), b.y(), z), color(k - 1),
              color(k));
    }
  }
}

void AddProximityRays(const Simulation& sim, uint32_t slot, SceneBatch& batch) {
  static thread_local std::vector<ProximityRay> rays;
  CastProximityRays(sim, slot, rays);
  const Color free{40, 200, 240, 150}, hit{255, 40, 160, 230};
  for (const ProximityRay& r : rays) {
    const Color color = r.hit ? hit : free;
    AddLine(batch.lines, r.from, r.to, color, color);
  }
}

void AddDrawing(const DrawList& drawing, SceneBatch& batch) {
  const Vec3 lift(0, 0, 1e-3);
  const auto& points = drawing.line_points();
  for (const DrawList::Line& line : drawing.lines()) {
    const uint32_t end = line.first + line.count;
    for (uint32_t k = line.first + 1; k < end; ++k) {
      AddLine(batch.drawn_lines, points[k - 1] + lift, points[k] + lift, line.color, line.color);
    }
    if (line.closed && line.count > 2) {
      AddLine(batch.drawn_lines, points[end - 1] + lift, points[line.first] + lift, line.color,
              line.color);
    }
  }
  constexpr int kSides = 64;
  for (const DrawList::Circle& c : drawing.circles()) {
    const Vec3 center = c.center + lift;
    auto rim = [&](int k) -> Vec3 {
      const double a = 2 * M_PI * k / kSides;
      return center + c.radius * Vec3(std::cos(a), std::sin(a), 0);
    };
    for (int k = 0; k < kSides; ++k) {
      if (!c.filled) {
        AddLine(batch.drawn_lines, rim(k), rim(k + 1), c.color, c.color);
        continue;
      }
      const Vec3 corners[3] = {center, rim(k), rim(k + 1)};
      for (const Vec3& v : corners) {
        const Eigen::Vector3f f = v.cast<float>();
        batch.drawn_triangles.push_back(
            {f.x(), f.y(), f.z(), c.color.r, c.color.g, c.color.b, c.color.a});
      }
    }
  }
}

void DrawPointsAndText(const DrawList& drawing, const View& view, Image& image) {
  const int scale = 1 + image.height / 1200;
  for (const DrawList::Point& p : drawing.points()) {
    const auto pixel = view.ToPixel(p.position);
    if (!pixel) continue;
    const int size = std::max(1, static_cast<int>(std::lround(p.size * scale)));
    const int x0 = static_cast<int>(std::lround(pixel->x())) - size / 2;
    const int y0 = static_cast<int>(std::lround(pixel->y())) - size / 2;
    for (int y = std::max(0, y0); y < std::min(image.height, y0 + size); ++y) {
      for (int x = std::max(0, x0); x < std::min(image.width, x0 + size); ++x) {
        uint8_t* out = image.Pixel(x, y);
        const int a = p.color.a;
        out[0] = static_cast<uint8_t>((p.color.r * a + out[0] * (255 - a)) / 255);
        out[1] = static_cast<uint8_t>((p.color.g * a + out[1] * (255 - a)) / 255);
        out[2] = static_cast<uint8_t>((p.color.b * a + out[2] * (255 - a)) / 255);
      }
    }
  }
  for (const DrawList::Text& t : drawing.texts()) {
    const auto pixel = view.ToPixel(t.position);
    if (!pixel) continue;
    DrawText(image, static_cast<int>(std::lround(pixel->x())),
             static_cast<int>(std::lround(pixel->y())) - 7 * scale - 2 * scale, t.text, scale,
             t.color);
  }
}

void DrawRobotIds(const Space& space, const View& view, Image& image) {
  const int scale = 1 + image.height / 1200;
  for (uint32_t i = 0; i < space.slots(); ++i) {
    if (!space.alive(i) || !(space.flags(i) & kRobot)) continue;
    const Vec3 top = space.pose(i).position + Vec3(0, 0, space.geometry(i).height() + 0.02);
    const auto pixel = view.ToPixel(top);
    if (!pixel || pixel->x() < 0 || pixel->x() >= image.width || pixel->y() < 0 ||
        pixel->y() >= image.height)
      continue;
    const int text_height = 7 * scale;
    DrawText(image, static_cast<int>(pixel->x()),
             static_cast<int>(pixel->y()) - text_height - 2 * scale, space.id(i), scale,
             Color::White());
  }
}

}  // namespace colony::render
