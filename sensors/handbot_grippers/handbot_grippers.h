// Hand-bot grippers sensor (control interface): each gripper's rotation
// encoder and torque, the aperture of its claws, and whether it holds
// something.
#pragma once

#include "core/control_interface.h"

namespace colony {

class HandbotGrippersSensor : public Sensor {
 public:
  static constexpr int kLeft = 0, kRight = 1;
  double rotation(int g) const { return rotation_[I(g)]; }  // rad, in (-pi, pi]
  double torque(int g) const { return torque_[I(g)]; }      // N m, the rotation motor's
  bool stalled(int g) const { return stalled_[I(g)]; }
  double aperture(int g) const { return aperture_[I(g)]; }  // rad, 0 closed .. pi/2 open
  bool holding(int g) const { return holding_[I(g)]; }      // the claws grasp something

 protected:
  static int I(int g) { return g == kRight ? kRight : kLeft; }
  double rotation_[2] = {}, torque_[2] = {}, aperture_[2] = {};
  bool stalled_[2] = {}, holding_[2] = {};
};

}  // namespace colony
