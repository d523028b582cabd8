// Gripper (control interface): the marXbot's docking turret and its gripper.
// The turret turns the jaws around the robot; Grip() closes them on whatever
// is right in front of them (a movable object, another marXbot's ring) and
// keeps trying until something is there; Release() opens them.
#pragma once

#include "core/control_interface.h"

namespace colony {

class GripperActuator : public Actuator {
 public:
  // Turret angle from the robot's front, counter-clockwise (rad). The turret
  // turns there at its own speed; it does not turn while holding something.
  void SetTurretAngle(double angle) { turret_target_ = angle; }
  void Grip() { grip_ = true; }
  void Release() { grip_ = false; }
  double turret_target() const { return turret_target_; }
  bool gripping() const { return grip_; }

 protected:
  double turret_target_ = 0;
  bool grip_ = false;
};

}  // namespace colony
