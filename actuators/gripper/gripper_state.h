// The gripper component (core/component.h): a docking turret and gripper,
// written by the gripper actuator, acted on by the physics models that
// simulate it (they set `held`), read by the gripper sensor.
#pragma once

#include <cstdint>

#include "core/state_hash.h"

namespace colony {

struct GripperState {
  static constexpr const char* kComponentName = "gripper";
  double turret = 0;            // turret angle from the robot's front, counter-clockwise (rad)
  double turret_speed = 1;      // most turret rotation per second (rad/s)
  double reach = 0.02;          // how far beyond the body the jaws close on something (m)
  bool want_grip = false;       // the controller asks to hold what is in front of the jaws
  uint32_t held = 0xFFFFFFFFu;  // slot of the held entity, or none
  bool holding() const { return held != 0xFFFFFFFFu; }
  void Hash(StateHasher& h) const {
    const double v[3] = {turret, want_grip ? 1.0 : 0.0, static_cast<double>(held)};
    h.Add(v, sizeof v);
  }
};

}  // namespace colony
