// Gripper sensor (control interface): where the marXbot's turret points and
// whether its gripper holds something.
#pragma once

#include "core/control_interface.h"

namespace colony {

class GripperSensor : public Sensor {
 public:
  double turret_angle() const {
    return turret_;
  }  // from the robot's front, counter-clockwise (rad)
  bool holding() const { return holding_; }

 protected:
  double turret_ = 0;
  bool holding_ = false;
};

}  // namespace colony
