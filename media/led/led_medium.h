// The LED medium: every lit LED in the arena (robots' LED rings and beacons,
// lights), every landmark, every visible pocket (not held, not covered beyond
// its threshold) and every laser spot (an eye-bot's laser pointer where it
// meets a surface), as coloured points in the world frame, in a
// uniform grid rebuilt once per tick after physics (tick step 3). Cameras
// (the omnidirectional camera) read the cells around them, so a query costs
// what is near. See media/led/README.md.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/color.h"
#include "core/medium.h"
#include "core/space.h"
#include "media/cell_grid.h"
#include "media/occlusion.h"

namespace colony {

// The attributes every camera reading blobs from the LED medium shares
// (omnidirectional, pan-tilt): check_occlusions, medium, and the noise on a
// blob's distance and its loss.
std::vector<AttributeDoc> BlobCameraAttributes();

class LedMedium : public Medium {
 public:
  void Configure(const ConfigNode& node) override;
  void Update() override;

  // A camera that looks `reach` metres around it (horizontally); the grid's
  // cells follow the largest (unless cell_size is set).
  void RequestReach(double reach) { reach_ = std::max(reach_, reach); }
  // A camera that checks occlusions: the medium then keeps an OccluderGrid.
  void RequestOcclusions() { occlusions_ = true; }
  const OccluderGrid& occluders() const { return occluders_; }

  // One coloured point: an LED, a landmark's centre, a pocket's top centre,
  // or a laser spot. 32 bytes.
  struct Led {
    double x, y, z;
    Color color;
    uint32_t owner;  // slot of the entity carrying it (of a laser spot: the laser's)
  };
  const std::vector<Led>& leds() const { return leds_; }
  // The laser spots among leds() (red, owned by the robot whose laser it is),
  // by owner's slot; and the spot of `owner`'s laser, or nullptr. A camera
  // that skips its robot's own points (its LEDs) takes its own spot here.
  const std::vector<Led>& laser_spots() const { return spots_; }
  const Led* LaserSpotOf(uint32_t owner) const {
    const auto it = std::lower_bound(spots_.begin(), spots_.end(), owner,
                                     [](const Led& s, uint32_t o) { return s.owner < o; });
    return it != spots_.end() && it->owner == owner ? &*it : nullptr;
  }

  // Calls visit(begin, end) for runs [begin, end) of indices into leds()
  // that together hold every point within `reach` horizontally of (x, y)
  // (and others near it). Runs come in a fixed order: grid rows, then cells,
  // then owners' slots, then each owner's LEDs in order.
  template <class Visit>
  void ForEachCandidateRun(double x, double y, double reach, Visit&& visit) const {
    if (leds_.empty()) return;
    grid_.ForEachRun(x, y, reach, visit);
  }
  double cell_size() const { return grid_.cell_size(); }

 private:
  // Where a type's LEDs sit in the entity's frame (from its "leds" ring).
  struct TypeLeds {
    bool known = false;
    std::vector<Vec3> ring;  // the ring's LEDs; LEDs beyond these are beacons on top of the axis
  };
  const TypeLeds& LedsOfType(uint32_t slot);
  // Fills spots_ from the pan-tilt units (entities/eyebot/eyebot.h).
  void FindLaserSpots();

  double cell_size_ = 0;  // 0: from reach_
  double reach_ = 0;
  bool occlusions_ = false;
  OccluderGrid occluders_;

  std::vector<TypeLeds> types_;         // by space type id
  size_t types_named_ = 0;              // space types whose labels were read
  int landmark_type_ = -1;              // space type id of "landmark", once it exists
  int pocket_type_ = -1;                // space type id of "pocket", once it exists
  std::vector<uint32_t> block_counts_;  // lit points per block of slots
  std::vector<Led> unsorted_;
  std::vector<uint32_t> cell_of_;
  std::vector<Led> leds_;          // sorted by cell
  std::vector<Led> spot_of_unit_;  // by item of the space's pan-tilt pool; owner kNoOwner: none
  std::vector<Led> spots_;         // laser spots, by owner
  CellGrid grid_;
};

}  // namespace colony
