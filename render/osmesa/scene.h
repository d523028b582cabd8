// What a frame shows, as vertex arrays built on the CPU from the space:
// every entity as simple shapes (or its mesh), shaded by a fixed light from
// above, plus line overlays. Built fresh for every frame and drawn in a few
// calls, so the cost grows with what is seen, not with draw calls.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/color.h"
#include "core/entity_type.h"
#include "core/space.h"
#include "render/osmesa/mesh.h"

namespace colony {
class Simulation;
}

namespace colony::render {

struct Vertex {
  float x, y, z;
  uint8_t r, g, b, a;
};

struct SceneBatch {
  std::vector<Vertex> triangles;  // shaded, depth-tested
  // Lines on the floor, under everything else: thin (grid) and wide (trails).
  std::vector<Vertex> floor_lines, wide_floor_lines;
  std::vector<Vertex> lines;  // depth-tested (sensor rays)
  // What loop functions draw (core/drawing.h): depth-tested and blended, over
  // everything else; lines wide.
  std::vector<Vertex> drawn_triangles, drawn_lines;
  void Clear() {
    triangles.clear();
    floor_lines.clear();
    wide_floor_lines.clear();
    lines.clear();
    drawn_triangles.clear();
    drawn_lines.clear();
  }
};

// Appends `from`-`to` to `lines` as one segment.
void AddLine(std::vector<Vertex>& lines, const Vec3& from, const Vec3& to, Color from_color,
             Color to_color);
// Faint lines every `spacing` metres over the arena's floor (10, 100...
// times farther apart if more than 2000 would cross a side).
void AddGrid(const Space& space, double spacing, SceneBatch& batch);

// How finely curved shapes are cut: coarse for entities a few pixels wide.
enum class Detail { kFine, kCoarse };

// Adds the red spot of every laser that is on (eye-bots' pointers: a small
// glowing disc on the surface it lit, entities/eyebot/eyebot.h CastLaser)
// and, with `beams`, each beam as a thin red line from the head (frames show
// it; cameras do not: a beam in clean air is invisible).
void AddLaserSpots(const Simulation& sim, SceneBatch& batch, bool beams);

// Adds entities to a batch: a marXbot as body, treels, LED ring and beacon;
// an eye-bot as legs, body, arms, rotors, protective ring, LED and pan-tilt
// head; a light as a small glowing ball; anything else as its box or cylinder;
// an entity with a mesh in `meshes` as that mesh (plus its LEDs).
class SceneBuilder {
 public:
  SceneBuilder(const Simulation& sim, const MeshTable* meshes) : sim_(sim), meshes_(meshes) {}
  // The alive entity in `slot`.
  void AddEntity(uint32_t slot, SceneBatch& batch, Detail detail = Detail::kFine) const;

 private:
  const Simulation& sim_;
  const MeshTable* meshes_;
};

}  // namespace colony::render
