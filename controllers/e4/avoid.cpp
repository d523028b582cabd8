// avoid: seed 000's bandwidth experiment (section 3.3.3, appendix B.1):
// drive and avoid obstacles with the 24 proximity sensors, learning what
// they see either by polling the ring in each control step (mode="poll")
// or from threshold events (mode="events", Sensor::Watch), with the same
// rule either way, so that only the traffic on the robot's bus differs.
//
// A sensor is active once its reading rose to `threshold` and until it fell
// below threshold - hysteresis. No active sensor ahead (within 90 degrees
// of the heading): drive straight; else turn on the spot away from the side
// the active sensors are on.
#include <array>
#include <cmath>
#include <string>

#include "actuators/differential_steering/differential_steering.h"
#include "core/registry.h"
#include "sensors/proximity/proximity.h"

namespace {

class Avoid : public colony::Controller {
 public:
  void Init(const colony::Params& params) override {
    speed_ = params.GetDouble("speed", 0.15, 0, 10);
    threshold_ = params.GetDouble("threshold", 0.2, 0, 1);
    hysteresis_ = params.GetDouble("hysteresis", 0.05, 0, 1);
    const std::string mode = params.GetString("mode", "poll");
    if (mode != "poll" && mode != "events")
      throw colony::ParamError("mode", mode, "mode must be \"poll\" or \"events\"");
    events_ = mode == "events";
    proximity_ = &GetSensor<colony::ProximitySensor>("proximity");
    wheels_ = &GetActuator<colony::DifferentialSteering>("differential_steering");
    // The sensors' directions are constants of the robot (read once here,
    // not polled): kept as a view of the ring, whose values are never read
    // through it.
    ring_ = proximity_->readings();
    if (ring_.size() > active_.size())
      throw std::invalid_argument("avoid handles rings of up to 24 sensors");
    if (events_) {
      colony::ThresholdWatch watch;  // every reading, both ways
      watch.threshold = threshold_;
      watch.hysteresis = hysteresis_;
      proximity_->Watch(watch);
    }
  }

  void ControlStep() override {
    if (!events_) {
      const auto& readings = proximity_->readings();
      for (size_t i = 0; i < readings.size(); ++i) {
        const double v = readings[i].value;
        active_[i] = active_[i] ? v >= threshold_ - hysteresis_ : v >= threshold_;
      }
    }
    Steer();
  }

  void OnEvent(const colony::SensorEvent& event) override {
    active_[event.reading] = event.rising;
    Steer();
  }

 private:
  void Steer() {
    double left = 0, right = 0;
    for (size_t i = 0; i < ring_.size(); ++i) {
      if (!active_[i]) continue;
      const double angle = ring_[i].angle;
      if (std::abs(angle) >= M_PI / 2) continue;
      (angle > 0 ? left : right) += std::cos(angle);
    }
    if (left == 0 && right == 0) {
      wheels_->SetLinearVelocity(speed_, speed_);
    } else if (left >= right) {
      wheels_->SetLinearVelocity(speed_, -speed_);  // obstacle on the left: turn right
    } else {
      wheels_->SetLinearVelocity(-speed_, speed_);
    }
  }

  double speed_ = 0, threshold_ = 0, hysteresis_ = 0;
  bool events_ = false;
  std::array<bool, 24> active_{};
  colony::ProximitySensor::Readings ring_;
  colony::ProximitySensor* proximity_ = nullptr;
  colony::DifferentialSteering* wheels_ = nullptr;
};

COLONY_REGISTER_CONTROLLER(
    Avoid, "avoid", "wander and avoid obstacles, polling the proximity ring or from its events",
    {{"speed", "a number in [0, 10] (m/s)", "0.15", "driving and turning wheel speed"},
     {"threshold", "a number in [0, 1]", "0.2",
      "a reading at or above it makes its sensor active (0.2: 5 cm)"},
     {"hysteresis", "a number in [0, 1]", "0.05",
      "an active sensor turns inactive below threshold - hysteresis"},
     {"mode", "poll, events", "poll",
      "poll: read the ring in each control step; events: threshold events from the ring"}});

}  // namespace
