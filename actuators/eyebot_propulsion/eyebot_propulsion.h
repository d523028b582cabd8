// Eye-bot propulsion actuator (control interface): the quadrotor's flight
// computer, commanded either by a position to fly to and hold (position
// mode) or by a velocity to fly at (speed mode), as on the real eye-bot.
// The last call chooses the mode. The flight computer keeps within the
// robot's limits (max_speed() and the others); a commanded velocity or yaw
// rate beyond them is flown at the limit, with a warning once per robot. A
// value that is not a finite number is ignored, with a warning once per
// robot: the robot keeps its previous command.
//
// Frames: world frame, metres and radians; yaw counter-clockwise from +x
// seen from above. Speeds in m/s, turn rates in rad/s.
#pragma once

#include <array>

#include "core/control_interface.h"

namespace colony {

class EyebotPropulsionActuator : public Actuator {
 public:
  enum class Mode { kOff, kPosition, kSpeed };

  // Position mode: fly to (x, y, z), the position of the robot's feet, and
  // hold it. Coming from another mode, the heading to hold is the one the
  // robot has when the command is applied (unless SetTargetYaw says).
  void SetTargetPosition(double x, double y, double z) {
    EnterPosition();
    target_ = {x, y, z};
    pending_ = Pending::kNone;
  }
  // Position mode: turn to heading `yaw` and hold it. Coming from another
  // mode, the position to hold is where the robot is when the command is
  // applied (unless SetTargetPosition says).
  void SetTargetYaw(double yaw) {
    EnterPosition();
    target_yaw_ = yaw;
    pending_yaw_ = false;
  }
  // Position mode: fly to the point `forward`, `left`, `up` (m) from where
  // the robot is when the command is applied, in its heading frame (forward
  // along its heading, left 90 degrees counter-clockwise from it, up
  // vertical). target_position() gives the world point from the next tick.
  void SetRelativePosition(double forward, double left, double up) {
    EnterPosition();
    relative_ = {forward, left, up};
    pending_ = Pending::kRelative;
  }
  // Speed mode: fly at (vx, vy, vz) (world frame); coming from another mode,
  // without turning (unless SetYawRate says).
  void SetVelocity(double vx, double vy, double vz) {
    EnterSpeed();
    velocity_ = {vx, vy, vz};
  }
  // Speed mode: turn at `rate` (counter-clockwise positive); coming from
  // another mode, without moving (unless SetVelocity says).
  void SetYawRate(double rate) {
    EnterSpeed();
    yaw_rate_ = rate;
  }
  // Rotors off: the robot falls (or stays on what it stands on).
  void Off() { mode_ = Mode::kOff; }

  Mode mode() const { return mode_; }
  // Position mode's targets (world frame): as commanded; after
  // SetRelativePosition, or for what a mode change leaves to be where the
  // robot is, the world values once applied (the next tick).
  const std::array<double, 3>& target_position() const { return target_; }
  double target_yaw() const { return target_yaw_; }
  // Speed mode's commands, as given (the robot flies within its limits).
  const std::array<double, 3>& velocity() const { return velocity_; }
  double yaw_rate() const { return yaw_rate_; }

  // The robot's limits: fastest horizontal speed, fastest climb or descent,
  // fastest turn, the rotors' most thrust (N, all four).
  double max_speed() const { return max_speed_; }
  double max_vertical_speed() const { return max_vertical_speed_; }
  double max_yaw_rate() const { return max_yaw_rate_; }
  double max_thrust() const { return max_thrust_; }

 protected:
  // What position mode still has to take from where the robot is when the
  // command is applied.
  enum class Pending { kNone, kHere, kRelative };

  void EnterPosition() {
    if (mode_ == Mode::kPosition) return;
    mode_ = Mode::kPosition;
    pending_ = Pending::kHere;
    pending_yaw_ = true;
  }
  void EnterSpeed() {
    if (mode_ == Mode::kSpeed) return;
    mode_ = Mode::kSpeed;
    velocity_ = {0, 0, 0};
    yaw_rate_ = 0;
  }

  Mode mode_ = Mode::kOff;
  std::array<double, 3> target_{0, 0, 0};
  std::array<double, 3> relative_{0, 0, 0};
  double target_yaw_ = 0;
  Pending pending_ = Pending::kNone;
  bool pending_yaw_ = false;
  std::array<double, 3> velocity_{0, 0, 0};
  double yaw_rate_ = 0;
  double max_speed_ = 0, max_vertical_speed_ = 0, max_yaw_rate_ = 0, max_thrust_ = 0;
};

}  // namespace colony
