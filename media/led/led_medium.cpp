#include "media/led/led_medium.h"

#include <algorithm>
#include <cmath>

#include "core/entity_type.h"
#include "core/simulation.h"
#include "entities/eyebot/eyebot.h"
#include "entities/objects/pocket.h"

namespace colony {
namespace {

// Slots are processed in fixed blocks (not per thread), so the index is the
// same whatever the thread count.
constexpr uint32_t kBlock = 512;

bool Lit(const Color& c) { return (c.r | c.g | c.b) != 0; }

// A laser spot is moved back this far along the beam, off the surface it lit,
// so that the surface does not hide it from cameras (occlusion checks).
constexpr double kSpotLift = 0.002;  // m
const Color kLaserRed{255, 0, 0, 255};

// Where an object's one point is (LED indices are >= 0).
constexpr int kCentre = -1;  // a landmark: on its axis at half its height
constexpr int kPocket = -2;  // a pocket: the centre of the uncovered part of its top

}  // namespace

void LedMedium::Configure(const ConfigNode& node) {
  cell_size_ = node.GetDouble("cell_size", 0, Range::Positive());
}

const LedMedium::TypeLeds& LedMedium::LedsOfType(uint32_t slot) {
  const uint16_t type = sim().space().type(slot);
  if (types_.size() <= type) types_.resize(type + 1);
  TypeLeds& t = types_[type];
  if (!t.known) {
    t.known = true;
    if (const RingMount* ring = sim().MountsOf(sim().space().HandleOf(slot)).Ring("leds")) {
      for (int i = 0; i < ring->count; ++i) {
        const double a = ring->AngleOf(i);
        t.ring.emplace_back(ring->radius * std::cos(a), ring->radius * std::sin(a),
                            ring->elevation);
      }
    }
  }
  return t;
}

void LedMedium::FindLaserSpots() {
  spots_.clear();
  // Only entities with a pan-tilt unit carry a laser: none, nothing to do.
  Space& space = sim().space();
  const ComponentPool<PanTiltState>& units = space.Pool<PanTiltState>();
  if (units.size() == 0) return;
  spot_of_unit_.resize(units.size());
  sim().pool().ParallelFor(units.size(), 64, [&](size_t b, size_t e) {
    for (size_t k = b; k < e; ++k) {
      const uint32_t item = static_cast<uint32_t>(k), owner = units.owner(item);
      Led& out = spot_of_unit_[k];
      out.owner = ComponentPoolBase::kNoOwner;
      if (owner == ComponentPoolBase::kNoOwner || !space.alive(owner)) continue;
      if (!units[item].laser_on) continue;
      const std::optional<LaserSpot> spot = CastLaser(space, owner);
      if (!spot) continue;
      const Vec3 beam = PanTiltFrame(space.pose(owner), units[item]).orientation * Vec3::UnitX();
      const Vec3 p = spot->point - std::min(kSpotLift, spot->distance) * beam;
      out = {p.x(), p.y(), p.z(), kLaserRed, owner};
    }
  });
  for (const Led& s : spot_of_unit_) {
    if (s.owner != ComponentPoolBase::kNoOwner) spots_.push_back(s);
  }
  std::sort(spots_.begin(), spots_.end(),
            [](const Led& a, const Led& b) { return a.owner < b.owner; });
}

void LedMedium::Update() {
  Space& space = sim().space();
  const uint32_t slots = space.slots();
  // Per-type LED layouts, read once per type (not thread-safe: done here).
  for (uint32_t s = 0; s < slots; ++s) {
    if (!space.alive(s) || space.leds(s).empty()) continue;
    const uint16_t type = space.type(s);
    if (type >= types_.size() || !types_[type].known) LedsOfType(s);
  }
  // The types seen as objects (one check per type, not per entity).
  for (; types_named_ < space.type_count(); ++types_named_) {
    const std::string& label = space.TypeLabel(static_cast<uint16_t>(types_named_));
    if (label == "landmark") landmark_type_ = static_cast<int>(types_named_);
    if (label == "pocket") pocket_type_ = static_cast<int>(types_named_);
  }

  // Pass 1: how many lit points each block of slots holds.
  const size_t blocks = (slots + kBlock - 1) / kBlock;
  block_counts_.assign(blocks + 1, 0);
  auto for_each_point = [&](uint32_t s, auto&& emit) {
    if (!space.alive(s)) return;
    const int type = space.type(s);
    if (type == landmark_type_) {
      if (Lit(space.color(s))) emit(kCentre, space.color(s));
      return;
    }
    if (type == pocket_type_) {
      const PocketState& pocket = *space.Get<PocketState>(s);
      if (pocket.holder == PocketState::kNobody && pocket.visible() && Lit(space.color(s)))
        emit(kPocket, space.color(s));
      return;
    }
    const auto leds = space.leds(s);
    for (size_t i = 0; i < leds.size(); ++i) {
      if (Lit(leds[i])) emit(static_cast<int>(i), leds[i]);
    }
  };
  sim().pool().ParallelFor(blocks, 1, [&](size_t b0, size_t b1) {
    for (size_t b = b0; b < b1; ++b) {
      uint32_t n = 0;
      const uint32_t end = std::min<uint32_t>(slots, static_cast<uint32_t>((b + 1) * kBlock));
      for (uint32_t s = static_cast<uint32_t>(b * kBlock); s < end; ++s) {
        for_each_point(s, [&](int, Color) { ++n; });
      }
      block_counts_[b + 1] = n;
    }
  });
  for (size_t b = 1; b <= blocks; ++b) block_counts_[b] += block_counts_[b - 1];
  FindLaserSpots();
  const size_t lit = block_counts_[blocks];
  const size_t count = lit + spots_.size();
  grid_.Configure(space, cell_size_ > 0 ? cell_size_ : (reach_ > 0 ? reach_ : 1.0), count);

  // Pass 2: the points in the world frame, and their cells.
  unsorted_.resize(count);
  cell_of_.resize(count);
  sim().pool().ParallelFor(blocks, 1, [&](size_t b0, size_t b1) {
    for (size_t b = b0; b < b1; ++b) {
      uint32_t at = block_counts_[b];
      const uint32_t end = std::min<uint32_t>(slots, static_cast<uint32_t>((b + 1) * kBlock));
      for (uint32_t s = static_cast<uint32_t>(b * kBlock); s < end; ++s) {
        const Pose& pose = space.pose(s);
        const double height = space.geometry(s).height();
        const std::vector<Vec3>* ring = nullptr;
        if (s < slots && space.alive(s) && !space.leds(s).empty())
          ring = &types_[space.type(s)].ring;
        bool rotated = false;
        Eigen::Matrix3d rotation;
        for_each_point(s, [&](int i, Color color) {
          // Ring LEDs on the ring; the others (beacons, a light's LED) on the
          // axis at the top of the body; a landmark at its centre; a pocket
          // at the centre of the uncovered part of its top (what a camera
          // sees of it, and never under another pocket).
          Vec3 local(0, 0, i == kCentre ? 0.5 * height : height);
          if (i >= 0 && ring && static_cast<size_t>(i) < ring->size()) local = (*ring)[i];
          if (i == kPocket) {
            const PocketState& pocket = *space.Get<PocketState>(s);
            local = Vec3(pocket.seen_x, pocket.seen_y, height);
          }
          if (!rotated) {
            rotation = pose.orientation.toRotationMatrix();
            rotated = true;
          }
          const Vec3 p = pose.position + rotation * local;
          unsorted_[at] = {p.x(), p.y(), p.z(), color, s};
          cell_of_[at] = grid_.CellOf(p.x(), p.y());
          ++at;
        });
      }
    }
  });

  // The laser spots after every entity's own points.
  for (size_t k = 0; k < spots_.size(); ++k) {
    unsorted_[lit + k] = spots_[k];
    cell_of_[lit + k] = grid_.CellOf(spots_[k].x, spots_[k].y);
  }

  // Counting sort by cell, stable (slot order, then LED order, then laser
  // spots by owner, within a cell).
  grid_.Sort(unsorted_, cell_of_, count, leds_);
  if (occlusions_ && count > 0) occluders_.Build(space, grid_.cell_size());
}

std::vector<AttributeDoc> BlobCameraAttributes() {
  return {
      {"check_occlusions", "true, false", "true", "a blob hidden behind a solid body is not seen"},
      {"medium", "the id of a <led> in <media>", "the only one, or one with default settings",
       "which LED medium the blobs come from"},
      {"noise", "none, gaussian, uniform", "none", "noise added to each blob's distance"},
      {"noise_std_dev", "a number >= 0 (m)", "0",
       "standard deviation of gaussian noise on the distance"},
      {"noise_range", "\"min,max\" (m)", "0,0", "bounds of uniform noise on the distance"},
      {"drop_probability", "a number in [0, 1]", "0", "probability that a blob is missed"},
  };
}

COLONY_REGISTER_MEDIUM(LedMedium, "led",
                       "every lit LED (robots' LED rings and beacons, lights), every landmark, "
                       "every visible pocket and every laser spot (eye-bots' laser pointers), as "
                       "coloured points that cameras see",
                       (std::vector<AttributeDoc>{
                           {"cell_size", "a number > 0 (m)", "the largest camera range",
                            "side of the index's grid cells (a speed knob: which blobs are seen "
                            "does not depend on it, their "
                            "order does)"},
                       }));

}  // namespace colony
