#include "core/space.h"

#include <algorithm>
#include <cstdio>
#include <functional>
#include <stdexcept>
#include <utility>

#include "core/bounds.h"
#include "core/huge_pages.h"
#include "core/thread_pool.h"

namespace colony {

std::string StateHasher::Hex(uint64_t v) {
  char buffer[17];
  std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(v));
  return buffer;
}

uint16_t Space::TypeId(const std::string& label) {
  for (size_t i = 0; i < type_labels_.size(); ++i) {
    if (type_labels_[i] == label) return static_cast<uint16_t>(i);
  }
  type_labels_.push_back(label);
  by_type_.emplace_back();
  return static_cast<uint16_t>(type_labels_.size() - 1);
}

const std::vector<uint32_t>& Space::OfType(uint16_t type) const {
  static const std::vector<uint32_t> kNone;
  return type < by_type_.size() ? by_type_[type] : kNone;
}

void Space::Reserve(size_t more, const EntityInit& like) {
  const size_t n = slots() + more;
  if (n <= flags_.capacity()) return;
  flags_.reserve(n);
  generation_.reserve(n);
  types_.reserve(n);
  poses_.reserve(n);
  twists_.reserve(n);
  geometries_.reserve(n);
  colors_.reserve(n);
  masses_.reserve(n);
  contact_.reserve(n);
  led_offset_.reserve(n);
  led_count_.reserve(n);
  light_slot_.reserve(n);
  component_begin_.reserve(n);
  component_count_.reserve(n);
  for (const auto& item : like.components.items_) item->ReserveIn(*this, more);
  component_refs_.reserve(component_refs_.size() + more * like.components.size());
  leds_.reserve(leds_.size() + more * static_cast<size_t>(like.led_count));
  // Filled in order as the block is placed; large enough only in big swarms.
  AdviseHugePages(poses_, Prefault::kInBackground);
  AdviseHugePages(twists_, Prefault::kInBackground);
  AdviseHugePages(geometries_, Prefault::kInBackground);
  AdviseHugePages(colors_, Prefault::kInBackground);
  AdviseHugePages(masses_, Prefault::kInBackground);
  AdviseHugePages(generation_, Prefault::kInBackground);
  AdviseHugePages(led_offset_, Prefault::kInBackground);
  AdviseHugePages(light_slot_, Prefault::kInBackground);
  AdviseHugePages(component_begin_, Prefault::kInBackground);
  AdviseHugePages(component_refs_, Prefault::kInBackground);
  AdviseHugePages(leds_, Prefault::kInBackground);
  GrowIdTable(n);
}

size_t Space::IdPosition(std::string_view id) const {
  const size_t mask = id_table_.size() - 1;
  size_t k = std::hash<std::string_view>()(id) & mask;
  while (id_table_[k] != kNoSlot) {
    if (id_table_[k] != kRemovedSlot && ids_[id_table_[k]] == id) return k;
    k = (k + 1) & mask;
  }
  return k;
}

void Space::GrowIdTable(size_t entries) {
  if (2 * entries <= id_table_.size()) return;
  size_t size = 16;
  while (size < 2 * entries) size *= 2;
  std::vector<uint32_t> old = std::move(id_table_);
  id_table_.reserve(size);
  AdviseHugePages(id_table_, Prefault::kInBackground);  // probed at random, filled whole
  id_table_.assign(size, kNoSlot);
  id_table_used_ = 0;
  for (uint32_t slot : old) {
    if (slot < kRemovedSlot) IndexId(slot);
  }
}

void Space::IndexId(uint32_t slot) {
  GrowIdTable(id_table_used_ + 1);
  const size_t mask = id_table_.size() - 1;
  size_t k = std::hash<std::string_view>()(ids_[slot]) & mask;
  while (id_table_[k] != kNoSlot) k = (k + 1) & mask;
  id_table_[k] = slot;
  ++id_table_used_;
}

void Space::UnindexId(uint32_t slot) {
  const size_t mask = id_table_.size() - 1;
  size_t k = std::hash<std::string_view>()(ids_[slot]) & mask;
  while (id_table_[k] != slot) k = (k + 1) & mask;
  id_table_[k] = kRemovedSlot;
}

EntityHandle Space::Add(const EntityInit& init, uint16_t type) {
  if (init.components.size() > 255)
    throw std::length_error("entity '" + init.id + "' has more than 255 components");
  uint32_t slot;
  if (!free_slots_.empty()) {
    slot = free_slots_.back();
    free_slots_.pop_back();
  } else {
    slot = slots();
    flags_.push_back(0);
    generation_.push_back(0);
    types_.push_back(0);
    poses_.emplace_back();
    twists_.emplace_back();
    geometries_.emplace_back();
    colors_.emplace_back();
    masses_.push_back(0);
    contact_.push_back(0);
    led_offset_.push_back(0);
    led_count_.push_back(0);
    light_slot_.push_back(-1);
    component_begin_.push_back(0);
    component_count_.push_back(0);
    ids_.emplace_back();
  }
  flags_[slot] = static_cast<uint8_t>(init.flags | kAlive);
  types_[slot] = type;
  poses_[slot] = init.pose;
  twists_[slot] = Twist{};
  geometries_[slot] = init.geometry;
  colors_[slot] = init.color;
  masses_[slot] = init.mass;
  contact_[slot] = 0;
  led_offset_[slot] = static_cast<uint32_t>(leds_.size());
  led_count_[slot] = static_cast<uint16_t>(init.led_count);
  // A light shines in its own colour; other LEDs start off.
  leds_.insert(leds_.end(), init.led_count, init.light_intensity > 0 ? init.color : Color::Black());
  component_begin_[slot] = static_cast<uint32_t>(component_refs_.size());
  component_count_[slot] = static_cast<uint8_t>(init.components.size());
  for (const auto& item : init.components.items_) {
    component_refs_.push_back({item->type(), item->AddTo(*this, slot)});
  }
  light_slot_[slot] = -1;
  if (init.light_intensity > 0) {
    light_slot_[slot] = static_cast<int32_t>(lights_.size());
    lights_.push_back({init.light_intensity});
  }
  ids_[slot] = init.id;
  IndexId(slot);
  by_type_[type].push_back(slot);
  ++alive_count_;
  index_dirty_ = true;
  if (!(init.flags & kMovable)) static_dirty_ = true;
  if ((init.flags & kMovable) && (init.flags & kSolid)) {
    max_movable_radius_ = std::max(max_movable_radius_, init.geometry.BoundingRadius());
  }
  return {slot, generation_[slot]};
}

void Space::Remove(EntityHandle h) {
  if (!IsAlive(h)) return;
  const uint32_t slot = h.index;
  if (!movable(slot)) static_dirty_ = true;
  flags_[slot] = 0;
  ++generation_[slot];
  UnindexId(slot);
  auto& list = by_type_[types_[slot]];
  list.erase(std::find(list.begin(), list.end(), slot));
  // Components stay allocated (their slots are not reused); LEDs are zeroed.
  led_count_[slot] = 0;
  light_slot_[slot] = -1;
  for (uint32_t k = 0; k < component_count_[slot]; ++k) {
    const ComponentRef& ref = component_refs_[component_begin_[slot] + k];
    pools_[ref.type]->Release(ref.index);
  }
  component_count_[slot] = 0;
  ids_[slot].clear();
  free_slots_.push_back(slot);
  --alive_count_;
  index_dirty_ = true;
}

std::vector<ComponentType> Space::ComponentsOf(uint32_t i) const {
  std::vector<ComponentType> out;
  for (uint32_t k = 0; k < component_count_[i]; ++k)
    out.push_back(component_refs_[component_begin_[i] + k].type);
  return out;
}

EntityHandle Space::Find(std::string_view id) const {
  if (id_table_.empty()) return {};
  const uint32_t slot = id_table_[IdPosition(id)];
  return slot == kNoSlot ? EntityHandle{} : HandleOf(slot);
}

void Space::SetArena(const Vec3& center, const Vec3& size) {
  arena_min_ = center - 0.5 * size;
  arena_max_ = center + 0.5 * size;
  index_dirty_ = static_dirty_ = true;
}

void Space::ConfigureGrid() {
  // Cells of at least 0.5 m and at least one movable body across: a
  // neighbour query then touches a handful of cells. Over a huge arena they
  // grow, so that the table stays within GridCellCap (core/bounds.h).
  const Vec3 extent = arena_max_ - arena_min_;
  const double cell = CappedCellSize(extent.x(), extent.y(), GridCellSize(max_movable_radius_),
                                     GridCellCap(alive_count_));
  const int nx = std::max(1, static_cast<int>(std::ceil(extent.x() / cell)));
  const int ny = std::max(1, static_cast<int>(std::ceil(extent.y() / cell)));
  if (cell == cell_ && nx == nx_ && ny == ny_ && !cell_start_.empty()) return;
  cell_ = cell;
  inv_cell_ = 1.0 / cell;
  nx_ = nx;
  ny_ = ny;
  cell_start_.assign(static_cast<size_t>(nx) * ny + 1, CellStart{});
  static_dirty_ = true;
}

void Space::BuildMovableGrid() {
  // A counting sort of the movable solid entities by the cell of their
  // centre, slot order within a cell. The grid's rows are cut into bands,
  // one per thread: each band counts, then places, the entities whose cell
  // it holds, reading every slot in order. The bands write apart, so the
  // order is the same whatever the thread count.
  const uint32_t n = slots();
  cell_scratch_.resize(n);
  auto cells_of = [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      if ((flags_[i] & (kAlive | kMovable | kSolid)) != (kAlive | kMovable | kSolid)) {
        cell_scratch_[i] = UINT32_MAX;
        continue;
      }
      const Vec3& p = poses_[i].position;
      cell_scratch_[i] = static_cast<uint32_t>(CellY(p.y()) * nx_ + CellX(p.x()));
    }
  };
  const size_t bands = pool_ ? std::min<size_t>(std::max(pool_->threads(), 1), ny_) : 1;
  auto band_cells = [&](size_t b) {
    return std::pair<uint32_t, uint32_t>(static_cast<uint32_t>(b * ny_ / bands * nx_),
                                         static_cast<uint32_t>((b + 1) * ny_ / bands * nx_));
  };
  band_offset_.assign(bands + 1, 0);
  // Counts of each cell c of the band in cell_start_[c + 1].
  auto count = [&](size_t b) {
    const auto [first, last] = band_cells(b);
    for (uint32_t c = first; c < last; ++c) cell_start_[c + 1].movable = 0;
    uint32_t total = 0;
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t c = cell_scratch_[i];
      if (c >= first && c < last) {
        ++cell_start_[c + 1].movable;
        ++total;
      }
    }
    band_offset_[b + 1] = total;
  };
  // Starts of the band's cells (the band's own offset first), then its
  // entities into place.
  std::vector<uint32_t>& cursor = cell_cursor_;
  cursor.resize(static_cast<size_t>(nx_) * ny_);
  auto place = [&](size_t b) {
    const auto [first, last] = band_cells(b);
    uint32_t run = band_offset_[b];
    for (uint32_t c = first; c < last; ++c) {
      cursor[c] = run;
      run += cell_start_[c + 1].movable;
      cell_start_[c + 1].movable = run;
    }
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t c = cell_scratch_[i];
      if (c >= first && c < last) movable_items_[cursor[c]++] = i;
    }
  };
  // On the pool's threads, or on this one without a pool.
  auto run = [&](size_t items, size_t min_chunk, auto&& fn) {
    if (pool_) {
      pool_->ParallelFor(items, min_chunk, fn);
    } else {
      fn(size_t{0}, items);
    }
  };
  auto each_band = [&](auto&& fn) {
    run(bands, 1, [&](size_t begin, size_t end) {
      for (size_t b = begin; b < end; ++b) fn(b);
    });
  };
  cell_start_[0].movable = 0;
  run(n, 1024, cells_of);
  each_band(count);
  for (size_t b = 0; b < bands; ++b) band_offset_[b + 1] += band_offset_[b];
  movable_items_.resize(band_offset_[bands]);
  each_band(place);
}

void Space::BuildStaticGrid() {
  const size_t cells = static_cast<size_t>(nx_) * ny_;
  // Two passes over the fixed solid entities: count the entries of each cell,
  // then place them (slot order within a cell).
  auto for_each_entry = [&](auto&& fn) {
    for (uint32_t i = 0; i < slots(); ++i) {
      if ((flags_[i] & (kAlive | kMovable | kSolid)) != (kAlive | kSolid)) continue;
      const Vec2 half = FootprintHalfExtents(geometries_[i], poses_[i].orientation);
      const Vec3& p = poses_[i].position;
      for (int cy = CellY(p.y() - half.y()); cy <= CellY(p.y() + half.y()); ++cy) {
        for (int cx = CellX(p.x() - half.x()); cx <= CellX(p.x() + half.x()); ++cx) {
          fn(static_cast<size_t>(cy) * nx_ + cx, i);
        }
      }
    }
  };
  for (CellStart& c : cell_start_) c.fixed = 0;
  for_each_entry([&](size_t c, uint32_t) { ++cell_start_[c + 1].fixed; });
  for (size_t c = 0; c < cells; ++c) cell_start_[c + 1].fixed += cell_start_[c].fixed;
  fixed_items_.resize(cell_start_[cells].fixed);
  std::vector<uint32_t> cursor(cells);
  for (size_t c = 0; c < cells; ++c) cursor[c] = cell_start_[c].fixed;
  for_each_entry([&](size_t c, uint32_t i) { fixed_items_[cursor[c]++] = i; });
  static_dirty_ = false;
}

void Space::UpdateIndex() {
  ConfigureGrid();
  if (static_dirty_) BuildStaticGrid();
  BuildMovableGrid();
  index_dirty_ = false;
}

void Space::Gather(double x0, double y0, double x1, double y1, std::vector<uint32_t>& out) const {
  // Movable entities are filed by centre: widen the query by their radius.
  const double m = max_movable_radius_;
  const int cx0 = CellX(x0 - m), cx1 = CellX(x1 + m);
  const int cy0 = CellY(y0 - m), cy1 = CellY(y1 + m);
  // A row's cells are one run of movable_items_: copied whole, with the size
  // grown once per row (a push_back per item reloads the vector's pointers,
  // which `out` could alias, at every item).
  // The same rows' fixed entries are counted on the way (the two kinds'
  // starts share their cache lines): the fixed ones' query below is a part
  // of this one, so with none here it finds none and is skipped.
  uint32_t fixed = 0;
  for (int cy = cy0; cy <= cy1; ++cy) {
    const size_t row = static_cast<size_t>(cy) * nx_;
    const CellStart& first = cell_start_[row + cx0];
    const CellStart& last = cell_start_[row + cx1 + 1];
    fixed += last.fixed - first.fixed;
    if (first.movable < last.movable) {
      out.insert(out.end(), movable_items_.data() + first.movable,
                 movable_items_.data() + last.movable);
    }
  }
  if (fixed == 0) return;
  // Non-movable ones may sit in several cells: keep each once.
  const size_t first_static = out.size();
  const int sx0 = CellX(x0), sx1 = CellX(x1), sy0 = CellY(y0), sy1 = CellY(y1);
  for (int cy = sy0; cy <= sy1; ++cy) {
    const size_t row = static_cast<size_t>(cy) * nx_;
    const uint32_t end = cell_start_[row + sx1 + 1].fixed;
    for (uint32_t k = cell_start_[row + sx0].fixed; k < end; ++k) {
      const uint32_t e = fixed_items_[k];
      if (std::find(out.begin() + first_static, out.end(), e) == out.end()) out.push_back(e);
    }
  }
}

void Space::Hash(StateHasher& h) const {
  for (uint32_t i = 0; i < slots(); ++i) {
    if (!alive(i)) continue;
    h.AddU64(i);
    const Pose& p = poses_[i];
    h.Add(p.position.data(), sizeof(double) * 3);
    h.Add(p.orientation.coeffs().data(), sizeof(double) * 4);
    const Twist& t = twists_[i];
    h.Add(t.linear.data(), sizeof(double) * 3);
    h.Add(t.angular.data(), sizeof(double) * 3);
    if (led_count_[i]) h.Add(leds_.data() + led_offset_[i], sizeof(Color) * led_count_[i]);
    for (uint32_t k = 0; k < component_count_[i]; ++k) {
      const ComponentRef& ref = component_refs_[component_begin_[i] + k];
      pools_[ref.type]->HashItem(ref.index, h);
    }
  }
}

}  // namespace colony
