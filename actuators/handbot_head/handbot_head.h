// Hand-bot head actuator (control interface): turns the head, and with it
// both arms, about the robot's forward axis (seed 003, 5.2.3, table 5.2:
// stall 1.44 N m, no-load 2.85 rad/s). Read where it is, its speed and its
// torque with the handbot_head sensor.
#pragma once

#include <cmath>

#include "core/control_interface.h"

namespace colony {

class HandbotHeadActuator : public Actuator {
 public:
  // Target rotation (rad, counter-clockwise seen from behind the robot;
  // taken modulo 2 pi, the head turns the shorter way). Not a finite number:
  // hold where it is.
  void SetRotation(double angle) { target_ = angle; }
  // The fastest it turns towards the target (rad/s, > 0): at most the motor's
  // no-load speed (beyond it, that speed, with a warning). Under load it
  // turns slower: the motor gives less torque the faster it turns.
  void SetSpeed(double speed) { speed_ = speed; }

  double rotation_target() const { return target_; }
  double speed() const { return speed_; }

 protected:
  double target_ = NAN, speed_ = NAN;  // NAN speed: the robot's nominal speed
};

}  // namespace colony
