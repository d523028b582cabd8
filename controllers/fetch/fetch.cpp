// fetch: drive to an object, grip it, drag it to a place, release it, back off.
// Navigation uses the positioning sensor (ground truth); the object's and
// the place's positions come from <params>:
//   object="x,y"  place="x,y"  speed (m/s, 0.1)  object_radius (m, 0.05)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "actuators/differential_steering/differential_steering.h"
#include "actuators/gripper/gripper.h"
#include "core/registry.h"
#include "sensors/gripper/gripper.h"
#include "sensors/positioning/positioning.h"

namespace {

struct Point {
  double x = 0, y = 0;
};

Point ParsePoint(const colony::Params& params, const char* key) {
  const std::string text = params.GetString(key);
  Point p;
  char extra = 0;
  if (std::sscanf(text.c_str(), "%lf,%lf%c", &p.x, &p.y, &extra) != 2 || !std::isfinite(p.x) ||
      !std::isfinite(p.y)) {
    throw colony::ParamError(key, text,
                             std::string("parameter '") + key + "': '" + text + "' is not \"x,y\"");
  }
  return p;
}

class Fetch : public colony::Controller {
 public:
  void Init(const colony::Params& params) override {
    object_ = ParsePoint(params, "object");
    place_ = ParsePoint(params, "place");
    speed_ = params.GetDouble("speed", 0.1, 0.01, 0.3);
    object_radius_ = params.GetDouble("object_radius", 0.05, 0.001, 1);
    position_ = &GetSensor<colony::PositioningSensor>("positioning");
    holding_ = &GetSensor<colony::GripperSensor>("gripper");
    wheels_ = &GetActuator<colony::DifferentialSteering>("differential_steering");
    gripper_ = &GetActuator<colony::GripperActuator>("gripper");
  }

  void ControlStep() override {
    const double x = position_->x(), y = position_->y(), yaw = position_->yaw();
    constexpr double kBody = 0.085;
    switch (phase_) {
      case Phase::kApproach:
        // Stop with the object against the jaws.
        if (Steer(x, y, yaw, object_, kBody + object_radius_ + 0.01)) phase_ = Phase::kGrip;
        break;
      case Phase::kGrip:
        wheels_->SetLinearVelocity(0, 0);
        gripper_->Grip();
        if (holding_->holding()) phase_ = Phase::kDrag;
        break;
      case Phase::kDrag: {
        // Drive until the held object, just ahead of the jaws, is at the place.
        const double ahead = kBody + object_radius_ + 0.01;
        const double ox = x + ahead * std::cos(yaw), oy = y + ahead * std::sin(yaw);
        const bool there = std::hypot(place_.x - ox, place_.y - oy) < 0.05;
        if (there || Steer(x, y, yaw, place_, ahead)) {
          wheels_->SetLinearVelocity(0, 0);
          phase_ = Phase::kRelease;
        }
        break;
      }
      case Phase::kRelease:
        gripper_->Release();
        wheels_->SetLinearVelocity(-speed_, -speed_);
        if (!holding_->holding() && ++backing_ > 10) phase_ = Phase::kDone;
        break;
      case Phase::kDone:
        wheels_->SetLinearVelocity(0, 0);
        break;
    }
  }

 private:
  enum class Phase { kApproach, kGrip, kDrag, kRelease, kDone };

  // Turns towards `target`, then drives until `stop_at` metres from it.
  // Returns true once there.
  bool Steer(double x, double y, double yaw, const Point& target, double stop_at) {
    const double dx = target.x - x, dy = target.y - y;
    const double distance = std::hypot(dx, dy);
    if (distance <= stop_at) {
      wheels_->SetLinearVelocity(0, 0);
      return true;
    }
    const double error = std::remainder(std::atan2(dy, dx) - yaw, 2 * M_PI);
    const double turn = std::clamp(error * 0.5, -speed_, speed_);
    const double forward =
        std::abs(error) > 0.3 ? 0.0 : std::min(speed_, distance - stop_at + 0.01);
    wheels_->SetLinearVelocity(forward - turn, forward + turn);
    return false;
  }

  Point object_, place_;
  double speed_ = 0.1, object_radius_ = 0.05;
  Phase phase_ = Phase::kApproach;
  int backing_ = 0;
  const colony::PositioningSensor* position_ = nullptr;
  const colony::GripperSensor* holding_ = nullptr;
  colony::DifferentialSteering* wheels_ = nullptr;
  colony::GripperActuator* gripper_ = nullptr;
};

COLONY_REGISTER_CONTROLLER(Fetch, "fetch",
                           "drive to an object, grip it, drag it to a place, release it",
                           {{"object", "\"x,y\" (m)", "", "where the object lies"},
                            {"place", "\"x,y\" (m)", "", "where to drag it"},
                            {"speed", "a number in [0.01, 0.3] (m/s)", "0.1", "driving speed"},
                            {"object_radius", "a number in [0.001, 1] (m)", "0.05",
                             "the object's radius, to stop in front of it"}});

}  // namespace
