// The hand-bot's fans component (core/component.h): two fans at the top of
// the hull, either side of the rope launcher, that turn the robot about its
// vertical axis while it hangs (seed 000, 2.3: "it can stabilise and
// orientate itself using an inertial measurement unit and two fans").
// Written by the handbot_fans actuator, applied by the physics model.
#pragma once

#include "core/state_hash.h"

namespace colony {

struct HandbotFansState {
  static constexpr const char* kComponentName = "handbot_fans";
  // Commands: a yaw torque (N m, counter-clockwise seen from above), or a
  // heading to hold (the fans' own controller, from the IMU).
  double torque = 0;
  bool hold = false;
  double heading = 0;  // rad, world frame
  // Limits (entity).
  double max_torque = 0.05;  // N m, both fans together
  // State (model): the torque the fans gave last tick.
  double applied = 0;
  void Hash(StateHasher& h) const {
    const double v[3] = {applied, hold ? 1.0 : 0.0, heading};
    h.Add(v, sizeof v);
  }
};

}  // namespace colony
