// The manipulator component (core/component.h): the marXbot's construction
// manipulator (seeds 000, 001 and 004), a head that moves up and down
// (elevation), turns about the vertical axis between its IR side and its
// magnet side (rotation) and pitches about its horizontal axis (tilt),
// carrying a switchable magnet that holds light ferromagnetic objects.
// Commands are written by the manipulator actuator; the state below them by
// the physics models that simulate it (dynamics3d, kinematics2d, dynamics2d).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/state_hash.h"

namespace colony {

struct ManipulatorState {
  static constexpr const char* kComponentName = "manipulator";
  // The anchor (PhysicsModel::Anchor) every model that simulates the
  // manipulator gives: the head's centre, its x axis out of the magnet face.
  static constexpr const char* kHeadAnchor = "manipulator_head";
  // Commands.
  double target_elevation = 0;  // height of the magnet's centre above the floor under the robot (m)
  double target_rotation = 0;  // head rotation: 0 = magnet side facing the robot's front (rad, ccw)
  double target_tilt = 0;      // head pitch: > 0 turns the magnet face down (rad)
  bool want_magnet = false;    // engage (true) or disengage the magnet
  // Limits (set by the entity; the actuator may override from XML).
  double min_elevation = 0.03, max_elevation = 0.20;  // m
  double elevation_speed = 0.05;                      // m/s
  double rotation_speed = 1.0;                        // rad/s
  double min_tilt = -M_PI / 2, max_tilt = M_PI / 2;   // rad (marxbot::kMinTilt, kMaxTilt)
  double tilt_speed = 1.0;                            // rad/s
  double switch_time = 1.0;                           // s for the magnet to switch over
  // State, written by the engine.
  double elevation = 0.03;      // m
  double rotation = 0;          // rad
  double tilt = 0;              // rad (dynamics3d keeps it at 0: the head stays upright)
  double magnet = 0;            // 0 disengaged .. 1 engaged; it holds only when fully engaged
  uint32_t held = 0xFFFFFFFFu;  // slot of the object the magnet holds, or none
  bool holding() const { return held != 0xFFFFFFFFu; }
  // Moves the magnet dt seconds towards what is wanted (switch_time for a
  // full switch), for the models of every engine.
  void SwitchMagnet(double dt) {
    const double step = switch_time > 0 ? dt / switch_time : 1.0;
    magnet = std::clamp(magnet + (want_magnet ? step : -step), 0.0, 1.0);
    // Summing dt / switch_time falls short of 1 (or 0) by a rounding error:
    // snap, so the switch takes switch_time, not a tick more.
    if (magnet > 1.0 - 1e-9) magnet = 1.0;
    if (magnet < 1e-9) magnet = 0.0;
  }
  void Hash(StateHasher& h) const {
    const double v[5] = {elevation, rotation, magnet, want_magnet ? 1.0 : 0.0,
                         static_cast<double>(held)};
    h.Add(v, sizeof v);
    // The tilt enters the hash once it leaves 0, so runs that never tilt
    // keep the hashes they had before the tilt existed.
    if (tilt != 0 || target_tilt != 0) {
      const double t[2] = {tilt, target_tilt};
      h.Add(t, sizeof t);
    }
  }
};

}  // namespace colony
