// handbot_rope: a hand-bot climbs its rope and comes back down, again and
// again: it launches the rope, climbs `height` above where it stood, holds
// `pause` seconds, goes back down, stands `pause` seconds, and so on, its
// fans holding the heading it started with. If the launch fails it tries
// again after `pause`. (The rope's behaviour, for demonstrations and for
// the hand-bot benchmark scene.)
//
// params:
//   height  m (1.0): how far it climbs
//   speed   m/s (0.1): how fast it climbs and goes down
//   pause   s (2): how long it holds at the top and stands at the bottom
#include <algorithm>
#include <cmath>

#include "actuators/handbot_fans/handbot_fans.h"
#include "actuators/rope_launcher/rope_launcher.h"
#include "core/registry.h"
#include "sensors/positioning/positioning.h"
#include "sensors/rope_traction/rope_traction.h"

namespace {

class HandbotRope : public colony::Controller {
 public:
  void Init(const colony::Params& params) override {
    height_ = params.GetDouble("height", 1.0, 0.01, 10);
    speed_ = params.GetDouble("speed", 0.1, 0.001, 1);
    pause_ = params.GetDouble("pause", 2, 0, 1000);
    rope_ = &GetActuator<colony::RopeLauncherActuator>("rope_launcher");
    fans_ = &GetActuator<colony::HandbotFansActuator>("handbot_fans");
    traction_ = &GetSensor<colony::RopeTractionSensor>("rope_traction");
    position_ = &GetSensor<colony::PositioningSensor>("positioning");
  }

  void ControlStep() override {
    in_phase_ += 0.1;
    switch (phase_) {
      case Phase::kLaunch:
        floor_ = position_->z();
        fans_->HoldHeading(position_->yaw());
        rope_->Launch();
        Enter(Phase::kWait);
        break;
      case Phase::kWait:
        if (traction_->attached()) Enter(Phase::kUp);
        if (traction_->launch_failed()) Enter(Phase::kRetry);
        break;
      case Phase::kRetry:
        if (in_phase_ >= pause_) Enter(Phase::kLaunch);
        break;
      case Phase::kUp:
        rope_->SetClimbSpeed(speed_);
        if (position_->z() - floor_ >= height_ || traction_->stalled()) {
          rope_->SetClimbSpeed(0);
          Enter(Phase::kTop);
        }
        break;
      case Phase::kTop:
        if (in_phase_ >= pause_) Enter(Phase::kDown);
        break;
      case Phase::kDown:
        rope_->SetClimbSpeed(-speed_);
        if (position_->z() - floor_ < 0.005) {
          rope_->SetClimbSpeed(0);
          Enter(Phase::kBottom);
        }
        break;
      case Phase::kBottom:
        if (in_phase_ >= pause_) Enter(Phase::kUp);
        break;
    }
  }

 private:
  enum class Phase { kLaunch, kWait, kRetry, kUp, kTop, kDown, kBottom };
  void Enter(Phase p) {
    phase_ = p;
    in_phase_ = 0;
  }

  colony::RopeLauncherActuator* rope_ = nullptr;
  colony::HandbotFansActuator* fans_ = nullptr;
  const colony::RopeTractionSensor* traction_ = nullptr;
  const colony::PositioningSensor* position_ = nullptr;
  double height_ = 1, speed_ = 0.1, pause_ = 2, floor_ = 0, in_phase_ = 0;
  Phase phase_ = Phase::kLaunch;
};

}  // namespace

COLONY_REGISTER_CONTROLLER(
    HandbotRope, "handbot_rope",
    "hand-bot: launch the rope, climb it and come back down, again and again",
    {{"height", "a number in [0.01, 10] (m)", "1", "how far it climbs"},
     {"speed", "a number in [0.001, 1] (m/s)", "0.1", "how fast it climbs and goes down"},
     {"pause", "a number in [0, 1000] (s)", "2",
      "how long it holds at the top and stands at the bottom"}});
