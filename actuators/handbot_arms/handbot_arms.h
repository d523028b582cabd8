// Hand-bot arms actuator (control interface): bends each arm forward
// (extends it) or folds it back, each with its own motor (seed 003, 5.2.3,
// table 5.1: stall 2.27 N m, no-load 2.61 rad/s). Extension 0: the arm folded
// along the head, pointing sideways; pi/2: straight ahead. Read the arms
// with the handbot_arms sensor.
#pragma once

#include <cmath>

#include "core/control_interface.h"

namespace colony {

class HandbotArmsActuator : public Actuator {
 public:
  static constexpr int kLeft = 0, kRight = 1;
  // Target extension of arm `arm` (rad, in [0, pi/2]; outside it, the
  // nearest end, with a warning). Not a finite number: hold where it is.
  void SetExtension(int arm, double angle) { target_[Index(arm)] = angle; }
  // The fastest the arm moves (rad/s, > 0; at most the motor's no-load
  // speed, beyond it that speed with a warning).
  void SetSpeed(int arm, double speed) { speed_[Index(arm)] = speed; }

  double extension_target(int arm) const { return target_[Index(arm)]; }
  double speed(int arm) const { return speed_[Index(arm)]; }

 protected:
  static int Index(int arm) { return arm == kRight ? kRight : kLeft; }
  double target_[2] = {NAN, NAN}, speed_[2] = {NAN, NAN};
};

}  // namespace colony
