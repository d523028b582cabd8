// Eye-bot pan-tilt actuator (control interface): turns the head under the
// eye-bot that carries its colour camera and laser pointer. Pan turns it
// about the robot's vertical axis, counter-clockwise from the robot's front;
// tilt from straight down (0) to horizontal (pi/2). The head moves toward
// the targets at the unit's speeds (the robot's pan_speed and tilt_speed),
// pan the shorter way round.
#pragma once

#include <cmath>

#include "core/control_interface.h"

namespace colony {

class EyebotPanTiltActuator : public Actuator {
 public:
  // Target pan (rad): any value, wrapped to (-pi, pi].
  void SetPan(double angle) { target_pan_ = Wrap(angle); }
  // Target tilt (rad) in [0, pi/2]: 0 looks straight down, pi/2 ahead
  // (horizontally). Beyond that range, the nearest limit, with a warning
  // once per robot.
  void SetTilt(double angle) { target_tilt_ = angle; }

  double target_pan() const { return target_pan_; }
  double target_tilt() const { return target_tilt_; }
  // Where the head is (rad), as of this tick's act step.
  double pan() const { return pan_; }
  double tilt() const { return tilt_; }

 protected:
  static double Wrap(double a) {
    const double w = std::remainder(a, 2 * M_PI);  // [-pi, pi]; NaN stays NaN
    return w <= -M_PI ? w + 2 * M_PI : w;
  }
  double target_pan_ = 0, target_tilt_ = 0;
  double pan_ = 0, tilt_ = 0;
};

}  // namespace colony
