// wall_stop: seed 000's latency experiment (section 3.3.4). Drive straight
// at `speed` and stop for good once a front proximity sensor (the two that
// flank the front, readings 0 and 23 of the marXbot's ring) sees an object
// at `distance` or closer, either by polling the ring in each control step
// (mode="poll", at the controller's rate) or by asking the ring for an event
// when one of those readings crosses the threshold (mode="events",
// Sensor::Watch): then the periodic step never reads the ring.
#include <cmath>
#include <string>

#include "actuators/differential_steering/differential_steering.h"
#include "core/registry.h"
#include "sensors/proximity/proximity.h"

namespace {

class WallStop : public colony::Controller {
 public:
  void Init(const colony::Params& params) override {
    speed_ = params.GetDouble("speed", 0.15, 0, 10);
    // The ring reads 0.01 m / d (sensors/proximity): d <= distance is a
    // reading >= 0.01 / distance.
    threshold_ = 0.01 / params.GetDouble("distance", 0.03, 1e-4, 1);
    const std::string mode = params.GetString("mode", "poll");
    if (mode != "poll" && mode != "events")
      throw colony::ParamError("mode", mode, "mode must be \"poll\" or \"events\"");
    events_ = mode == "events";
    proximity_ = &GetSensor<colony::ProximitySensor>(params.GetString("sensor", "proximity"));
    wheels_ = &GetActuator<colony::DifferentialSteering>("differential_steering");
    // The robot sets off on the first tick whatever the controller's rate
    // and phase: its steps and the ring's samples fall anywhere along the way.
    Drive();
    if (events_) {
      for (int front : {0, kLastFront}) {
        colony::ThresholdWatch watch;
        watch.reading = front;
        watch.threshold = threshold_;
        watch.crossing = colony::Crossing::kRising;
        proximity_->Watch(watch);
      }
    }
  }

  void ControlStep() override {
    if (!events_ && !stopped_) {
      const auto& readings = proximity_->readings();
      stopped_ = readings[0].value >= threshold_ || readings[kLastFront].value >= threshold_;
    }
    Drive();
  }

  void OnEvent(const colony::SensorEvent& event) override {
    (void)event;  // only the front readings' rising crossings are watched
    stopped_ = true;
    Drive();
  }

  void RecordValues(colony::RobotValues& values) const override {
    values.SetLabel("state", stopped_ ? "stopped" : "driving");
  }

 private:
  static constexpr int kLastFront = 23;
  void Drive() { wheels_->SetLinearVelocity(stopped_ ? 0 : speed_, stopped_ ? 0 : speed_); }

  double speed_ = 0, threshold_ = 0;
  bool events_ = false, stopped_ = false;
  colony::ProximitySensor* proximity_ = nullptr;
  colony::DifferentialSteering* wheels_ = nullptr;
};

COLONY_REGISTER_CONTROLLER(
    WallStop, "wall_stop",
    "drive straight, stop when a front proximity sensor sees an object (polling or events)",
    {{"speed", "a number in [0, 10] (m/s)", "0.15", "driving speed"},
     {"distance", "a number in [0.0001, 1] (m)", "0.03",
      "stop when a front sensor reads this distance or less"},
     {"mode", "poll, events", "poll",
      "poll: read the ring in each control step; events: a threshold event from the ring"},
     {"sensor", "a sensor label", "proximity", "the proximity ring to use"}});

}  // namespace
