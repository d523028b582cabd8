// handbot_climb: a hand-bot climbs a shelf's vertical board and takes a book
// from it (seed 000, 3.3.2, figures 3.6-3.8).
//
// The rope carries the robot's weight; the grippers hold it to the board's
// front edge, one at a time, and move it up (Figure 3.7's sequence):
//  1. it fires the rope, hangs a moment to read its weight on the rope, and
//     stands again;
//  2. standing, arms straight ahead, the head turned so the left gripper is
//     on top, it closes that gripper on the edge (its IR sensors see the
//     edge between the claws), and the rope takes its weight. Gripping while
//     standing keeps it level: hanging free with its arms out it would tip
//     forward, and every grip after would inherit the tilt;
//  3. the grip's wrist turns the arms half a turn about the grip, so the
//     head swings up over it by twice the arms' spacing (0.12 m); the head
//     turns as much the other way relative to the hull, which stays upright;
//     the rope is coiled in as the hull rises, at the rate the measured turn
//     implies, corrected by how far its pull is from the robot's weight;
//  4. the other gripper, now on top, closes on the edge, the first opens,
//     and the next half-turn goes the other way;
//  5. at the book's height, mid-turn, the free gripper closes when its IR
//     sensors see the book ahead (and opens again if it closed on nothing);
//     holding it, the robot opens the grip on the board and goes down its
//     rope until the rope is slack.
//
// Sensor-driven: the gripper IR sensors find the board and the book, the
// grippers' sensors say when they hold, the rope's traction says when the
// robot hangs and how much weight the rope carries, the arms' encoders say
// where they are. It needs the actuators rope_launcher, handbot_fans,
// handbot_head, handbot_arms, handbot_grippers and the sensors
// rope_traction, positioning, handbot_head, handbot_arms, handbot_grippers,
// handbot_gripper_proximity.
//
// params:
//   book_height  m (0.8): about how high above the floor the book is; the
//                free gripper looks for it within 0.25 m of there
//   max_height   m (1.6): gives up above this (no book found)
//   turn_speed   rad/s (0.4): how fast the grip turns the arms
#include <algorithm>
#include <cmath>
#include <string>

#include "actuators/handbot_arms/handbot_arms.h"
#include "actuators/handbot_fans/handbot_fans.h"
#include "actuators/handbot_grippers/handbot_grippers.h"
#include "actuators/handbot_head/handbot_head.h"
#include "actuators/rope_launcher/rope_launcher.h"
#include "core/log.h"
#include "core/registry.h"
#include "entities/handbot/handbot.h"
#include "sensors/handbot_arms/handbot_arms.h"
#include "sensors/handbot_gripper_proximity/handbot_gripper_proximity.h"
#include "sensors/handbot_grippers/handbot_grippers.h"
#include "sensors/handbot_head/handbot_head.h"
#include "sensors/positioning/positioning.h"
#include "sensors/rope_traction/rope_traction.h"

namespace {

using colony::HandbotArmsActuator;

constexpr double kDt = 0.1;
constexpr double kG = 9.81;  // m/s^2
constexpr int kL = HandbotArmsActuator::kLeft, kR = HandbotArmsActuator::kRight;
// Claws ready to close (rad): a little wider than a 2 cm board or book, so
// they close on it quickly.
constexpr double kReady = 0.5;
// An IR reading at which a board or book is between the claws (within about
// 2.5 cm of the gripper's tip; the claws close on what is within 3 cm).
constexpr double kGraspReading = 0.3;
// Following the turn with the rope: the weight of the newest measured turn
// rate in its running average, and m/s of rope per N the rope pulls short of
// the robot's weight (at most kMaxCorrection m/s).
constexpr double kRateSmoothing = 0.3;
constexpr double kTractionGain = 0.001, kMaxCorrection = 0.005;

double Wrap(double a) { return std::remainder(a, 2 * M_PI); }

class HandbotClimb : public colony::Controller {
 public:
  void Init(const colony::Params& params) override {
    book_height_ = params.GetDouble("book_height", 0.8, 0.1, 10);
    max_height_ = params.GetDouble("max_height", 1.6, 0.1, 10);
    turn_speed_ = params.GetDouble("turn_speed", 0.4, 0.01, 0.6);
    rope_ = &GetActuator<colony::RopeLauncherActuator>("rope_launcher");
    fans_ = &GetActuator<colony::HandbotFansActuator>("handbot_fans");
    head_ = &GetActuator<colony::HandbotHeadActuator>("handbot_head");
    arms_ = &GetActuator<colony::HandbotArmsActuator>("handbot_arms");
    grippers_ = &GetActuator<colony::HandbotGrippersActuator>("handbot_grippers");
    traction_ = &GetSensor<colony::RopeTractionSensor>("rope_traction");
    position_ = &GetSensor<colony::PositioningSensor>("positioning");
    head_sensor_ = &GetSensor<colony::HandbotHeadSensor>("handbot_head");
    arms_sensor_ = &GetSensor<colony::HandbotArmsSensor>("handbot_arms");
    grippers_sensor_ = &GetSensor<colony::HandbotGrippersSensor>("handbot_grippers");
    ir_ = &GetSensor<colony::HandbotGripperProximitySensor>("handbot_gripper_proximity");
  }

  void ControlStep() override {
    in_phase_ += kDt;
    time_ += kDt;
    switch (phase_) {
      case Phase::kLaunch:
        floor_ = position_->z();
        fans_->HoldHeading(position_->yaw());
        rope_->Launch();
        Enter(Phase::kWaitRope);
        break;
      case Phase::kWaitRope:
        if (traction_->launch_failed()) Fail("the rope's launch failed");
        if (traction_->attached()) Enter(Phase::kWeigh);
        break;
      case Phase::kWeigh:
        // Hang a moment, arms folded, to read the robot's weight on the rope.
        rope_->SetClimbSpeed(position_->z() - floor_ < 0.03 ? 0.02 : 0.0);
        if (position_->z() - floor_ >= 0.03 && in_phase_ > 4) {
          weight_ = traction_->traction();
          Enter(Phase::kSetDown);
        }
        break;
      case Phase::kSetDown:
        // Back on the floor, the rope just slack.
        rope_->SetClimbSpeed(-0.02);
        if (traction_->traction() < 0.05 * weight_) {
          rope_->SetClimbSpeed(0);
          Enter(Phase::kPose);
        }
        break;
      case Phase::kPose:
        // Standing: arms straight ahead, the head turned so the left gripper
        // is on top, claws ready.
        for (int g : {kL, kR}) {
          arms_->SetExtension(g, M_PI / 2);
          grippers_->SetAperture(g, kReady);
          grippers_->SetRotation(g, 0);
        }
        // The arms first, then the head: turning the head with the arms
        // half out would turn the robot on the floor.
        if (Near(arms_sensor_->extension(kL), M_PI / 2) &&
            Near(arms_sensor_->extension(kR), M_PI / 2)) {
          head_->SetRotation(M_PI / 2);
          if (Near(head_sensor_->rotation(), M_PI / 2) && in_phase_ > 1) {
            grip_ = kL;
            Enter(Phase::kGrasp);
          }
        }
        break;
      case Phase::kTension:
        // Holding the board, standing: the rope takes the robot's weight.
        rope_->SetClimbSpeed(0.01);
        if (traction_->traction() > 0.95 * weight_) {
          rope_->SetClimbSpeed(0);
          StartTurn();
        }
        if (in_phase_ > 10) Fail("the rope does not take the robot's weight");
        break;
      case Phase::kGrasp:
        // Close the upper gripper on the board once its IR sensors see it.
        rope_->SetClimbSpeed(0);
        if (!grippers_sensor_->holding(grip_)) {
          // The robot swings on its rope: close when the edge is between the
          // claws, open again if they missed it.
          grippers_->SetAperture(grip_, Sees(grip_) > kGraspReading ? 0.0 : kReady);
          if (in_phase_ > 20) Fail("the board is not within the upper gripper's reach");
          break;
        }
        // Holding: the other one lets go.
        grippers_->SetAperture(1 - grip_, kReady);
        if (grippers_sensor_->holding(1 - grip_)) break;
        if (position_->z() - floor_ > max_height_) {
          Fail("no book up to max_height");
          break;
        }
        if (traction_->traction() < 0.5 * weight_) {
          Enter(Phase::kTension);  // the first grip, standing on the floor
        } else {
          StartTurn();
        }
        break;
      case Phase::kTurn:
        Turn();
        break;
      case Phase::kBook:
        // Holding the book: the grip lets go of the board.
        rope_->SetClimbSpeed(0);
        grippers_->Open(grip_);
        if (!grippers_sensor_->holding(grip_)) Enter(Phase::kDown);
        break;
      case Phase::kDown:
        // Down the rope until it goes slack: the robot stands on the floor.
        rope_->SetClimbSpeed(-0.05);
        if (traction_->traction() < 0.2 * weight_ && position_->z() - floor_ < 0.05) {
          rope_->SetClimbSpeed(0);
          Enter(Phase::kDone);
        }
        break;
      case Phase::kDone:
      case Phase::kFailed:
        rope_->SetClimbSpeed(0);
        break;
    }
  }

 private:
  enum class Phase {
    kLaunch,
    kWaitRope,
    kWeigh,
    kSetDown,
    kPose,
    kGrasp,
    kTension,
    kTurn,
    kBook,
    kDown,
    kDone,
    kFailed
  };

  // Half a turn about the grip: its wrist turns the arms, the head turns
  // back relative to the hull as much, the rope is coiled in as the hull
  // rises.
  void Turn() {
    const double dir = direction_;  // +1: the head turns anticlockwise about the grip
    const double remaining = M_PI - turned_;
    const double step = std::min(turn_speed_ * kDt, remaining);
    // The wrist turns opposite to the head's turn about the grip.
    grippers_->SetRotationSpeed(grip_, turn_speed_);
    grippers_->SetRotation(grip_, Wrap(turn_start_wrist_ - dir * (turned_ + step)));
    const double wrist_turned =
        std::abs(Wrap(grippers_sensor_->rotation(grip_) - turn_start_wrist_));
    // The head turns as much the other way relative to the hull, so the
    // hull stays upright; it leads the grip by a step (following the grip's
    // measured turn instead, a robot standing on the floor stays stuck:
    // the grip cannot turn without the hull rolling into the floor).
    head_->SetSpeed(3 * turn_speed_);
    head_->SetRotation(Wrap(turn_start_head_ + dir * (turned_ + step)));
    // The rope follows the hull up: the head's centre is r cos(a) below the
    // grip after turning a, so it rises at r sin(a) a'. The grip turns
    // slower than asked under load, so a' is the measured rate (smoothed);
    // and a little more or less rope keeps the rope carrying the weight.
    const double r = colony::handbot::kShoulderY;
    const double measured = std::max(0.0, wrist_turned - turned_) / kDt;
    rate_ = kRateSmoothing * measured + (1 - kRateSmoothing) * rate_;
    const double rise = r * std::sin(wrist_turned) * rate_;
    const double correction = std::clamp(kTractionGain * (weight_ - traction_->traction()),
                                         -kMaxCorrection, kMaxCorrection);
    rope_->SetClimbSpeed(std::max(0.0, rise + correction));
    turned_ = std::max(turned_, wrist_turned);
    // Mid-turn, at the book's height, the free gripper closes when its IR
    // sensors see something ahead, and opens again if its claws closed on
    // nothing; holding the book, the robot stops turning.
    const int free = 1 - grip_;
    const double grippers_z = position_->z() - floor_ + colony::handbot::kHeadZ;
    if (!book_ && std::abs(grippers_z - book_height_) < 0.25 &&
        std::abs(wrist_turned - M_PI / 2) < 0.8) {
      if (grippers_sensor_->holding(free)) {
        book_ = true;
        Enter(Phase::kBook);
        return;
      }
      const double aperture = grippers_sensor_->aperture(free);
      if (aperture < 0.3) {
        grippers_->SetAperture(free, kReady);  // missed: open again
      } else if (Sees(free) > kGraspReading && aperture >= kReady - 0.01) {
        grippers_->SetAperture(free, 0.0);
      }
    } else if (!grippers_sensor_->holding(free)) {
      grippers_->SetAperture(free, kReady);
    }
    if (wrist_turned > M_PI - 0.03) {
      // The other gripper is on top: it takes the board.
      grip_ = 1 - grip_;
      direction_ = -direction_;
      Enter(Phase::kGrasp);
    }
  }

  void StartTurn() {
    turn_start_wrist_ = grippers_sensor_->rotation(grip_);
    turn_start_head_ = head_sensor_->rotation();
    turned_ = 0;
    rate_ = 0;
    Enter(Phase::kTurn);
  }

  // The strongest reading of gripper g's IR sensors.
  double Sees(int g) const {
    double best = 0;
    for (const auto& r : ir_->readings(g)) best = std::max(best, static_cast<double>(r.value));
    return best;
  }

  static bool Near(double a, double b) { return std::abs(Wrap(a - b)) < 0.03; }

  void Fail(const char* why) {
    colony::LogWarning(std::string("hand-bot '") + id() + "': " + why + "; it stops climbing");
    Enter(Phase::kFailed);
  }
  void Enter(Phase p) {
    phase_ = p;
    in_phase_ = 0;
  }

  colony::RopeLauncherActuator* rope_ = nullptr;
  colony::HandbotFansActuator* fans_ = nullptr;
  colony::HandbotHeadActuator* head_ = nullptr;
  colony::HandbotArmsActuator* arms_ = nullptr;
  colony::HandbotGrippersActuator* grippers_ = nullptr;
  const colony::RopeTractionSensor* traction_ = nullptr;
  const colony::PositioningSensor* position_ = nullptr;
  const colony::HandbotHeadSensor* head_sensor_ = nullptr;
  const colony::HandbotArmsSensor* arms_sensor_ = nullptr;
  const colony::HandbotGrippersSensor* grippers_sensor_ = nullptr;
  const colony::HandbotGripperProximitySensor* ir_ = nullptr;
  double book_height_ = 0.8, max_height_ = 1.6, turn_speed_ = 0.4;
  double floor_ = 0, weight_ = 2 * kG, in_phase_ = 0, time_ = 0;
  double rate_ = 0, turn_start_wrist_ = 0, turn_start_head_ = 0, turned_ = 0, direction_ = -1;
  int grip_ = kL;
  bool book_ = false;
  Phase phase_ = Phase::kLaunch;
};

}  // namespace

COLONY_REGISTER_CONTROLLER(HandbotClimb, "handbot_climb",
                           "hand-bot: climb a shelf's board with the rope and both grippers, take "
                           "the book, come back down",
                           {{"book_height", "a number in [0.1, 10] (m)", "0.8",
                             "height of the board the book lies on"},
                            {"max_height", "a number in [0.1, 10] (m)", "1.6", "highest it climbs"},
                            {"turn_speed", "a number in [0.01, 0.6] (rad/s)", "0.4",
                             "how fast it turns to face the shelf"}});
