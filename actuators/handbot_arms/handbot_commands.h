// What the hand-bot's head, arms and grippers actuators share: turning a
// controller's speed and target into what a joint can do, saying so (once
// per robot and joint) when it cannot.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>

#include "actuators/handbot_arms/handbot_arms_state.h"
#include "core/log.h"
#include "core/text.h"

namespace colony::handbot_commands {

// Warnings already given, per robot and joint.
struct Warned {
  bool speed = false, range = false;
};

// The speed the joint moves at: `asked` (rad/s) if the motor can, the
// joint's nominal speed if `asked` is not a finite number; beyond the motor's
// no-load speed that speed, below 0 none, each with a warning.
inline double Speed(double asked, double nominal, const HandbotJoint& joint,
                    const std::string& robot, const char* what, Warned& warned) {
  if (!std::isfinite(asked)) return nominal;
  const double fastest = joint.motor.no_load_speed;
  if (asked >= 0 && asked <= fastest) return asked;
  if (!warned.speed) {
    warned.speed = true;
    LogWarning("robot '" + robot + "': " + what + " speed " + FormatNumber(asked) +
               " rad/s is outside [0, " + FormatNumber(fastest) +
               "] (the motor's no-load speed); it moves at " +
               FormatNumber(std::clamp(asked, 0.0, fastest)) + " rad/s (said once per robot)");
  }
  return std::clamp(asked, 0.0, fastest);
}

// A target within [lo, hi], with a warning when `asked` is outside; a value
// that is not a finite number keeps `current`.
inline double Target(double asked, double current, double lo, double hi, const std::string& robot,
                     const char* what, Warned& warned) {
  if (!std::isfinite(asked)) return current;
  if (asked >= lo && asked <= hi) return asked;
  if (!warned.range) {
    warned.range = true;
    LogWarning("robot '" + robot + "': " + what + " " + FormatNumber(asked) + " rad is outside [" +
               FormatNumber(lo) + ", " + FormatNumber(hi) + "]; it goes to " +
               FormatNumber(std::clamp(asked, lo, hi)) + " rad (said once per robot)");
  }
  return std::clamp(asked, lo, hi);
}

}  // namespace colony::handbot_commands
