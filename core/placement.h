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
// other while an experiment is built. The index keeps only the space slot
// and file line of each placed entity (its pose and shape are read from the
// space; those of a block numbered by place are kept here until it is
// added), filed in the cells of a uniform grid over the arena that its
// footprint touches; each cell is a list in the order the entities were
// placed (head and tail per cell, one link per entry), so a load allocates a
// few flat arrays instead of a node per cell. Large footprints (walls of a
// huge arena) are kept apart in a short list that every query tests, so that
// no footprint is filed in more than kMaxCellsPerItem cells. The grid has at
// most max(4096, 4 x expected entities) cells: over a huge, nearly empty
// arena its cells grow, so it costs memory for the entities, not the area.
// Entities are placed inside the arena (checked first); a footprint beyond
// it is filed in the edge cells.
class PlacementIndex {
 public:
  // Cells of at least `cell` metres over the arena of `space`, for about
  // `expected` entities.
  PlacementIndex(double cell, const Space& space, size_t expected);
  struct Item {
    uint32_t slot;  // in the space
    int line;       // in the experiment file (0: none)
  };
  // A placed footprint overlapping `pose`/`g` (only movable ones if
  // `movable_only`), or nullptr: cells row by row, each in the order placed,
  // then the large footprints.
  const Item* FindOverlap(const Pose& pose, const Geometry& g, bool movable_only) const;
  // Files the entity in `slot` of the space, as it stands now.
  void Insert(uint32_t slot, int line);
  // Entities drawn but not yet in the space (a <distribute> block numbered
  // by place is drawn whole before it is added), all of shape `g` (which
  // must outlive the index): BeginPending, then InsertPending for each
  // (returns its number, from 0; its pose is kept here), then Settle to name
  // each one's slot once it is added. A block that fails to load may leave
  // some pending.
  void BeginPending(const Geometry& g, bool movable, size_t expected);
  uint32_t InsertPending(const Pose& pose, int line);
  const Pose& PendingPose(uint32_t pending) const { return pending_[pending]; }
  void Settle(uint32_t pending, uint32_t slot) { items_[pending_base_ + pending].slot = slot; }
  // Asks for a pending entity's pose and item early (read and settled in an
  // order unrelated to the order drawn, a cache miss each in a big block).
  void PrefetchPending(uint32_t pending) const {
    __builtin_prefetch(&pending_[pending]);
    __builtin_prefetch(&items_[pending_base_ + pending], 1);
  }
  // Whether `item` is still pending (it has no slot, so no id yet).
  static bool IsPending(const Item& item) { return item.slot & kPending; }

 private:
  static constexpr double kMaxCellsPerItem = 4096;
  static constexpr uint32_t kNone = UINT32_MAX;
  // In Item::slot: a pending entity, numbered by the other bits.
  static constexpr uint32_t kPending = 1u << 31;
  // Files item `k` in the cells its footprint touches.
  void File(uint32_t k, const Pose& pose, const Geometry& g);
  // The cells [x0, x1] x [y0, y1] a footprint's bounding box touches.
  struct CellSpan {
    int64_t x0, y0, x1, y1;
    double cells() const {
      return (static_cast<double>(x1 - x0) + 1) * (static_cast<double>(y1 - y0) + 1);
    }
  };
  struct Entry {
    uint32_t item;
    uint32_t next;  // next entry of the same cell, or kNone
  };
  CellSpan SpanOf(const Pose& pose, const Geometry& g) const;
  int64_t CellX(double v) const;
  int64_t CellY(double v) const;
  const Space& space_;
  double cell_;
  int64_t base_x_ = 0, base_y_ = 0;  // cell coordinates of the grid's first column and row
  int64_t nx_ = 1, ny_ = 1;
  std::vector<Item> items_;
  std::vector<uint32_t> head_, tail_;  // per cell: first and last entry, or kNone
  std::vector<Entry> entries_;
  std::vector<uint32_t> large_;  // items spanning over kMaxCellsPerItem cells
  // The pending block: its poses, shape, whether movable, its first item.
  std::vector<Pose> pending_;
  const Geometry* pending_geometry_ = nullptr;
  bool pending_movable_ = false;
  uint32_t pending_base_ = 0;
};

// Why `init` cannot stand where it is among the footprints of `index` and in
// `space`'s arena ("is outside the arena: ...", "overlaps 'b' (line 3)"), or
// "".
std::string PlacementProblem(const Space::EntityInit& init, const Space& space,
                             const PlacementIndex& index);

// Draws `draw`'s triple for the entity numbered `index` (a grid's place, or
// a random draw from `rng`), in metres or radians.
Vec3 Draw(const DistributeDraw& draw, RandomStream& rng, size_t index);

// Places the entities of `block`. Each is given the first pose drawn
// (position, then orientation, from one stream seeded by `seed` and the
// block's line) that PlacementProblem finds clear in `space` and `index`,
// then handed to `add`, which adds it to `space` (and not to `index`: solid
// ones are filed here). Entity i gets the template's id followed by
// base_num + i: with order="drawn" it is the i-th drawn and added, each as
// soon as it is drawn; with order="place" the whole block is drawn first,
// then numbered and added in the order of its places row by row over the
// arena, rows as wide as the space's grid cells (RowKey). Stops at the
// first entity that finds no place in max_trials draws, recorded in
// `diagnostics` against `file`, or that `add` refuses (returns an invalid
// handle: it recorded why).
void PlaceDistributed(const DistributeSpec& block, uint64_t seed, const std::string& file,
                      const Space& space, PlacementIndex& index,
                      const std::function<EntityHandle(const EntityDesc&)>& add,
                      Diagnostics& diagnostics);

// The place of `p` in rows of the floor [lo, hi] `cell` wide along y (rows
// as the space's grid cuts them with cells of that size), then along x in
// 2^31 steps: rows in order, each from low x to high x.
uint64_t RowKey(const Vec3& p, const Vec3& lo, const Vec3& hi, double cell);

}  // namespace colony
