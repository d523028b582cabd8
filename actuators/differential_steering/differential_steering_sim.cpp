// Simulated differential steering: wheel speed commands beyond +-max_speed
// run at max_speed, with a warning once per robot (a controller written for
// cm/s gives 100 times the speed it means: that must not pass unnoticed);
// the wheels reach them no faster than max_acceleration;
// the engine then moves the robot with the resulting wheel speeds. A robot
// without power (DriveState::powered false) is commanded to stop.
#include <algorithm>
#include <cmath>

#include "actuators/differential_steering/differential_steering.h"
#include "core/device.h"
#include "core/log.h"
#include "core/simulation.h"
#include "core/text.h"

namespace colony {
namespace {

struct SteeringInstance : DifferentialSteering, InstanceBaseWithoutStream {
  using Interface = DifferentialSteering;  // draws no random numbers: no stream
  bool warned_speed = false, warned_not_finite = false;
};

class SteeringSystem : public ActuatorSystem {
 public:
  void Configure(const ConfigNode& node) override {
    max_speed_ = node.GetDouble("max_speed", -1, Range::Positive());
    max_acceleration_ = node.GetDouble("max_acceleration", 3.0, Range::Positive());
  }
  std::vector<std::string> NeededComponents() const override {
    return {DriveState::kComponentName};
  }
  Actuator* Attach(EntityHandle robot, const RandomStream& rng) override {
    return &instances_.Add(robot, rng);
  }
  void Detach(Actuator* a) override { instances_.Remove(static_cast<DifferentialSteering*>(a)); }
  size_t size() const override { return instances_.size(); }

  void Act(size_t begin, size_t end) override {
    Space& space = sim().space();
    const double max_delta = max_acceleration_ * sim().dt();
    for (size_t k = begin; k < end; ++k) {
      SteeringInstance& s = instances_[k];
      if (!s.alive) continue;
      DriveState& d = *space.drive(s.robot.index);
      const double limit = max_speed_ > 0 ? std::min(max_speed_, d.max_speed) : d.max_speed;
      // NaN commands stop the wheels rather than poisoning the state; speeds
      // beyond the limit run at it. Both say so once per robot (out of line:
      // the check itself is inlined).
      auto clamp = [&](double v) {
        return std::abs(v) <= limit ? v : OutOfRange(s, space, v, limit);
      };
      // Without power (e.g. an empty battery) the wheels are commanded to stop.
      d.target_left = d.powered ? clamp(s.target_left()) : 0.0;
      d.target_right = d.powered ? clamp(s.target_right()) : 0.0;
      d.left += std::clamp(d.target_left - d.left, -max_delta, max_delta);
      d.right += std::clamp(d.target_right - d.right, -max_delta, max_delta);
    }
  }

 private:
  // The speed a wheel runs at for a command `v` that is not within +-limit
  // (or not a number), with the robot's warning the first time.
  [[gnu::cold, gnu::noinline]] static double OutOfRange(SteeringInstance& s, const Space& space,
                                                        double v, double limit) {
    if (!std::isfinite(v)) {
      if (!s.warned_not_finite) {
        s.warned_not_finite = true;
        LogWarning("robot '" + space.id(s.robot.index) +
                   "': differential_steering wheel speed is not a finite number; that wheel "
                   "stops (said once per robot)");
      }
      return 0.0;
    }
    if (!s.warned_speed) {
      s.warned_speed = true;
      LogWarning("robot '" + space.id(s.robot.index) + "': differential_steering wheel speed " +
                 FormatNumber(v) + " m/s is beyond the wheels' limit, " + FormatNumber(limit) +
                 " m/s; the wheel runs at " + FormatNumber(std::clamp(v, -limit, limit)) +
                 " m/s (said once per robot)");
    }
    return std::clamp(v, -limit, limit);
  }

  double max_speed_ = -1;
  double max_acceleration_ = 3.0;
  InstanceStore<SteeringInstance> instances_;
};

COLONY_REGISTER_ACTUATOR(
    SteeringSystem, "differential_steering", "default",
    "left and right wheel speeds (m/s), at most max_speed (beyond: a warning) and limited in "
    "acceleration",
    DeviceInterface{"actuators/differential_steering/differential_steering.h",
                    "colony::DifferentialSteering",
                    {"SetLinearVelocity(left, right): each wheel's speed (m/s)",
                     "target_left(), target_right(): the last speeds set (m/s)"}},
    (std::vector<AttributeDoc>{
        {"max_speed", "a number > 0 (m/s)", "the robot's (marXbot: 0.3)",
         "speed limit of each wheel"},
        {"max_acceleration", "a number > 0 (m/s^2)", "3", "how fast a wheel changes speed"},
    }));

}  // namespace
}  // namespace colony
