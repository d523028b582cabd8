// The eye-bot's flight computer, shared by its physics models (pointmass3d,
// dynamics3d): from the propulsion command (QuadrotorState) and the robot's
// state, the force the rotors give (world frame) and the yaw rate, within the
// robot's limits. A cascade of two proportional loops: the position error
// gives a velocity (at most the speed limits, and slow enough to brake in
// time), the velocity error an acceleration (at most max_acceleration), and
// the acceleration plus gravity the thrust, which the rotors cap: vertical
// thrust first (holding altitude), what is left for moving sideways. Rotors
// only push up: a robot whose weight is beyond max_thrust cannot climb.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/math.h"
#include "entities/eyebot/eyebot.h"

namespace colony::eyebot {

inline constexpr double kGravity = 9.81;  // m/s^2, pointmass3d's (and dynamics3d's default)
// Loop gains (1/s): position to velocity, velocity to acceleration (a
// damping ratio of 0.7), heading to yaw rate.
inline constexpr double kPositionGain = 2.0;
inline constexpr double kVelocityGain = 4.0;
inline constexpr double kYawGain = 3.0;

struct FlightOutput {
  Vec3 force = Vec3::Zero();  // N, world frame, the rotors' thrust
  double yaw_rate = 0;        // rad/s
  double thrust = 0;          // N, |force|
};

// A velocity of `limit` at most, and no faster than a stop at half the
// largest acceleration allows over the distance `error`, toward `error`.
inline double ApproachSpeed(double error, double limit, double acceleration) {
  const double d = std::abs(error);
  const double v = std::min({limit, kPositionGain * d, std::sqrt(acceleration * d)});
  return std::copysign(v, error);
}

// `gravity`: the engine's, pulling down (m/s^2).
inline FlightOutput Fly(const QuadrotorState& q, const Vec3& position, const Vec3& velocity,
                        double yaw, double mass, double gravity = kGravity) {
  FlightOutput out;
  if (q.mode == QuadrotorState::Mode::kOff) return out;
  Vec3 target_velocity;
  if (q.mode == QuadrotorState::Mode::kPosition) {
    const Vec3 e = q.target_position - position;
    const Vec2 eh = e.head<2>();
    const double dh = eh.norm();
    const double vh = ApproachSpeed(dh, q.max_speed, q.max_acceleration);
    target_velocity.head<2>() = dh > 0 ? Vec2(eh * (vh / dh)) : Vec2::Zero();
    target_velocity.z() = ApproachSpeed(e.z(), q.max_vertical_speed, q.max_acceleration);
    out.yaw_rate =
        std::clamp(kYawGain * WrapAngle(q.target_yaw - yaw), -q.max_yaw_rate, q.max_yaw_rate);
  } else {
    target_velocity = q.target_velocity;
    const double vh = target_velocity.head<2>().norm();
    if (vh > q.max_speed) target_velocity.head<2>() *= q.max_speed / vh;
    target_velocity.z() =
        std::clamp(target_velocity.z(), -q.max_vertical_speed, q.max_vertical_speed);
    out.yaw_rate = std::clamp(q.target_yaw_rate, -q.max_yaw_rate, q.max_yaw_rate);
  }
  Vec3 a = kVelocityGain * (target_velocity - velocity);
  const double an = a.norm();
  if (an > q.max_acceleration) a *= q.max_acceleration / an;
  Vec3 f = mass * (a + Vec3(0, 0, gravity));
  f.z() = std::clamp(f.z(), 0.0, q.max_thrust);
  const double side = std::sqrt(std::max(0.0, q.max_thrust * q.max_thrust - f.z() * f.z()));
  const double fh = f.head<2>().norm();
  if (fh > side) f.head<2>() *= side / fh;
  out.force = f;
  out.thrust = f.norm();
  return out;
}

}  // namespace colony::eyebot
