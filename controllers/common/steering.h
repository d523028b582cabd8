// Steering helpers shared by the swarm controllers (flocking, aggregation,
// foraging). Control-interface types only, so they compile for a real robot.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "actuators/differential_steering/differential_steering.h"
#include "core/random.h"
#include "sensors/proximity/proximity.h"

namespace colony::swarm {

// A vector in the robot's frame: x forwards, y to the left.
struct Vector {
  double x = 0, y = 0;
  Vector& operator+=(const Vector& o) {
    x += o.x;
    y += o.y;
    return *this;
  }
  Vector operator*(double k) const { return {x * k, y * k}; }
  double Length() const { return std::sqrt(x * x + y * y); }
  double Angle() const { return std::atan2(y, x); }
  static Vector FromPolar(double length, double angle) {
    return {length * std::cos(angle), length * std::sin(angle)};
  }
};

// The proximity ring as one vector: each reading along its sensor's
// direction, summed (a long vector = something close; its direction = where).
// The directions are computed once, in Bind, from the readings'
// angles (set when the sensor is attached, before the controller's Init).
class ObstacleVector {
 public:
  void Bind(const ProximitySensor& proximity) {
    proximity_ = &proximity;
    for (const auto& r : proximity.readings()) {
      cos_.push_back(std::cos(r.angle));
      sin_.push_back(std::sin(r.angle));
    }
  }
  Vector Read() const {
    Vector v;
    const auto& readings = proximity_->readings();
    // Values of 0 (of either sign) would leave both sums at +0.
    if (readings.AllZero()) return v;
    for (size_t i = 0; i < readings.size(); ++i) {
      v.x += readings[i].value * cos_[i];
      v.y += readings[i].value * sin_[i];
    }
    return v;
  }

 private:
  const ProximitySensor* proximity_ = nullptr;
  std::vector<double> cos_, sin_;
};

// Turns towards `angle` (robot frame, rad, 0 = straight ahead) while driving:
// full speed when the target is ahead, slowing as it moves aside, turning on
// the spot when it is beside or behind. The turn is proportional to the
// angle, saturating at 90 degrees. Wheel speeds stay within 2 x `speed`.
inline void SteerTowards(double angle, double speed, DifferentialSteering& wheels) {
  if (std::abs(angle) > M_PI) angle = std::remainder(angle, 2 * M_PI);
  const double forward = speed * std::max(0.0, std::cos(angle));
  const double turn = speed * std::clamp(angle / (M_PI / 2), -1.0, 1.0);
  wheels.SetLinearVelocity(forward - turn, forward + turn);
}

// A random walk: straight ahead; with probability `turn_probability` per
// tick, a turn on the spot (either way, even odds) for 1..`turn_ticks` ticks;
// and, whenever the proximity ring sees something in front (the obstacle
// vector longer than 0.05 and within 90 degrees of the front), a turn on the
// spot away from it.
class RandomWalk {
 public:
  void Configure(double speed, double turn_probability, int turn_ticks) {
    speed_ = speed;
    turn_probability_ = turn_probability;
    turn_ticks_ = std::max(turn_ticks, 1);
  }
  void Step(const Vector& obstacle, RandomStream& rng, DifferentialSteering& wheels) {
    if (obstacle.Length() > 0.05 && std::abs(obstacle.Angle()) < M_PI / 2) {
      turning_ = 0;
      const double away = obstacle.Angle() > 0 ? -1 : 1;  // obstacle on the left: turn right
      wheels.SetLinearVelocity(-away * speed_, away * speed_);
      return;
    }
    if (turning_ == 0 && rng.Bernoulli(turn_probability_)) {
      turning_ = 1 + static_cast<int>(rng.UniformInt(static_cast<uint64_t>(turn_ticks_)));
      turn_left_ = rng.Bernoulli(0.5);
    }
    if (turning_ > 0) {
      --turning_;
      const double s = turn_left_ ? 1 : -1;
      wheels.SetLinearVelocity(-s * speed_, s * speed_);
    } else {
      wheels.SetLinearVelocity(speed_, speed_);
    }
  }

 private:
  double speed_ = 0, turn_probability_ = 0;
  int turn_ticks_ = 1, turning_ = 0;
  bool turn_left_ = false;
};

}  // namespace colony::swarm
