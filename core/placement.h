// Where entities may stand: wholly inside the arena (down into a ditch they
// fit in), and movable ones clear of every solid entity (fixed ones may touch
// each other: walls meet at corners). At load the footprints placed so far
// are kept in a PlacementIndex; <distribute> draws poses until its entities
// fit (PlaceDistributed). Simulation::Create and Simulation::AddEntity use
// these.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/error.h"
#include "core/experiment_spec.h"
#include "core/random.h"
#include "core/space.h"

namespace colony {

// Whether two solid footprints (shapes turned about z, with their heights)
// overlap.
bool FootprintsOverlap(const Pose& a, const Geometry& ga, const Pose& b, const Geometry& gb);

// "is outside the arena: its footprint spans x [...] but the arena spans
// ..." when `init`'s footprint does not fit inside `space`'s arena (a ditch
// it lies within lowers the floor), or "". Entities without a shape fit
// anywhere.
std::string OutsideArenaProblem(const Space::EntityInit& init, const Space& space);

// Placed solid footprints, to reject entities inside walls or on top of each
// other while an experiment is built. Footprints are filed in the cells of a
// hash grid they touch, except large ones (walls of a huge arena): those are
// kept apart in a short list that every query tests, so that no footprint
// is filed in more than kMaxCellsPerItem cells and the index grows with the
// entities, not the area.
class PlacementIndex {
 public:
  explicit PlacementIndex(double cell) : cell_(cell) {}
  struct Item {
    Pose pose;
    Geometry geometry;
    std::string id;
    int line;
    bool movable;
  };
  // A placed footprint overlapping `pose`/`g` (only movable ones if
  // `movable_only`), or nullptr.
  const Item* FindOverlap(const Pose& pose, const Geometry& g, bool movable_only) const;
  void Insert(const Pose& pose, const Geometry& g, const std::string& id, int line, bool movable);

 private:
  static constexpr double kMaxCellsPerItem = 4096;
  // The cells [x0, x1] x [y0, y1] a footprint's bounding box touches.
  struct CellSpan {
    int64_t x0, y0, x1, y1;
    double cells() const {
      return (static_cast<double>(x1 - x0) + 1) * (static_cast<double>(y1 - y0) + 1);
    }
  };
  CellSpan SpanOf(const Pose& pose, const Geometry& g) const;
  int64_t Cell(double v) const;
  static uint64_t Key(int64_t x, int64_t y) {
    return (static_cast<uint64_t>(x) << 32) ^ static_cast<uint32_t>(y);
  }
  double cell_;
  std::vector<Item> items_;
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
  std::vector<uint32_t> large_;  // items spanning over kMaxCellsPerItem cells
};

// Why `init` cannot stand where it is among the footprints of `index` and in
// `space`'s arena ("is outside the arena: ...", "overlaps 'b' (line 3)"), or
// "".
std::string PlacementProblem(const Space::EntityInit& init, const Space& space,
                             const PlacementIndex& index);

// Draws `draw`'s triple for the entity numbered `index` (a grid's place, or
// a random draw from `rng`), in metres or radians.
Vec3 Draw(const DistributeDraw& draw, RandomStream& rng, size_t index);

// Places the entities of `block`, in order: entity i gets the template's id
// followed by base_num + i, and the first pose drawn (position, then
// orientation, from one stream seeded by `seed` and the block's line) for
// which `problem` returns ""; it is then handed to `add`. Stops at the first
// entity that `add` refuses (returns false: it recorded why) or that finds no
// place in max_trials draws, recorded in `diagnostics` against `file`.
void PlaceDistributed(const DistributeSpec& block, uint64_t seed, const std::string& file,
                      const std::function<std::string(const EntityDesc&)>& problem,
                      const std::function<bool(const EntityDesc&)>& add, Diagnostics& diagnostics);

}  // namespace colony
