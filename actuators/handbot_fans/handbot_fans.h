// Hand-bot fans actuator (control interface): the two fans that turn the
// hanging robot about its vertical axis. Either set the torque yourself, or
// let the fans hold a heading (their built-in controller, from the IMU).
#pragma once

#include <cmath>

#include "core/control_interface.h"

namespace colony {

class HandbotFansActuator : public Actuator {
 public:
  // Yaw torque (N m, counter-clockwise seen from above); beyond the fans'
  // most (max_torque()), that, with a warning. Cancels a heading hold.
  void SetTorque(double torque) {
    torque_ = torque;
    hold_ = false;
  }
  // Hold heading `yaw` (rad, world frame, counter-clockwise from +x).
  void HoldHeading(double yaw) {
    heading_ = yaw;
    hold_ = true;
  }
  void Stop() { SetTorque(0); }

  double torque() const { return torque_; }
  bool holding_heading() const { return hold_; }
  double heading() const { return heading_; }
  double max_torque() const { return max_torque_; }

 protected:
  double torque_ = 0, heading_ = 0, max_torque_ = 0;
  bool hold_ = false;
};

}  // namespace colony
