// The marXbot's construction manipulator in the 2D engines (kinematics2d,
// dynamics2d), simulated kinematically and the same way in both; each
// engine's marXbot model calls it (kinematics2d_model.cpp,
// dynamics2d_model.cpp).
//
// After the engine moved the robots, each head moves towards its elevation,
// rotation and tilt targets at its speeds, the magnet switches over
// switch_time, and the fully engaged magnet holds a pocket it lies on
// (marxbot.h: kMagnetReach, kMagnetMaxSlant, kMagnetStripReach). A held
// pocket is carried: every tick its top is against the magnet face, its
// centre keeps its offset from the face's centre and its heading relative to
// the robot (both as they were when the magnet took it), and its
// PocketState::holder names the robot. When the magnet is no longer fully
// engaged the pocket is let go where it is (x, y and heading; moved ahead
// along the robot's heading, in 5 mm steps, if it would overlap the robot's
// body) and settles on the heap (SettlePocket). The head is not a body: it
// collides with nothing. Construction cubes are not held in these engines.
#pragma once

#include <cstdint>
#include <functional>
#include <string_view>
#include <vector>

#include "core/space.h"

namespace colony {

struct ManipulatorState;

class Manipulator2d {
 public:
  // Tells the engine that entity `s` is now carried (true) or no longer.
  using CarriedHook = std::function<void(uint32_t s, bool carried)>;

  // Robot `s` enters the engine (ignored without a manipulator).
  void Add(Space& space, uint32_t s);
  // Entity `s` leaves the engine: a robot drops what it holds, a held pocket
  // is let go of.
  void Leaving(Space& space, uint32_t s, const CarriedHook& carried);
  // One tick of every manipulator, after the robots moved.
  void Step(Space& space, double dt, const CarriedHook& carried);
  // The head's centre (ManipulatorState::kHeadAnchor): on its vertical pivot
  // kHeadPivotX ahead of the robot's axis, `elevation` above the robot's
  // base; its x axis (out of the magnet face) turned by the rotation about
  // the vertical, then pitched by the tilt about the head's own y axis.
  static bool Anchor(const Space& space, uint32_t s, std::string_view name, Pose& pose);

 private:
  // Where a held pocket sits relative to the magnet face's centre, in the
  // robot's heading frame, as it was when the magnet took it.
  struct Carry {
    Vec2 offset = Vec2::Zero();  // of the pocket's centre from the face's centre (m)
    double yaw = 0;              // pocket's heading minus the robot's (rad)
    bool warned = false;         // about a drop onto something solid
  };

  void Grab(Space& space, uint32_t s, ManipulatorState& m, const CarriedHook& carried);
  void CarryAlong(Space& space, uint32_t s, const ManipulatorState& m, double dt) const;
  // Returns false, holding on, when the pocket would land on something solid
  // other than pockets (unless `forced`: the robot is going away).
  bool Drop(Space& space, uint32_t s, ManipulatorState& m, const CarriedHook& carried, bool forced);

  std::vector<uint32_t> slots_;  // robots with a manipulator, in slot order
  std::vector<Carry> carry_;     // per space slot
  std::vector<uint32_t> near_;   // scratch
};

}  // namespace colony
