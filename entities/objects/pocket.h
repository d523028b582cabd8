// The deformable pocket of seed 004 (3.2): a plastic bag of rice, 12 x 7 x
// 1.5 cm, about 100 g, red, with a ferromagnetic strip along its long axis
// that the manipulator's magnet holds. Pockets pile up and conform, which the
// heap model below stands for (entities/objects/README.md, "Pockets"): a
// pocket put down settles onto the highest pockets its footprint overlaps
// (or the floor), level, and every pocket carries its occlusion: the fraction
// of its top covered by pockets above it. A pocket covered beyond its
// threshold is invisible to cameras (seed 004, 5.1: 75% chosen).
#pragma once

#include <cstdint>

#include "core/state_hash.h"

namespace colony {

class Space;

namespace pocket {
inline constexpr double kLength = 0.12, kWidth = 0.07, kThickness = 0.015;  // m
inline constexpr double kMass = 0.1;                                        // kg
inline constexpr double kOcclusionThreshold = 0.75;                         // seed 004, 5.1
inline constexpr int kSamplesX = 8, kSamplesY = 5;  // occlusion samples along length, width
}  // namespace pocket

// Component "pocket", on every pocket entity.
struct PocketState {
  static constexpr const char* kComponentName = "pocket";
  static constexpr uint32_t kNobody = 0xFFFFFFFFu;
  // Fraction of the top covered by pockets above it, in [0, 1] (written by
  // UpdatePocketOcclusion).
  double occlusion = 0;
  // Centre of the uncovered part of its top, in its own frame (x along its
  // length, m): where a camera sees its blob (written with occlusion).
  double seen_x = 0, seen_y = 0;
  // Invisible to cameras once occlusion > threshold (entity attribute
  // occlusion_threshold, percent).
  double threshold = pocket::kOcclusionThreshold;
  // The robot whose manipulator holds it, or kNobody. A held pocket is
  // carried, neither settles nor covers anything.
  uint32_t holder = kNobody;
  // Whether it has been put down since it was added (SettlePocket): a pocket
  // added by the file or by loop functions is still pending until
  // SettlePendingPockets puts it down. Not hashed: pending only until the
  // simulation has added it (EntityType::Placed).
  bool settled = false;
  bool visible() const { return occlusion <= threshold; }
  void Hash(StateHasher& h) const {
    const double v[2] = {occlusion, static_cast<double>(holder)};
    h.Add(v, sizeof v);
  }
};

// The heap model. Puts pocket `slot` down where it is in x, y and heading:
// level, its bottom on the highest top among the pockets (not held) whose
// footprints overlap its own, or on the floor; then updates the occlusion of
// every pocket. Pending pockets (SettlePendingPockets) are put down first.
// Returns the height of its bottom above the floor (m).
double SettlePocket(Space& space, uint32_t slot);
// Recomputes every pocket's occlusion from the pockets above it: the fraction
// of the sample points (kSamplesX x kSamplesY, centres of a regular grid on
// its top) that lie under a pocket, not held, whose bottom is at or above its
// top. Held pockets get 0.
void UpdatePocketOcclusion(Space& space);
// Puts down every pocket added since the last call (pending, not held),
// lowest declared height first (then slot), each as SettlePocket does, then
// updates every occlusion; returns how many. Costs a scan of the pockets
// when none is pending (none at all: nothing). The pocket entity type calls
// it once the arena is built and whenever a pocket is added while running
// (EntityType::Placed), so pockets are settled before anything reads them.
int SettlePendingPockets(Space& space);

}  // namespace colony
