// Positioning sensor (control interface): the robot's pose in the arena, as
// from a tracking system (ground truth plus optional noise).
#pragma once

#include "core/control_interface.h"

namespace colony {

class PositioningSensor : public Sensor {
 public:
  double x() const { return x_; }  // m
  double y() const { return y_; }  // m
  double z() const { return z_; }  // m
  // Heading: rotation about the vertical axis, counter-clockwise from +x (rad, (-pi, pi]).
  double yaw() const { return yaw_; }

 protected:
  double x_ = 0, y_ = 0, z_ = 0, yaw_ = 0;
};

}  // namespace colony
