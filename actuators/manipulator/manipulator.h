// Manipulator actuator (control interface): the marXbot's magnetic
// construction manipulator. Its head moves up and down (elevation), turns
// about the vertical axis (rotation) and pitches about its horizontal axis
// (tilt); one side of the head carries a switchable magnet that holds light
// ferromagnetic objects (construction cubes in dynamics3d, pockets in the 2D engines), the opposite
// side 6 IR proximity sensors (sensors/manipulator). Commands are targets: the head moves towards
// them at its own speeds and the magnet takes about 1 s to switch over; read where it is and
// whether it holds something with the manipulator sensor.
#pragma once

#include <cmath>

#include "core/control_interface.h"

namespace colony {

class ManipulatorActuator : public Actuator {
 public:
  // Head rotations that turn one side of the head to the robot's front.
  static constexpr double kMagnetSide = 0;  // magnet to the front, IR sensors to the back (rad)
  static constexpr double kIrSide = M_PI;   // IR sensors to the front, magnet to the back (rad)

  // Target height of the magnet's centre above the floor under the robot (m),
  // clamped to [min_elevation(), max_elevation()]. A value that is not a
  // finite number holds the head where it is.
  void SetElevation(double elevation) { elevation_target_ = elevation; }
  // Target head rotation, counter-clockwise from "magnet side to the front"
  // (rad), taken modulo 2 pi; the head turns the shorter way. A value that is
  // not a finite number holds the head where it is.
  void SetRotation(double angle) { rotation_target_ = angle; }
  // Target head pitch about its horizontal axis (rad): 0 upright, > 0 turns
  // the magnet face down (pi/2: it looks straight down, to lie on a pocket's
  // top), < 0 turns the IR face down. Beyond [min_tilt(), max_tilt()] the head
  // goes to the nearer limit and a warning says so, once per robot. A value
  // that is not a finite number holds the head where it is. dynamics3d does
  // not simulate the tilt (the head stays upright, with a warning).
  void SetTilt(double angle) { tilt_target_ = angle; }
  void SetMagnetSide() { SetRotation(kMagnetSide); }
  void SetIrSide() { SetRotation(kIrSide); }
  // Switch the magnet on (holds a ferromagnetic face it touches once fully
  // engaged) or off (drops what it holds).
  void EngageMagnet() { magnet_ = true; }
  void DisengageMagnet() { magnet_ = false; }

  double elevation_target() const { return elevation_target_; }
  double rotation_target() const { return rotation_target_; }
  double tilt_target() const { return tilt_target_; }
  bool magnet_wanted() const { return magnet_; }
  // The elevation range of this robot's manipulator (m).
  double min_elevation() const { return min_elevation_; }
  double max_elevation() const { return max_elevation_; }
  // The tilt range of this robot's manipulator (rad).
  double min_tilt() const { return min_tilt_; }
  double max_tilt() const { return max_tilt_; }

 protected:
  double elevation_target_ = NAN;  // until a command: stay
  double rotation_target_ = NAN;
  double tilt_target_ = NAN;
  bool magnet_ = false;
  double min_elevation_ = 0, max_elevation_ = 0;
  double min_tilt_ = 0, max_tilt_ = 0;
};

}  // namespace colony
