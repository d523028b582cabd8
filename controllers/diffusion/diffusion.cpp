// Diffusion: the classic first swarm controller. Drive straight while the
// proximity readings, summed as vectors, point within +-alpha of the heading
// and stay shorter than delta; otherwise turn on the spot (wheels at +v and
// -v) away from the side the obstacle is on. Turning on the spot rather than
// about one wheel keeps the body from swinging into what it is avoiding; a
// robot whose obstacles are all behind it (|angle| > 90 degrees) drives on,
// away from them, instead of spinning in front of them.
#include <algorithm>
#include <cmath>
#include <deque>
#include <mutex>
#include <vector>

#include "actuators/differential_steering/differential_steering.h"
#include "core/registry.h"
#include "sensors/proximity/proximity.h"

namespace {

class Diffusion : public colony::Controller {
 public:
  void Init(const colony::Params& params) override {
    alpha_ = params.GetDouble("alpha", 7.5, 0, 180) * M_PI / 180.0;
    delta_ = params.GetDouble("delta", 0.1, 0, 1e9);
    velocity_ = params.GetDouble("velocity", 0.05, 0, 10);
    proximity_ = &GetSensor<colony::ProximitySensor>("proximity");
    wheels_ = &GetActuator<colony::DifferentialSteering>("differential_steering");
    ring_ = &RingFor(proximity_->readings());
  }

  void ControlStep() override {
    double x = 0, y = 0;
    const auto& readings = proximity_->readings();
    // Most robots of a swarm see nothing. When every value is 0 (of either
    // sign), both sums would stay +0 (they start at +0, and adding -0 to +0
    // gives +0), and the loop of dependent additions is skipped.
    if (!readings.AllZero()) {
      for (size_t i = 0; i < readings.size(); ++i) {
        x += readings[i].value * ring_->cos[i];
        y += readings[i].value * ring_->sin[i];
      }
      x /= readings.size();
      y /= readings.size();
    }
    // Both sums +0: their atan2 and hypot are 0.
    const bool nothing = x == 0 && y == 0;
    const double angle = nothing ? 0.0 : std::atan2(y, x);
    const double length = nothing ? 0.0 : std::hypot(x, y);
    const bool clear_ahead = std::abs(angle) <= alpha_ && length < delta_;
    if (clear_ahead || std::abs(angle) > M_PI / 2) {
      wheels_->SetLinearVelocity(velocity_, velocity_);
    } else if (angle > 0) {
      wheels_->SetLinearVelocity(velocity_, -velocity_);  // obstacle on the left: turn right
    } else {
      wheels_->SetLinearVelocity(-velocity_, velocity_);  // obstacle on the right: turn left
    }
  }

 private:
  // The unit vectors of a ring of sensors' directions, which never change:
  // computed once per distinct ring and shared by every robot that has it
  // (a copy per robot cost 335 bytes of each robot).
  struct Ring {
    std::vector<float> angles, cos, sin;
  };
  static const Ring& RingFor(const colony::ProximitySensor::Readings& readings) {
    static std::mutex mutex;
    static std::deque<Ring> rings;  // deque: a ring's address stays valid
    const std::lock_guard<std::mutex> lock(mutex);
    for (const Ring& ring : rings) {
      if (std::equal(ring.angles.begin(), ring.angles.end(), readings.begin(), readings.end(),
                     [](float a, const auto& r) { return a == r.angle; }))
        return ring;
    }
    Ring& ring = rings.emplace_back();
    for (const auto& r : readings) {
      ring.angles.push_back(r.angle);
      ring.cos.push_back(std::cos(r.angle));
      ring.sin.push_back(std::sin(r.angle));
    }
    return ring;
  }

  double alpha_ = 0, delta_ = 0, velocity_ = 0;
  const Ring* ring_ = nullptr;
  const colony::ProximitySensor* proximity_ = nullptr;
  colony::DifferentialSteering* wheels_ = nullptr;
};

COLONY_REGISTER_CONTROLLER(
    Diffusion, "diffusion", "wander and avoid obstacles with the proximity ring",
    {{"velocity", "a number in [0, 10] (m/s)", "0.05", "wheel speed, driving and turning"},
     {"alpha", "a number in [0, 180] (degrees)", "7.5",
      "obstacles within +-alpha of the heading do not make it turn while they are far (below "
      "delta)"},
     {"delta", "a number >= 0", "0.1",
      "length of the mean proximity vector below which the way ahead counts as clear"}});

}  // namespace
