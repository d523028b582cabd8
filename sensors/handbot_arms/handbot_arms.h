// Hand-bot arms sensor (control interface): each arm's encoder (extension
// and speed) and its motor's torque (positive extending).
#pragma once

#include "core/control_interface.h"

namespace colony {

class HandbotArmsSensor : public Sensor {
 public:
  static constexpr int kLeft = 0, kRight = 1;
  double extension(int arm) const {
    return extension_[I(arm)];
  }  // rad, 0 folded .. pi/2 straight ahead
  double velocity(int arm) const { return velocity_[I(arm)]; }  // rad/s
  double torque(int arm) const {
    return torque_[I(arm)];
  }  // N m, averaged over the tick (noise may be added)
  bool stalled(int arm) const {
    return stalled_[I(arm)];
  }  // about its stall torque, not moving to its target

 protected:
  static int I(int arm) { return arm == kRight ? kRight : kLeft; }
  double extension_[2] = {}, velocity_[2] = {}, torque_[2] = {};
  bool stalled_[2] = {};
};

}  // namespace colony
