// The hand-bot's arms component (core/component.h): the head, which turns
// both arms about the robot's forward axis; the two arms, each bent forward
// (extended) by its own motor; and at the end of each arm a gripper that
// turns about the arm and opens and closes its claws (seed 003, 5.2.3-5.2.4;
// seed 000, 2.3). Each motorised joint follows a target at a commanded
// speed, with the torque its motor can give at its speed (a DC motor's
// line from stall torque at rest to none at no-load speed). Commands are
// written by the handbot_head, handbot_arms and handbot_grippers actuators;
// the state by the physics model (dynamics3d); the same-named sensors read it.
#pragma once

#include <cstdint>

#include "core/state_hash.h"

namespace colony {

// A DC motor: the line through (0 rad/s, stall) and (no_load_speed, 0 N m).
struct MotorFigures {
  double stall_torque = 1;   // N m
  double no_load_speed = 1;  // rad/s
  // The most torque it gives while the joint turns at `speed` (rad/s) in the
  // direction it drives: less the faster it goes, none at no-load speed;
  // braking (the joint turning against it) or holding, its stall torque
  // (the driver limits the current to the stall current).
  double TorqueAt(double speed) const {
    if (speed <= 0) return stall_torque;
    return speed >= no_load_speed ? 0.0 : stall_torque * (1.0 - speed / no_load_speed);
  }
};

struct HandbotJoint {
  // Commands.
  double target = 0;  // rad
  double speed = 0;  // rad/s, the fastest to move towards the target (<= the motor's no-load speed)
  // Limits (entity).
  double min = 0, max = 0;  // rad; min == max: turns without limit
  MotorFigures motor;
  // State (model).
  double position = 0;   // rad
  double velocity = 0;   // rad/s
  double torque = 0;     // N m, the motor's torque about the joint, averaged over the tick
  bool stalled = false;  // the motor gives its most and the joint does not move towards the target
  bool limited() const { return max > min; }
  void Hash(StateHasher& h) const {
    const double v[5] = {position, velocity, torque, stalled ? 1.0 : 0.0, target};
    h.Add(v, sizeof v);
  }
};

struct HandbotArmsState {
  static constexpr const char* kComponentName = "handbot_arms";
  static constexpr int kLeft = 0, kRight = 1;
  static constexpr uint32_t kNothing = 0xFFFFFFFFu;
  static constexpr uint32_t kFixedThing =
      0xFFFFFFFEu;  // grasping something fixed with no slot of its own

  HandbotJoint head;      // rotation of the head (both arms) about the robot's forward axis
  HandbotJoint arm[2];    // extension: 0 folded (pointing sideways), pi/2 straight ahead
  HandbotJoint wrist[2];  // rotation of each gripper about its arm
  // The claws of each gripper.
  struct Claws {
    double target = 1.5707963267948966;    // rad, 0 closed .. pi/2 open
    double speed = 1.0;                    // rad/s
    double aperture = 1.5707963267948966;  // rad (model)
    uint32_t held = kNothing;  // slot of the grasped entity, kFixedThing, or kNothing (model)
    bool holding() const { return held != kNothing; }
  } claws[2];
  double grasp_force = 25;  // N, the claws' grip (seed 003, table 5.3)
  double holding_limit =
      39.2;  // N, the pull beyond which a grasped thing slips out (4 kg, seed 000)

  void Hash(StateHasher& h) const {
    head.Hash(h);
    for (int k = 0; k < 2; ++k) {
      arm[k].Hash(h);
      wrist[k].Hash(h);
      const double v[2] = {claws[k].aperture, static_cast<double>(claws[k].held)};
      h.Add(v, sizeof v);
    }
  }
};

}  // namespace colony
