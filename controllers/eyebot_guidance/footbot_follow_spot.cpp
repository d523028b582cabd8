// footbot_follow_spot: the foot-bot's part in the guidance experiment
// (experiments/eyebot_guidance.xml). It wanders (diffusion: straight on,
// turning away from what its proximity ring sees) until its omnidirectional
// camera sees a blob of the laser's colour, then drives to it, steering by its
// bearing and still avoiding obstacles, and stops `stop_distance` from it. A
// spot lost from sight (hidden by another robot, or switched off) is driven
// toward where it was seen for `memory_steps` more control steps before it
// wanders again.
//   params: velocity (m/s, 0.2), spot_color (a colour, 255,0,0),
//           color_tolerance (per channel, 60), stop_distance (m, 0.3),
//           avoid_distance (proximity value above which it turns away, 0.3),
//           memory_steps (30)
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "actuators/differential_steering/differential_steering.h"
#include "core/color.h"
#include "core/registry.h"
#include "sensors/omnidirectional_camera/omnidirectional_camera.h"
#include "sensors/proximity/proximity.h"

namespace colony {
namespace {

class FootbotFollowSpot : public Controller {
 public:
  void Init(const Params& params) override {
    velocity_ = params.GetDouble("velocity", 0.2, 0, 10);
    const std::string color = params.GetString("spot_color", "255,0,0");
    const std::optional<Color> spot = ParseColor(color);
    if (!spot) {
      throw ParamError(
          "spot_color", color,
          "parameter 'spot_color': '" + color + "' is not a colour; accepted: " + kColorAccepted);
    }
    spot_[0] = spot->r, spot_[1] = spot->g, spot_[2] = spot->b;
    tolerance_ = params.GetDouble("color_tolerance", 60, 0, 255);
    stop_distance_ = params.GetDouble("stop_distance", 0.3, 0, 100);
    avoid_ = params.GetDouble("avoid_distance", 0.3, 0, 1);
    memory_steps_ = static_cast<int>(params.GetInt("memory_steps", 30, 0, 1000000));
    proximity_ = &GetSensor<ProximitySensor>("proximity");
    camera_ = &GetSensor<OmnidirectionalCamera>("omnidirectional_camera");
    wheels_ = &GetActuator<DifferentialSteering>("differential_steering");
  }

  void Reset() override { remembered_ = 0; }

  void ControlStep() override {
    // The nearest blob of the spot's colour.
    const OmnidirectionalCamera::Blob* spot = nullptr;
    for (const auto& b : camera_->blobs()) {
      if (std::abs(b.red - spot_[0]) > tolerance_ || std::abs(b.green - spot_[1]) > tolerance_ ||
          std::abs(b.blue - spot_[2]) > tolerance_)
        continue;
      if (!spot || b.distance < spot->distance) spot = &b;
    }
    if (spot) {
      bearing_ = spot->bearing;
      distance_ = spot->distance;
      remembered_ = memory_steps_;
    } else if (remembered_ > 0) {
      --remembered_;
    }
    // What the proximity ring sees, summed as a vector.
    double x = 0, y = 0, strongest = 0;
    for (const auto& r : proximity_->readings()) {
      x += r.value * std::cos(r.angle);
      y += r.value * std::sin(r.angle);
      strongest = std::max<double>(strongest, r.value);
    }
    const double obstacle = std::atan2(y, x);
    const bool blocked = strongest > avoid_ && std::abs(obstacle) < M_PI / 2;
    if (remembered_ > 0 && distance_ <= stop_distance_) {
      wheels_->SetLinearVelocity(0, 0);  // arrived
      return;
    }
    if (blocked) {
      // Turn on the spot away from the obstacle.
      if (obstacle > 0) {
        wheels_->SetLinearVelocity(velocity_, -velocity_);
      } else {
        wheels_->SetLinearVelocity(-velocity_, velocity_);
      }
      return;
    }
    if (remembered_ > 0) {
      // Steer toward the spot: slower the more it lies to the side.
      const double turn = std::clamp(bearing_, -1.0, 1.0);
      const double forward = velocity_ * std::max(0.0, std::cos(bearing_));
      wheels_->SetLinearVelocity(forward - turn * velocity_, forward + turn * velocity_);
      return;
    }
    wheels_->SetLinearVelocity(velocity_, velocity_);
  }

 private:
  double velocity_ = 0, tolerance_ = 0, stop_distance_ = 0, avoid_ = 0;
  double spot_[3] = {0, 0, 0};
  int memory_steps_ = 0, remembered_ = 0;
  double bearing_ = 0, distance_ = 0;
  const ProximitySensor* proximity_ = nullptr;
  const OmnidirectionalCamera* camera_ = nullptr;
  DifferentialSteering* wheels_ = nullptr;
};

COLONY_REGISTER_CONTROLLER(
    FootbotFollowSpot, "footbot_follow_spot",
    "the foot-bot of the guidance experiment: wanders until its omnidirectional camera sees a "
    "laser spot, then drives to it",
    {{"velocity", "a number in [0, 10] (m/s)", "0.2", "wheel speed"},
     {"spot_color", "a colour (a name or \"r,g,b\")", "255,0,0", "colour of the laser spot"},
     {"color_tolerance", "a number in [0, 255]", "60",
      "largest difference per channel from spot_color"},
     {"stop_distance", "a number in [0, 100] (m)", "0.3", "stops this far from the spot"},
     {"avoid_distance", "a number in [0, 1]", "0.3", "proximity reading above which it turns away"},
     {"memory_steps", "a whole number >= 0", "30",
      "control steps it drives on towards a lost spot"}});

}  // namespace
}  // namespace colony
