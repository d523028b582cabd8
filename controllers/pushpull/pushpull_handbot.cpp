// pushpull_handbot: the hand-bot of the Push-Pull experiment (seed 003,
// 6.2.2, figure 6.3b). It stands by the heavy object, facing it, arms
// straight ahead, its rope already on the ceiling:
//  - while its grippers' IR sensors do not see the object, it shows a push
//    slot at its back (ring LEDs 6-7: blue, violet), asking to be pushed to
//    it (seed: "a hand-bot lights up a push slot in the back as soon as it
//    does not detect something in the gripper"); pressed against it (a
//    reading above `press`), a pull slot there (blue, green), asking to be
//    pulled back;
//  - now and then (try_probability per second) it broadcasts kTryLift; a
//    hand-bot that hears it (or sent it), sees the object and holds its rope
//    tries to lift: it closes its grippers on the object, broadcasts kWait
//    (foot-bots nearby hold still) and climbs its rope;
//  - it gives up and goes back down (then lets go) if its rope pulls more
//    than max_traction, less than min_traction (no rope), or its IMU tilts
//    past max_tilt: holding the object alone, the load in front tips it
//    forward; with a second hand-bot holding the object's other side the two
//    hang level;
//  - having climbed lift_height with none of these, it holds: lifted.
// Sensors: rope_traction, imu, handbot_gripper_proximity, handbot_grippers,
// range_and_bearing; actuators: rope_launcher, handbot_arms,
// handbot_grippers, handbot_fans, leds, range_and_bearing (data_size >= 4).
// params: try_probability (1/s, 0.02), lift_speed (m/s, 0.02), lift_height
// (m, 0.1), max_traction (N, 40), min_traction (N, 5), max_tilt (rad, 0.1),
// retry_time (s, 20: the least time between two of its own calls to try), see (IR reading,
// 0.3: the object within the claws' reach), press (IR reading, 0.9: pressed
// against it).
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "actuators/handbot_arms/handbot_arms.h"
#include "actuators/handbot_fans/handbot_fans.h"
#include "actuators/handbot_grippers/handbot_grippers.h"
#include "actuators/leds/leds.h"
#include "actuators/range_and_bearing/range_and_bearing.h"
#include "actuators/rope_launcher/rope_launcher.h"
#include "controllers/pushpull/pushpull_protocol.h"
#include "core/registry.h"
#include "sensors/handbot_gripper_proximity/handbot_gripper_proximity.h"
#include "sensors/handbot_grippers/handbot_grippers.h"
#include "sensors/imu/imu.h"
#include "sensors/range_and_bearing/range_and_bearing.h"
#include "sensors/rope_traction/rope_traction.h"

namespace colony::pushpull {
namespace {

constexpr double kDt = 0.1;
constexpr int kLeft = HandbotArmsActuator::kLeft, kRight = HandbotArmsActuator::kRight;
constexpr size_t kSlotLed = 6;  // the back of the ring (LEDs counter-clockwise from the front)

class PushPullHandbot : public Controller {
 public:
  void Init(const Params& params) override {
    try_probability_ = params.GetDouble("try_probability", 0.02, 0, 10);
    lift_speed_ = params.GetDouble("lift_speed", 0.02, 0.001, 1);
    lift_height_ = params.GetDouble("lift_height", 0.1, 0.001, 10);
    max_traction_ = params.GetDouble("max_traction", 40, 0, 1e6);
    min_traction_ = params.GetDouble("min_traction", 5, 0, 1e6);
    max_tilt_ = params.GetDouble("max_tilt", 0.1, 0.001, 1.5);
    retry_time_ = params.GetDouble("retry_time", 20, 0, 1e6);
    see_ = params.GetDouble("see", 0.35, 0.001, 1);
    reach_ = params.GetDouble("reach", 0.2, 0.001, 1);
    if (reach_ > see_) {
      throw ParamError("reach", std::to_string(reach_),
                       "parameter 'reach' (" + std::to_string(reach_) +
                           ") must not be above parameter 'see' (" + std::to_string(see_) + ")");
    }
    press_ = params.GetDouble("press", 0.9, 0.001, 1);
    align_tolerance_ = params.GetDouble("align_tolerance", 0.15, 0.001, M_PI);
    if (press_ <= see_) {
      throw ParamError("press", std::to_string(press_),
                       "parameter 'press' (" + std::to_string(press_) +
                           ") must be above parameter 'see' (" + std::to_string(see_) + ")");
    }
    rope_ = &GetActuator<RopeLauncherActuator>("rope_launcher");
    arms_ = &GetActuator<HandbotArmsActuator>("handbot_arms");
    grippers_ = &GetActuator<HandbotGrippersActuator>("handbot_grippers");
    fans_ = &GetActuator<HandbotFansActuator>("handbot_fans");
    leds_ = &GetActuator<Leds>("leds");
    rab_out_ = &GetActuator<RangeAndBearingActuator>("range_and_bearing");
    traction_ = &GetSensor<RopeTractionSensor>("rope_traction");
    imu_ = &GetSensor<Imu>("imu");
    ir_ = &GetSensor<HandbotGripperProximitySensor>("handbot_gripper_proximity");
    grippers_sensor_ = &GetSensor<HandbotGrippersSensor>("handbot_grippers");
    rab_in_ = &GetSensor<RangeAndBearingSensor>("range_and_bearing");
    CheckPayload(*rab_out_, "pushpull_handbot");
    since_try_ = retry_time_;
    in_state_ = 1;  // standing since before the run
  }

  void ControlStep() override {
    in_state_ += kDt;
    since_try_ += kDt;
    // Its heading from where it started (facing the object), from the
    // gyroscope.
    heading_ = std::remainder(heading_ + imu_->angular_velocity()[2] * kDt, 2 * M_PI);
    for (int g : {kLeft, kRight}) arms_->SetExtension(g, M_PI / 2);
    fans_->SetTorque(0);
    rab_out_->SetByte(0, kNothing);
    rab_out_->SetByte(1, kHandBot);
    bool try_lift = false;
    for (const auto& p : rab_in_->packets()) {
      if (p.data.size() >= 2 && p.data[0] == kTryLift && p.data[1] == kHandBot) try_lift = true;
    }
    switch (state_) {
      case State::kStand:
        ShowSlot();
        // No rope on the ceiling (none yet, or it came off): fire it.
        if (!traction_->attached() && in_state_ >= 1) {
          rope_->Launch();
          in_state_ = 0;
        }
        // It asks at random, at most every retry_time; every hand-bot that
        // hears the call (or made it) and stands ready answers it, so hand-bots
        // by the object try together.
        if (since_try_ >= retry_time_ && InReach() && traction_->attached() &&
            rng().Bernoulli(try_probability_ * kDt)) {
          rab_out_->SetByte(0, kTryLift);
          since_try_ = 0;
          try_lift = true;
        }
        if (try_lift && in_state_ >= 1 && InReach() && traction_->attached()) {
          Enter(State::kGrasp);
        } else if (in_state_ >= 2 && traction_->attached() &&
                   std::abs(heading_) > align_tolerance_) {
          // Turned away from the object by a push or a bump (its gyroscope
          // says how far): it hangs just off the floor and turns back with
          // its fans.
          start_length_ = traction_->length();
          Enter(State::kAlign);
        }
        break;
      case State::kAlign: {
        leds_->SetAllColors(kOff);
        rab_out_->SetByte(0, kWait);
        const bool hanging = start_length_ - traction_->length() >= 0.02;
        rope_->SetClimbSpeed(hanging ? 0.0 : lift_speed_);
        const double rate = imu_->angular_velocity()[2];
        if (hanging) {
          const double most = fans_->max_torque();
          fans_->SetTorque(std::clamp(-0.2 * heading_ - 0.1 * rate, -most, most));
          if (std::abs(heading_) < 0.3 * align_tolerance_ && std::abs(rate) < 0.02) {
            fans_->SetTorque(0);
            Enter(State::kDown);
          }
        }
        if (in_state_ > 60) Enter(State::kDown);
        break;
      }
      case State::kGrasp:
        leds_->SetAllColors(kOff);
        for (int g : {kLeft, kRight}) grippers_->Close(g);
        if (Holding()) {
          start_length_ = traction_->length();
          Enter(State::kLift);
        } else if (in_state_ > 3) {
          for (int g : {kLeft, kRight}) grippers_->Open(g);
          Enter(State::kStand);
        }
        break;
      case State::kLift:
        leds_->SetAllColors(kOff);
        rab_out_->SetByte(0, kWait);
        rope_->SetClimbSpeed(lift_speed_);
        if (GiveUp()) {
          Enter(State::kDown);
        } else if (start_length_ - traction_->length() >= lift_height_) {
          rope_->SetClimbSpeed(0);
          Enter(State::kLifted);
        }
        break;
      case State::kDown:
        leds_->SetAllColors(kOff);
        rab_out_->SetByte(0, kWait);
        rope_->SetClimbSpeed(-lift_speed_);
        if (traction_->traction() < min_traction_ || in_state_ > 30) {
          rope_->SetClimbSpeed(0);
          for (int g : {kLeft, kRight}) grippers_->Open(g);
          Enter(State::kStand);
        }
        break;
      case State::kLifted:
        leds_->SetAllColors(kOff);
        rope_->SetClimbSpeed(0);
        break;
    }
  }

 private:
  enum class State { kStand, kAlign, kGrasp, kLift, kDown, kLifted };

  // Whether a lift must stop: the rope pulls too much (the object is too
  // heavy) or too little (no rope), or the hull tilts too far (from the
  // accelerometer, which at rest reads +g along the body's z).
  bool GiveUp() const {
    const double t = traction_->traction();
    if (t > max_traction_) return true;                   // too heavy
    if (in_state_ > 2 && t < min_traction_) return true;  // no rope
    const auto& a = imu_->acceleration();
    return std::atan2(std::hypot(a[0], a[1]), a[2]) > max_tilt_;  // tipped
  }

  // Not seeing the object ahead, a push slot at its back (to be pushed
  // to it); pressed against it, a pull slot there (to be pulled back).
  void ShowSlot() {
    leds_->SetAllColors(kOff);
    const double seen = Seen();
    if (seen > see_ && seen < press_) return;
    leds_->SetSingleColor(kSlotLed, kSlotBlue);
    leds_->SetSingleColor(kSlotLed + 1, seen <= see_ ? kPushViolet : kPullGreen);
  }

  // The strongest reading of the grippers' IR sensors.
  double Seen() const {
    double best = 0;
    for (int g : {kLeft, kRight}) {
      for (const auto& r : ir_->readings(g)) best = std::max(best, static_cast<double>(r.value));
    }
    return best;
  }

  bool SeesObject() const { return Seen() > see_; }
  // Near enough to grasp it: readings flicker with noise, so this is lower
  // than `see`, which ends the push.
  bool InReach() const { return Seen() > reach_; }
  bool Holding() const {
    return grippers_sensor_->holding(kLeft) || grippers_sensor_->holding(kRight);
  }
  void Enter(State s) {
    state_ = s;
    in_state_ = 0;
  }

  double try_probability_ = 0.02, lift_speed_ = 0.02, lift_height_ = 0.1, max_traction_ = 40;
  double min_traction_ = 5, max_tilt_ = 0.1, retry_time_ = 20, see_ = 0.3, press_ = 0.9;
  double align_tolerance_ = 0.15, heading_ = 0, reach_ = 0.2;
  double in_state_ = 0, since_try_ = 0, start_length_ = 0;
  State state_ = State::kStand;
  RopeLauncherActuator* rope_ = nullptr;
  HandbotArmsActuator* arms_ = nullptr;
  HandbotGrippersActuator* grippers_ = nullptr;
  HandbotFansActuator* fans_ = nullptr;
  Leds* leds_ = nullptr;
  RangeAndBearingActuator* rab_out_ = nullptr;
  const RopeTractionSensor* traction_ = nullptr;
  const Imu* imu_ = nullptr;
  const HandbotGripperProximitySensor* ir_ = nullptr;
  const HandbotGrippersSensor* grippers_sensor_ = nullptr;
  const RangeAndBearingSensor* rab_in_ = nullptr;
};

}  // namespace
}  // namespace colony::pushpull

COLONY_REGISTER_CONTROLLER(
    colony::pushpull::PushPullHandbot, "pushpull_handbot",
    "Push-Pull hand-bot (seed 003, 6.2.2): tries to lift the object with its "
    "rope; after a failure shows a push or pull slot to be moved",
    {{"try_probability", "a number in [0, 10]", "0.02", "chance per second of trying to lift"},
     {"lift_speed", "a number in [0.001, 1] (m/s)", "0.02", "climbing speed while lifting"},
     {"lift_height", "a number in [0.001, 10] (m)", "0.1", "how high a lift must raise the object"},
     {"max_traction", "a number >= 0 (N)", "40", "traction above which the lift fails (too heavy)"},
     {"min_traction", "a number >= 0 (N)", "5", "traction below which the rope is slack"},
     {"max_tilt", "a number in [0.001, 1.5] (rad)", "0.1", "tilt above which the lift fails"},
     {"retry_time", "a number >= 0 (s)", "20", "wait before trying again"},
     {"see", "a number in [0.001, 1]", "0.35",
      "gripper proximity reading at which the object is seen"},
     {"reach", "a number in [0.001, 1], at most see", "0.2",
      "gripper proximity reading at which it reaches for the object"},
     {"press", "a number in [0.001, 1], above see", "0.9",
      "gripper proximity reading at which the claws close"},
     {"align_tolerance", "a number in [0.001, pi] (rad)", "0.15",
      "heading error accepted when aligning"}});
