// Hand-bot grippers actuator (control interface): each gripper turns about
// its arm (seed 003, table 5.4: stall 0.265 N m, no-load 0.604 rad/s) and
// opens or closes its claws, 0 (closed) to pi/2 (open, 90 degrees). Closing
// on something in front of the gripper's tip grasps it with 25 N (table
// 5.3); a grasped thing pulled harder than the claws hold (4 kg) slips out.
// Read them with the handbot_grippers sensor.
#pragma once

#include <cmath>

#include "core/control_interface.h"

namespace colony {

class HandbotGrippersActuator : public Actuator {
 public:
  static constexpr int kLeft = 0, kRight = 1;
  // Target rotation of gripper `gripper` about its arm (rad, modulo 2 pi).
  // Not a finite number: hold where it is.
  void SetRotation(int gripper, double angle) { rotation_[Index(gripper)] = angle; }
  // The fastest it turns (rad/s, > 0; at most the motor's no-load speed,
  // beyond it that speed with a warning).
  void SetRotationSpeed(int gripper, double speed) { speed_[Index(gripper)] = speed; }
  // Target aperture of the claws (rad, in [0, pi/2]; outside it, the nearest
  // end, with a warning).
  void SetAperture(int gripper, double angle) { aperture_[Index(gripper)] = angle; }
  void Open(int gripper) { SetAperture(gripper, M_PI / 2); }
  void Close(int gripper) { SetAperture(gripper, 0); }

  double rotation_target(int gripper) const { return rotation_[Index(gripper)]; }
  double rotation_speed(int gripper) const { return speed_[Index(gripper)]; }
  double aperture_target(int gripper) const { return aperture_[Index(gripper)]; }

 protected:
  static int Index(int g) { return g == kRight ? kRight : kLeft; }
  double rotation_[2] = {NAN, NAN}, speed_[2] = {NAN, NAN}, aperture_[2] = {M_PI / 2, M_PI / 2};
};

}  // namespace colony
