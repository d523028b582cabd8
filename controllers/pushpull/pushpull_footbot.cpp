// pushpull_footbot: the foot-bot of the Push-Pull experiment (seed 003,
// 6.2.1, figure 6.3a). It searches with its omnidirectional camera for a
// hand-bot's slot (two adjacent ring LEDs: blue, and counter-clockwise from
// it green for "pull me" or violet for "push me"), comes round to face the
// slot, connects to the hand-bot's ring there with its gripper, pulls (backs
// away) or pushes (drives on) while the slot stays lit, lets go and searches
// again. While connecting, pushing or pulling it lights its LEDs yellow.
//
// MACA-like pause: a foot-bot about to connect broadcasts kPause with a random
// token; other foot-bots that hear it within pause_radius hold still until it
// stops (it has connected) or pause_timeout passes; of two connecting
// foot-bots that hear each other, the lower token yields. A hand-bot lifting
// or going down broadcasts kWait: foot-bots that hear it within wait_radius
// hold still (letting go of it if they hold it) until it stops.
//
// Sensors: omnidirectional_camera, proximity, range_and_bearing, gripper;
// actuators: differential_steering, gripper, leds, range_and_bearing
// (data_size >= 4). Every number is a <params> attribute:
//   speed (m/s, 0.1), move_speed (m/s, 0.05: pushing and pulling),
//   turn_probability (0.05) and turn_ticks (20): the search's random walk,
//   avoidance (3): how hard it steers away from what its proximity ring sees,
//   dock_distance (m, 0.18): centre to centre when connecting,
//   staging (m, 0.15): how far out from the slot it lines up first,
//   approach_timeout (s, 20): lining up longer than this (crowded out by
//     others), it backs off and ignores slots for a random 1 to 3 times
//     ignore_time,
//   connect_timeout (s, 15), move_time (s, 10): the longest push or pull,
//   pause_timeout (s, 5), pause_radius (m, 1), wait_radius (m, 1.5),
//   back_time (s, 2): backing off after letting go,
//   ignore_time (s, 5): slots ignored after backing off.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "actuators/differential_steering/differential_steering.h"
#include "actuators/gripper/gripper.h"
#include "actuators/leds/leds.h"
#include "actuators/range_and_bearing/range_and_bearing.h"
#include "controllers/common/steering.h"
#include "controllers/pushpull/pushpull_protocol.h"
#include "core/registry.h"
#include "sensors/gripper/gripper.h"
#include "sensors/omnidirectional_camera/omnidirectional_camera.h"
#include "sensors/proximity/proximity.h"
#include "sensors/range_and_bearing/range_and_bearing.h"

namespace colony::pushpull {
namespace {

constexpr double kDt = 0.1;
constexpr double kRingRadius = 0.075;  // m, the hand-bot's LED ring
constexpr double kPairGap = 0.07;      // m: two LEDs closer than this are neighbours

struct Point {
  double x = 0, y = 0;
  Point operator+(Point o) const { return {x + o.x, y + o.y}; }
  Point operator-(Point o) const { return {x - o.x, y - o.y}; }
  Point operator*(double k) const { return {x * k, y * k}; }
  double Norm() const { return std::hypot(x, y); }
  double Angle() const { return std::atan2(y, x); }
};

// A slot seen by the camera, in the robot's frame.
struct Slot {
  bool push = false;    // violet: push; green: pull
  Point centre;         // the hand-bot's centre, from the two LEDs
  Point outward;        // unit vector from the centre through the slot
  double distance = 0;  // to the slot's middle
};

class PushPullFootbot : public Controller {
 public:
  void Init(const Params& params) override {
    speed_ = params.GetDouble("speed", 0.1, 0.01, 0.3);
    move_speed_ = params.GetDouble("move_speed", 0.05, 0.01, 0.3);
    walk_.Configure(speed_, params.GetDouble("turn_probability", 0.05, 0, 1),
                    static_cast<int>(params.GetInt("turn_ticks", 20, 1, 100000)));
    avoidance_ = params.GetDouble("avoidance", 3, 0, 1e3);
    dock_ = params.GetDouble("dock_distance", 0.18, 0.1, 0.5);
    staging_ = params.GetDouble("staging", 0.15, 0.02, 1);
    approach_timeout_ = params.GetDouble("approach_timeout", 20, 0.1, 1e6);
    connect_timeout_ = params.GetDouble("connect_timeout", 15, 0.1, 1e6);
    move_time_ = params.GetDouble("move_time", 10, 0.1, 1e6);
    pause_timeout_ = params.GetDouble("pause_timeout", 5, 0.1, 1e6);
    pause_radius_ = params.GetDouble("pause_radius", 1, 0, 100);
    wait_radius_ = params.GetDouble("wait_radius", 1.5, 0, 100);
    back_time_ = params.GetDouble("back_time", 2, 0, 1e6);
    ignore_time_ = params.GetDouble("ignore_time", 5, 0, 1e6);
    camera_ = &GetSensor<OmnidirectionalCamera>("omnidirectional_camera");
    obstacles_.Bind(GetSensor<ProximitySensor>("proximity"));
    rab_in_ = &GetSensor<RangeAndBearingSensor>("range_and_bearing");
    gripper_sensor_ = &GetSensor<GripperSensor>("gripper");
    wheels_ = &GetActuator<DifferentialSteering>("differential_steering");
    gripper_ = &GetActuator<GripperActuator>("gripper");
    leds_ = &GetActuator<Leds>("leds");
    rab_out_ = &GetActuator<RangeAndBearingActuator>("range_and_bearing");
    CheckPayload(*rab_out_, "pushpull_footbot");
    token_ = static_cast<uint16_t>(1 + rng().UniformInt(65535));
  }

  void ControlStep() override {
    in_state_ += kDt;
    ignore_left_ = std::max(0.0, ignore_left_ - kDt);
    const Heard heard = Listen();
    // Holding still for a hand-bot going up or down, or for a connecting
    // foot-bot (unless this one connects and has priority).
    if (heard.wait) {
      Hold(/*release=*/true);
      return;
    }
    if (heard.pause && state_ != State::kConnect) {
      paused_for_ += kDt;
      if (paused_for_ < pause_timeout_) {
        Hold(/*release=*/false);
        return;
      }
    } else if (!heard.pause) {
      paused_for_ = 0;
    }
    rab_out_->SetByte(0, kNothing);
    rab_out_->SetByte(1, kFootBot);
    leds_->SetAllColors(kOff);
    switch (state_) {
      case State::kSearch:
        Search();
        break;
      case State::kApproach:
        Approach();
        break;
      case State::kConnect:
        Connect(heard);
        break;
      case State::kMove:
        Move();
        break;
      case State::kBackOff:
        gripper_->Release();
        wheels_->SetLinearVelocity(-speed_, -speed_);
        if (in_state_ >= back_time_) {
          ignore_left_ = backoff_ > 0 ? backoff_ : ignore_time_;
          backoff_ = 0;
          Enter(State::kSearch);
        }
        break;
    }
  }

 private:
  enum class State { kSearch, kApproach, kConnect, kMove, kBackOff };
  struct Heard {
    bool wait = false, pause = false;
    bool yield = false;  // a connecting foot-bot with a higher token is near
  };

  Heard Listen() const {
    Heard h;
    for (const auto& p : rab_in_->packets()) {
      if (p.data.size() < static_cast<size_t>(kPayloadSize)) continue;
      if (p.data[0] == kWait && p.data[1] == kHandBot && p.range <= wait_radius_) h.wait = true;
      if (p.data[0] == kPause && p.data[1] == kFootBot && p.range <= pause_radius_) {
        h.pause = true;
        const uint16_t token = static_cast<uint16_t>((p.data[2] << 8) | p.data[3]);
        if (token > token_) h.yield = true;
      }
    }
    return h;
  }

  void Hold(bool release) {
    wheels_->SetLinearVelocity(0, 0);
    if (release && gripper_sensor_->holding()) {
      gripper_->Release();
      Enter(State::kBackOff);
    }
    rab_out_->SetByte(0, kNothing);
  }

  // The slots the camera sees (nearest first).
  std::vector<Slot> Slots() const {
    std::vector<Point> blue;
    std::vector<std::pair<Point, bool>> other;  // position, push
    for (const auto& b : camera_->blobs()) {
      const Point p{b.distance * std::cos(b.bearing), b.distance * std::sin(b.bearing)};
      switch (Classify(b.red, b.green, b.blue)) {
        case Colour::kBlue:
          blue.push_back(p);
          break;
        case Colour::kGreen:
          other.push_back({p, false});
          break;
        case Colour::kViolet:
          other.push_back({p, true});
          break;
        default:
          break;
      }
    }
    std::vector<Slot> slots;
    for (const Point& a : blue) {
      for (const auto& [b, push] : other) {
        const Point chord = b - a;
        const double len = chord.Norm();
        if (len > kPairGap || len < 1e-6) continue;
        // Counter-clockwise from blue to the other colour: the ring's centre
        // is on the chord's left.
        const Point left{-chord.y / len, chord.x / len};
        const double h = std::sqrt(std::max(0.0, kRingRadius * kRingRadius - 0.25 * len * len));
        const Point middle = (a + b) * 0.5;
        Slot s;
        s.push = push;
        s.centre = middle + left * h;
        // The foot-bot lines up on the blue LED: the hand-bot puts it on the
        // axis it wants to be moved along, so the push or pull goes through
        // its centre along that axis.
        const Point radial = a - s.centre;
        s.outward = radial * (1.0 / std::max(radial.Norm(), 1e-9));
        s.distance = middle.Norm();
        slots.push_back(s);
      }
    }
    std::sort(slots.begin(), slots.end(),
              [](const Slot& l, const Slot& r) { return l.distance < r.distance; });
    return slots;
  }

  void Search() {
    if (ignore_left_ <= 0) {
      const auto slots = Slots();
      if (!slots.empty()) {
        Enter(State::kApproach);
        Approach();
        return;
      }
    }
    walk_.Step(obstacles_.Read(), rng(), *wheels_);
  }

  // To the staging point straight out from the slot, then facing the
  // hand-bot's centre.
  void Approach() {
    const auto slots = Slots();
    if (slots.empty()) {
      Enter(State::kSearch);
      return;
    }
    // Crowded out (others around the same slot): back off for a random
    // while, as MACA's stations do.
    if (in_state_ > approach_timeout_) {
      backoff_ = ignore_time_ * (1 + 2 * rng().Uniform());
      Enter(State::kBackOff);
      return;
    }
    const Slot& s = slots.front();
    const Point staging = s.centre + s.outward * (dock_ + staging_);
    if (staging.Norm() > 0.03) {
      swarm::Vector to{staging.x, staging.y};
      const double d = to.Length();
      to = to * (1.0 / d);
      // Steer round obstacles, but not away from the hand-bot once close.
      const swarm::Vector obstacle = obstacles_.Read();
      if (s.centre.Norm() > dock_ + 0.1) to += obstacle * -avoidance_;
      swarm::SteerTowards(to.Angle(), std::min(speed_, std::max(0.03, d)), *wheels_);
      return;
    }
    const double facing = s.centre.Angle();
    if (std::abs(facing) > 0.05) {
      const double w = std::clamp(facing, -1.0, 1.0) * 0.05;
      wheels_->SetLinearVelocity(-w, w);
      return;
    }
    push_ = s.push;
    Enter(State::kConnect);
  }

  // Forward onto the slot, the jaws closing as they reach the ring.
  void Connect(const Heard& heard) {
    leds_->SetAllColors(kBusyYellow);
    if (heard.yield) {  // another connects here first
      wheels_->SetLinearVelocity(0, 0);
      if (in_state_ > connect_timeout_) Enter(State::kBackOff);
      return;
    }
    rab_out_->SetByte(0, kPause);
    rab_out_->SetByte(2, static_cast<uint8_t>(token_ >> 8));
    rab_out_->SetByte(3, static_cast<uint8_t>(token_ & 0xff));
    if (gripper_sensor_->holding()) {
      Enter(State::kMove);
      return;
    }
    const auto slots = Slots();
    if (!slots.empty() && slots.front().centre.Norm() > dock_) {
      swarm::SteerTowards(slots.front().centre.Angle(), 0.03, *wheels_);
    } else {
      wheels_->SetLinearVelocity(0.01, 0.01);
    }
    gripper_->SetTurretAngle(0);
    gripper_->Grip();
    if (in_state_ > connect_timeout_) Enter(State::kBackOff);
  }

  // Pushing or pulling while the slot stays lit (the hand-bot turns it off
  // once it has been moved enough), for at most move_time.
  void Move() {
    leds_->SetAllColors(kBusyYellow);
    if (!gripper_sensor_->holding()) {
      Enter(State::kBackOff);
      return;
    }
    bool lit = false;
    for (const Slot& s : Slots()) lit = lit || (s.distance < dock_ + 0.1 && s.push == push_);
    if (!lit || in_state_ > move_time_) {
      gripper_->Release();
      Enter(State::kBackOff);
      return;
    }
    const double v = push_ ? move_speed_ : -move_speed_;
    wheels_->SetLinearVelocity(v, v);
  }

  void Enter(State s) {
    state_ = s;
    in_state_ = 0;
  }

  double speed_ = 0.1, move_speed_ = 0.05, avoidance_ = 3, dock_ = 0.18, staging_ = 0.15;
  double connect_timeout_ = 15, move_time_ = 10, pause_timeout_ = 5, pause_radius_ = 1;
  double wait_radius_ = 1.5, back_time_ = 2, ignore_time_ = 5;
  double approach_timeout_ = 20, backoff_ = 0;
  double in_state_ = 0, paused_for_ = 0, ignore_left_ = 0;
  bool push_ = false;
  uint16_t token_ = 1;
  State state_ = State::kSearch;
  swarm::RandomWalk walk_;
  swarm::ObstacleVector obstacles_;
  const OmnidirectionalCamera* camera_ = nullptr;
  const RangeAndBearingSensor* rab_in_ = nullptr;
  const GripperSensor* gripper_sensor_ = nullptr;
  DifferentialSteering* wheels_ = nullptr;
  GripperActuator* gripper_ = nullptr;
  Leds* leds_ = nullptr;
  RangeAndBearingActuator* rab_out_ = nullptr;
};

}  // namespace
}  // namespace colony::pushpull

COLONY_REGISTER_CONTROLLER(
    colony::pushpull::PushPullFootbot, "pushpull_footbot",
    "Push-Pull foot-bot (seed 003, 6.2.1): finds a hand-bot's slot with its "
    "camera, connects with its gripper, pushes or pulls it",
    {{"speed", "a number in [0.01, 0.3] (m/s)", "0.1", "speed while searching"},
     {"move_speed", "a number in [0.01, 0.3] (m/s)", "0.05", "speed while pushing or pulling"},
     {"turn_probability", "a number in [0, 1]", "0.05",
      "chance per tick of a random turn while searching"},
     {"turn_ticks", "a whole number in [1, 100000]", "20", "longest random turn (ticks)"},
     {"avoidance", "a number in [0, 1000]", "3", "weight of the obstacle term"},
     {"dock_distance", "a number in [0.1, 0.5] (m)", "0.18",
      "distance to the slot at which it grips"},
     {"staging", "a number in [0.02, 1] (m)", "0.15",
      "how far out from the slot it lines up first"},
     {"approach_timeout", "a number in [0.1, 1e6] (s)", "20",
      "gives up an approach after this long"},
     {"connect_timeout", "a number in [0.1, 1e6] (s)", "15", "gives up connecting after this long"},
     {"move_time", "a number in [0.1, 1e6] (s)", "10", "how long it pushes or pulls"},
     {"pause_timeout", "a number in [0.1, 1e6] (s)", "5",
      "longest pause while the hand-bot tries to lift"},
     {"pause_radius", "a number in [0, 100] (m)", "1", "pauses when a hand-bot is this close"},
     {"wait_radius", "a number in [0, 100] (m)", "1.5", "waits when a hand-bot is this close"},
     {"back_time", "a number in [0, 1e6] (s)", "2", "how long it backs off after letting go"},
     {"ignore_time", "a number in [0, 1e6] (s)", "5", "how long it ignores the slot it left"}});
