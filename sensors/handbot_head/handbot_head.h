// Hand-bot head sensor (control interface): the head's encoder (rotation
// and speed) and its motor's torque.
#pragma once

#include "core/control_interface.h"

namespace colony {

class HandbotHeadSensor : public Sensor {
 public:
  double rotation() const { return rotation_; }  // rad, in (-pi, pi]
  double velocity() const { return velocity_; }  // rad/s
  double torque() const {
    return torque_;
  }  // N m, the motor's, averaged over the tick (noise may be added)
  // The motor gives about its stall torque and the head does not move
  // towards its target.
  bool stalled() const { return stalled_; }

 protected:
  double rotation_ = 0, velocity_ = 0, torque_ = 0;
  bool stalled_ = false;
};

}  // namespace colony
