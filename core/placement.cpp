// Placement checks, the load-time overlap index and <distribute> (see
// core/placement.h).
#include "core/placement.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/bounds.h"
#include "core/geometry2d.h"
#include "core/huge_pages.h"

namespace colony {

namespace {

bool HeightsOverlap(const Pose& a, const Geometry& ga, const Pose& b, const Geometry& gb) {
  return a.position.z() < b.position.z() + gb.height() &&
         b.position.z() < a.position.z() + ga.height();
}

// Separating axis test on the four edge normals.
bool RectsOverlap(const Rect& a, const Rect& b) {
  const Vec2 axes[4] = {{a.cos_yaw, a.sin_yaw},
                        {-a.sin_yaw, a.cos_yaw},
                        {b.cos_yaw, b.sin_yaw},
                        {-b.sin_yaw, b.cos_yaw}};
  for (const Vec2& axis : axes) {
    auto extent = [&](const Rect& r) {
      return r.half.x() * std::abs(axis.dot(Vec2(r.cos_yaw, r.sin_yaw))) +
             r.half.y() * std::abs(axis.dot(Vec2(-r.sin_yaw, r.cos_yaw)));
    };
    if (std::abs(axis.dot(a.center - b.center)) >= extent(a) + extent(b)) return false;
  }
  return true;
}

}  // namespace

bool FootprintsOverlap(const Pose& a, const Geometry& ga, const Pose& b, const Geometry& gb) {
  if (!HeightsOverlap(a, ga, b, gb)) return false;
  if (ga.shape == ShapeKind::kCylinder)
    return CircleOverlapsFootprint(a.position.head<2>(), ga.radius, b, gb);
  if (gb.shape == ShapeKind::kCylinder)
    return CircleOverlapsFootprint(b.position.head<2>(), gb.radius, a, ga);
  return RectsOverlap(RectOf(a, ga), RectOf(b, gb));
}

std::string OutsideArenaProblem(const Space::EntityInit& init, const Space& space) {
  if (init.geometry.shape == ShapeKind::kNone) return "";
  const Vec2 half = FootprintHalfExtents(init.geometry, init.pose.orientation);
  const Vec3& p = init.pose.position;
  const Vec3& lo = space.arena_min();
  const Vec3& hi = space.arena_max();
  // Down to a ditch's bottom when the footprint lies within the ditch.
  double bottom = lo.z();
  for (const Ditch& d : space.floor().ditches()) {
    if (p.x() - half.x() >= d.min_x - 1e-9 && p.x() + half.x() <= d.max_x + 1e-9 &&
        p.y() - half.y() >= d.min_y - 1e-9 && p.y() + half.y() <= d.max_y + 1e-9) {
      bottom = std::min(bottom, lo.z() - d.depth);
    }
  }
  if (p.x() - half.x() < lo.x() - 1e-9 || p.x() + half.x() > hi.x() + 1e-9 ||
      p.y() - half.y() < lo.y() - 1e-9 || p.y() + half.y() > hi.y() + 1e-9 ||
      p.z() < bottom - 1e-9 || p.z() + init.geometry.height() > hi.z() + 1e-9) {
    std::ostringstream s;
    s << "is outside the arena: its footprint spans x [" << p.x() - half.x() << ", "
      << p.x() + half.x() << "], y [" << p.y() - half.y() << ", " << p.y() + half.y() << "], z ["
      << p.z() << ", " << p.z() + init.geometry.height() << "] but the arena spans x [" << lo.x()
      << ", " << hi.x() << "], y [" << lo.y() << ", " << hi.y() << "], z [" << lo.z() << ", "
      << hi.z() << "]";
    return s.str();
  }
  if (space.ceiling() && p.z() + init.geometry.height() > space.ceiling()->z + 1e-9) {
    std::ostringstream s;
    s << "reaches above the ceiling: its top is at z = " << p.z() + init.geometry.height()
      << " but the ceiling is at z = " << space.ceiling()->z;
    return s.str();
  }
  return "";
}

PlacementIndex::PlacementIndex(double cell, const Space& space, size_t expected) : space_(space) {
  const Vec3 lo = space.arena_min(), hi = space.arena_max();
  const double max_cells = std::clamp(4.0 * static_cast<double>(expected), 4096.0, kMaxGridCells);
  cell_ = CappedCellSize(hi.x() - lo.x() + cell, hi.y() - lo.y() + cell, cell, max_cells);
  // Cells are aligned on multiples of the cell size from the origin.
  base_x_ = static_cast<int64_t>(std::floor(lo.x() / cell_));
  base_y_ = static_cast<int64_t>(std::floor(lo.y() / cell_));
  nx_ = static_cast<int64_t>(std::floor(hi.x() / cell_)) - base_x_ + 1;
  ny_ = static_cast<int64_t>(std::floor(hi.y() / cell_)) - base_y_ + 1;
  // The grid is read and written at random, the lists filled in order.
  const size_t cells = static_cast<size_t>(nx_ * ny_);
  head_.reserve(cells);
  tail_.reserve(cells);
  items_.reserve(expected);
  entries_.reserve(2 * expected);  // a footprint spans 1.8 cells on average at 0.5 m
  AdviseHugePages(head_, Prefault::kInBackground);
  AdviseHugePages(tail_, Prefault::kInBackground);
  AdviseHugePages(items_, Prefault::kInBackground);
  AdviseHugePages(entries_, Prefault::kInBackground);
  head_.assign(cells, kNone);
  tail_.assign(cells, kNone);
}

const PlacementIndex::Item* PlacementIndex::FindOverlap(const Pose& pose, const Geometry& g,
                                                        bool movable_only) const {
  auto overlap = [&](uint32_t k) {
    const uint32_t s = items_[k].slot;
    if (s & kPending) {
      return (!movable_only || pending_movable_) &&
             FootprintsOverlap(pose, g, pending_[s & ~kPending], *pending_geometry_);
    }
    return (!movable_only || space_.movable(s)) &&
           FootprintsOverlap(pose, g, space_.pose(s), space_.geometry(s));
  };
  const CellSpan span = SpanOf(pose, g);
  if (span.cells() > kMaxCellsPerItem) {
    // A query larger than the cells it would visit tests every item.
    for (uint32_t k = 0; k < items_.size(); ++k) {
      if (overlap(k)) return &items_[k];
    }
    return nullptr;
  }
  for (int64_t cy = span.y0; cy <= span.y1; ++cy) {
    for (int64_t cx = span.x0; cx <= span.x1; ++cx) {
      for (uint32_t e = head_[cy * nx_ + cx]; e != kNone; e = entries_[e].next) {
        if (overlap(entries_[e].item)) return &items_[entries_[e].item];
      }
    }
  }
  for (uint32_t k : large_) {
    if (overlap(k)) return &items_[k];
  }
  return nullptr;
}

void PlacementIndex::Insert(uint32_t slot, int line) {
  const uint32_t k = static_cast<uint32_t>(items_.size());
  items_.push_back({slot, line});
  File(k, space_.pose(slot), space_.geometry(slot));
}

void PlacementIndex::BeginPending(const Geometry& g, bool movable, size_t expected) {
  pending_.clear();
  pending_.reserve(expected);
  pending_geometry_ = &g;
  pending_movable_ = movable;
  pending_base_ = static_cast<uint32_t>(items_.size());
}

uint32_t PlacementIndex::InsertPending(const Pose& pose, int line) {
  const uint32_t k = static_cast<uint32_t>(items_.size());
  const uint32_t n = static_cast<uint32_t>(pending_.size());
  items_.push_back({kPending | n, line});
  pending_.push_back(pose);
  File(k, pose, *pending_geometry_);
  return n;
}

void PlacementIndex::File(uint32_t k, const Pose& pose, const Geometry& g) {
  const CellSpan span = SpanOf(pose, g);
  if (span.cells() > kMaxCellsPerItem) {
    large_.push_back(k);
    return;
  }
  for (int64_t cy = span.y0; cy <= span.y1; ++cy) {
    for (int64_t cx = span.x0; cx <= span.x1; ++cx) {
      const size_t c = static_cast<size_t>(cy * nx_ + cx);
      const uint32_t e = static_cast<uint32_t>(entries_.size());
      entries_.push_back({k, kNone});
      if (tail_[c] == kNone) {
        head_[c] = e;
      } else {
        entries_[tail_[c]].next = e;
      }
      tail_[c] = e;
    }
  }
}

PlacementIndex::CellSpan PlacementIndex::SpanOf(const Pose& pose, const Geometry& g) const {
  const Vec2 half = FootprintHalfExtents(g, pose.orientation);
  const Vec3& p = pose.position;
  return {CellX(p.x() - half.x()), CellY(p.y() - half.y()), CellX(p.x() + half.x()),
          CellY(p.y() + half.y())};
}

int64_t PlacementIndex::CellX(double v) const {
  return std::clamp(static_cast<int64_t>(std::floor(v / cell_)) - base_x_, int64_t{0}, nx_ - 1);
}

int64_t PlacementIndex::CellY(double v) const {
  return std::clamp(static_cast<int64_t>(std::floor(v / cell_)) - base_y_, int64_t{0}, ny_ - 1);
}

std::string PlacementProblem(const Space::EntityInit& init, const Space& space,
                             const PlacementIndex& index) {
  if (init.geometry.shape == ShapeKind::kNone) return "";
  if (std::string outside = OutsideArenaProblem(init, space); !outside.empty()) return outside;
  if (!(init.flags & kSolid)) return "";
  // Non-movable things may touch each other (walls meet at corners);
  // anything movable must start clear of everything, whichever comes first.
  const bool movable = init.flags & kMovable;
  if (const auto* other = index.FindOverlap(init.pose, init.geometry, !movable)) {
    const std::string line = "(line " + std::to_string(other->line) + ")";
    if (PlacementIndex::IsPending(*other))
      return "overlaps an entity of the same <distribute> block drawn before it " + line;
    return "overlaps '" + space.id(other->slot) + "' " + line;
  }
  return "";
}

Vec3 Draw(const DistributeDraw& draw, RandomStream& rng, size_t index) {
  const auto& a = draw.a;
  const auto& b = draw.b;
  auto unit = [&](double v) { return draw.degrees ? DegToRad(v) : v; };
  switch (draw.method) {
    case DistributeDraw::Method::kUniform: {
      // One draw per statement: the order of a call's arguments is
      // unspecified (GCC and clang differ), and z, y, x is the order every
      // recorded result was made with.
      const double z = rng.Uniform(unit(a[2]), unit(b[2]));
      const double y = rng.Uniform(unit(a[1]), unit(b[1]));
      const double x = rng.Uniform(unit(a[0]), unit(b[0]));
      return Vec3(x, y, z);
    }
    case DistributeDraw::Method::kGaussian: {
      const double z = rng.Gaussian(unit(a[2]), unit(b[2]));
      const double y = rng.Gaussian(unit(a[1]), unit(b[1]));
      const double x = rng.Gaussian(unit(a[0]), unit(b[0]));
      return Vec3(x, y, z);
    }
    case DistributeDraw::Method::kGrid: {
      // Places filled x fastest, then y, then z, centred on a.
      const auto& n = draw.layout;
      const int64_t i = static_cast<int64_t>(index);
      const int64_t k[3] = {i % n[0], i / n[0] % n[1], i / (n[0] * n[1])};
      Vec3 v;
      for (int c = 0; c < 3; ++c)
        v[c] = unit(a[c] + (static_cast<double>(k[c]) - (n[c] - 1) / 2.0) * b[c]);
      return v;
    }
    case DistributeDraw::Method::kConstant:
      break;
  }
  return Vec3(unit(a[0]), unit(a[1]), unit(a[2]));
}

uint64_t RowKey(const Vec3& p, const Vec3& lo, const Vec3& hi, double cell) {
  const double wx = hi.x() - lo.x(), wy = hi.y() - lo.y();
  // The row as the space's grid finds it (Space::CellY: clamped to the
  // rows, NaN in the first), kept below 2^32 rows; in doubles, so that a
  // huge arena cannot overflow an int.
  const double rows = std::clamp(std::ceil(wy / cell), 1.0, 4294967296.0);
  const double f = (p.y() - lo.y()) * (1.0 / cell);
  const uint64_t row = f >= 1 ? static_cast<uint64_t>(std::min(f, rows - 1)) : 0;
  constexpr double kSteps = 2147483648.0;  // 2^31 along x
  const double t = wx > 0 ? (p.x() - lo.x()) / wx : 0;
  // Places are inside the arena; the bounds only keep a key in range.
  return row << 32 | static_cast<uint64_t>(std::clamp(t * kSteps, 0.0, kSteps - 1));
}

void PlaceDistributed(const DistributeSpec& block, uint64_t seed, const std::string& file,
                      const Space& space, PlacementIndex& index,
                      const std::function<EntityHandle(const EntityDesc&)>& add,
                      Diagnostics& diagnostics) {
  RandomStream rng = RandomStream::For(seed, "distribute", std::to_string(block.line));
  const std::string& base_id = block.entity.init.id;
  EntityDesc desc = block.entity;
  const bool solid = desc.init.flags & kSolid;
  const bool movable = desc.init.flags & kMovable;
  auto id_of = [&](int64_t i) { return base_id + std::to_string(block.base_num + i); };
  // Numbered by place: the poses drawn, in the order drawn, kept by the
  // index (solid entities, which later draws must stay clear of) or here.
  std::vector<Pose> drawn;
  if (block.order_by_place && solid)
    index.BeginPending(block.entity.init.geometry, movable, static_cast<size_t>(block.quantity));
  else if (block.order_by_place)
    drawn.reserve(static_cast<size_t>(block.quantity));
  for (int64_t i = 0; i < block.quantity; ++i) {
    bool placed = false;
    std::string last_problem;
    for (int64_t trial = 0; trial < block.max_trials && !placed; ++trial) {
      desc.init.pose.position = Draw(block.position, rng, static_cast<size_t>(i));
      const Vec3 o = Draw(block.orientation, rng, static_cast<size_t>(i));
      desc.init.pose.orientation = FromEulerZYX(o[0], o[1], o[2]);
      last_problem = PlacementProblem(desc.init, space, index);
      placed = last_problem.empty();
    }
    if (!placed) {
      const std::string which = block.order_by_place ? "the next" : "'" + id_of(i) + "'";
      diagnostics.Add(Diagnostic{
          file, block.entity_line, "entity", "max_trials", std::to_string(block.max_trials),
          "could place only " + std::to_string(i) + " of " + std::to_string(block.quantity) +
              " entities: " + which + " found no free place in " +
              std::to_string(block.max_trials) + " trials (last try: it " + last_problem +
              "); enlarge the <position> range or the arena, lower quantity, or raise max_trials"});
      return;
    }
    if (block.order_by_place) {
      if (solid) {
        index.InsertPending(desc.init.pose, desc.line);
      } else {
        drawn.push_back(desc.init.pose);
      }
      continue;
    }
    desc.init.id = id_of(i);
    const EntityHandle h = add(desc);
    if (!h.valid()) return;
    if (solid) index.Insert(h.index, desc.line);
  }
  if (!block.order_by_place) return;
  auto pose = [&](uint32_t k) -> const Pose& { return solid ? index.PendingPose(k) : drawn[k]; };
  // Rows as wide as the space's grid cells for this block's entities, so
  // that the entities' order in memory is the order of the space's
  // cell-by-cell index (which engines and sensors walk) as far as they fill
  // the cells alone. Ties (the same place) keep the order drawn.
  const double cell = Space::GridCellSize(block.entity.init.geometry.BoundingRadius());
  std::vector<std::pair<uint64_t, uint32_t>> order(static_cast<size_t>(block.quantity));
  for (uint32_t k = 0; k < order.size(); ++k)
    order[k] = {RowKey(pose(k).position, space.arena_min(), space.arena_max(), cell), k};
  std::sort(order.begin(), order.end());
  constexpr size_t kAhead = 8;
  std::string next_id = id_of(0);
  for (size_t i = 0; i < order.size(); ++i) {
    if (i + kAhead < order.size()) {
      const uint32_t ahead = order[i + kAhead].second;
      if (solid) {
        index.PrefetchPending(ahead);
      } else {
        __builtin_prefetch(&drawn[ahead]);
      }
    }
    desc.init.id = std::move(next_id);
    if (i + 1 < order.size()) {
      next_id = id_of(static_cast<int64_t>(i) + 1);
      space.PrefetchId(next_id);
    }
    const uint32_t k = order[i].second;
    desc.init.pose = pose(k);
    const EntityHandle h = add(desc);
    if (!h.valid()) return;
    if (solid) index.Settle(k, h.index);
  }
}

}  // namespace colony
