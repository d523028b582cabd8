// Flocking: marXbots that align and stay together through range-and-bearing.
//
// Every tick each robot broadcasts its heading (from the positioning sensor,
// used as a compass) in the first two bytes of its range-and-bearing payload,
// as a unit vector in the arena's frame (x and y, each a signed byte, 127 =
// 1: about half a degree of resolution, and no trigonometry for receivers),
// and steers towards the sum of three vectors in its own frame:
//   - alignment: `alignment` x the unit vector of the mean heading of itself
//     and every neighbour it hears (a neighbour's heading minus its own);
//   - cohesion / separation: `gain` x the mean over neighbours of
//     f(d) = (T/d)^2 - (T/d)^4 (T = target_distance, d = the neighbour's
//     range) along the neighbour's bearing: a Lennard-Jones-like term that
//     attracts beyond T, repels within it and fades far away; f is held at
//     >= -max_repulsion so one very close neighbour cannot swamp the rest;
//   - avoidance: -`avoidance` x the proximity ring's vector (walls, objects,
//     robots within 10 cm).
// It drives at `velocity`, turning in proportion to the angle of that sum
// (controllers/common/steering.h).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "actuators/range_and_bearing/range_and_bearing.h"
#include "controllers/common/steering.h"
#include "core/registry.h"
#include "sensors/positioning/positioning.h"
#include "sensors/range_and_bearing/range_and_bearing.h"

namespace {

using colony::swarm::Vector;

// One component of a heading unit vector as a signed byte (127 = 1).
uint8_t EncodeComponent(double v) {
  const double scaled = std::clamp(v, -1.0, 1.0) * 127;
  return static_cast<uint8_t>(static_cast<int8_t>(scaled + (scaled >= 0 ? 0.5 : -0.5)));
}

class Flocking : public colony::Controller {
 public:
  void Init(const colony::Params& params) override {
    velocity_ = params.GetDouble("velocity", 0.1, 0, 0.3);
    target_distance_ = params.GetDouble("target_distance", 0.4, 0.01, 100);
    gain_ = params.GetDouble("gain", 1, 0, 1e6);
    max_repulsion_ = params.GetDouble("max_repulsion", 4, 0, 1e6);
    alignment_ = params.GetDouble("alignment", 1, 0, 1e6);
    avoidance_ = params.GetDouble("avoidance", 5, 0, 1e6);
    obstacles_.Bind(GetSensor<colony::ProximitySensor>("proximity"));
    position_ = &GetSensor<colony::PositioningSensor>("positioning");
    receiver_ = &GetSensor<colony::RangeAndBearingSensor>("range_and_bearing");
    emitter_ = &GetActuator<colony::RangeAndBearingActuator>("range_and_bearing");
    wheels_ = &GetActuator<colony::DifferentialSteering>("differential_steering");
    if (emitter_->size() < 2) {
      throw std::runtime_error(
          "the range_and_bearing actuator's payload holds " + std::to_string(emitter_->size()) +
          " byte(s); flocking sends its heading in 2 (give the actuator data_size=\"2\" or more)");
    }
  }

  void ControlStep() override {
    const double yaw = position_->yaw();
    const double c = std::cos(yaw), sn = std::sin(yaw);
    emitter_->SetByte(0, EncodeComponent(c));
    emitter_->SetByte(1, EncodeComponent(sn));

    // Neighbours' headings summed in the arena's frame (in 1/127ths); the
    // cohesion term in the robot's (float trigonometry: bearings are floats).
    int sum_x = 0, sum_y = 0;
    Vector cohesion;
    int neighbours = 0;
    for (const auto& packet : receiver_->packets()) {
      if (packet.data.size() < 2 || packet.range <= 0) continue;
      sum_x += static_cast<int8_t>(packet.data[0]);
      sum_y += static_cast<int8_t>(packet.data[1]);
      const double f = LennardJones(packet.range);
      cohesion += Vector{f * std::cos(packet.bearing), f * std::sin(packet.bearing)};
      ++neighbours;
    }
    // Sum of its own heading and its neighbours', in its own frame.
    const double hx = sum_x / 127.0, hy = sum_y / 127.0;
    const Vector heading{1 + hx * c + hy * sn, hy * c - hx * sn};
    Vector direction;
    const double length = heading.Length();
    if (length > 1e-9) direction = heading * (alignment_ / length);
    if (neighbours > 0) direction += cohesion * (gain_ / neighbours);
    direction += obstacles_.Read() * -avoidance_;
    colony::swarm::SteerTowards(direction.Angle(), velocity_, *wheels_);
  }

 private:
  // > 0 attracts (the neighbour is farther than the target distance).
  double LennardJones(double d) const {
    const double s = (target_distance_ / d) * (target_distance_ / d);
    return std::max(s - s * s, -max_repulsion_);
  }

  double velocity_ = 0, target_distance_ = 0, gain_ = 0, max_repulsion_ = 0, alignment_ = 0,
         avoidance_ = 0;
  colony::swarm::ObstacleVector obstacles_;
  const colony::PositioningSensor* position_ = nullptr;
  const colony::RangeAndBearingSensor* receiver_ = nullptr;
  colony::RangeAndBearingActuator* emitter_ = nullptr;
  colony::DifferentialSteering* wheels_ = nullptr;
};

COLONY_REGISTER_CONTROLLER(Flocking, "flocking",
                           "align with and keep near the neighbours heard through "
                           "range-and-bearing (each sends its heading)",
                           {{"velocity", "0..0.3 (m/s)", "0.1", "forward speed"},
                            {"target_distance", "0.01..100 (m)", "0.4",
                             "T, where cohesion changes sign"},
                            {"gain", ">= 0", "1", "weight of the cohesion / separation term"},
                            {"max_repulsion", ">= 0", "4",
                             "floor of f (so one very close neighbour cannot swamp the rest)"},
                            {"alignment", ">= 0", "1", "weight of the alignment term"},
                            {"avoidance", ">= 0", "5", "weight of the obstacle term"}});

}  // namespace
