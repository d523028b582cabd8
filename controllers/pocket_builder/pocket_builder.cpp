// pocket_builder: seed 004's barrier construction with deformable pockets,
// one marXbot (section 3.4): the seven behaviours explore, goto-reservoir,
// approach, pick-up, goto-structure, deploy and drop, with odometry
// navigation in the robot's own template frame (3.4.1) and visual navigation
// in the instantaneous coordinate system (3.4.2), and the two stochastic
// deposition rules (eq. 3.3 and 3.5, deposition.h).
//
// No ground truth: the robot reads its wheel encoders (odometry), the
// omnidirectional camera (green landmark and red pocket blobs), the proximity
// ring (walls, landmarks) and the manipulator sensor (IR readings, tilt,
// rotation, holding). Template landmarks are told from reservoir landmarks by
// their spacing (`template_spacing`, `reservoir_spacing`): the camera gives
// every landmark the same colour. README.md has the parameters.
//
// With `swarm="true"`, the inter-robot rules of section 3.4.4: the robots see
// each other with the range-and-bearing device (position, and one byte: "I am
// approaching a pocket"); the double path along the boundary (main path right
// to left, nearer; auxiliary path left to right, `lane_gap` farther), entered
// by the auxiliary path, switched when the robot's left side is free, the
// loop mechanism P(lambda -> -lambda) = tau; a robot stops behind another on
// its path; at the reservoir a robot waits, clear of the approach point, while
// another robot closer to the pocket approaches it.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "actuators/differential_steering/differential_steering.h"
#include "actuators/manipulator/manipulator.h"
#include "actuators/range_and_bearing/range_and_bearing.h"
#include "controllers/common/steering.h"
#include "controllers/pocket_builder/deposition.h"
#include "core/registry.h"
#include "sensors/manipulator/manipulator.h"
#include "sensors/omnidirectional_camera/omnidirectional_camera.h"
#include "sensors/proximity/proximity.h"
#include "sensors/range_and_bearing/range_and_bearing.h"
#include "sensors/wheel_encoders/wheel_encoders.h"

namespace colony::pocket_builder {
namespace {

double Wrap(double a) { return std::remainder(a, 2 * M_PI); }

constexpr double kBodyRadius = 0.085;  // m: the marXbot's body, where its proximity ring sits

// What the camera shows this tick, in the body frame.
struct View {
  std::vector<Point> landmarks, pockets;
  // The structure region: two landmarks `template_spacing` apart in view.
  bool structure = false;
  InstantFrame frame;                   // of the nearest boundary line
  double ahead_min = 0, ahead_max = 0;  // extent of the visible template along y_p
  std::vector<Point> pockets_p;         // visible pockets in the instantaneous frame
  // The reservoir region: two landmarks `reservoir_spacing` apart.
  bool reservoir = false;
  Point res_a, res_b;
  bool res_pocket = false;  // a pocket between them
  Point pocket;
};

// The two paths of the double path (3.4.4); the values are lambda.
constexpr int kMainPath = 1, kAuxiliaryPath = -1;

enum class Behaviour {
  kExplore,
  kGotoReservoir,
  kApproach,
  kPickUp,
  kGotoStructure,
  kDeploy,
  kDrop
};

class PocketBuilder : public Controller {
 public:
  void Init(const Params& params) override {
    speed_ = params.GetDouble("speed", 0.1, 0.01, 0.3);
    slow_ = params.GetDouble("slow_speed", 0.05, 0.01, 0.3);
    tick_ = params.GetDouble("tick", 0.1, 1e-3, 1);
    template_spacing_ = params.GetDouble("template_spacing", 0.333, 0.05, 5);
    reservoir_spacing_ = params.GetDouble("reservoir_spacing", 0.24, 0.05, 5);
    spacing_tolerance_ = params.GetDouble("spacing_tolerance", 0.04, 0, 1);
    path_distance_ = params.GetDouble("path_distance", 0.35, 0.1, 2);
    end_margin_ = params.GetDouble("end_margin", 0.0, -1, 1);
    k1_ = params.GetDouble("k1", 0.02, 0, 1);
    alpha_ = params.GetDouble("alpha", 0.5, 0, 100);
    delta1_ = params.GetDouble("delta1", 0.08, 0, 2);
    height_reading_ = params.GetDouble("height_reading", 0.15, 0, 1);
    max_inhibitions_ = static_cast<int>(params.GetInt("max_inhibitions", 3, 0, 1000000));
    k2_ = params.GetDouble("k2", 0.2, 0, 1);
    sigma_ = params.GetDouble("sigma", 0.03, 1e-4, 1);
    delta2_ = params.GetDouble("delta2", 0.06, 0, 2);
    d_m_ = params.GetDouble("manipulator_distance", 0.12, 0, 0.5);
    force_distance_ = params.GetDouble("force_distance", 0.17, 0, 1);
    approach_distance_ = params.GetDouble("approach_distance", 0.3, 0.15, 1);
    pickup_distance_ = params.GetDouble("pickup_distance", 0.2, 0.05, 1);
    carry_elevation_ = params.GetDouble("carry_elevation", 0.1, 0.03, 0.2);
    goto_timeout_ = params.GetDouble("goto_timeout", 60, 1, 1e6);
    lost_time_ = params.GetDouble("lost_time", 2, 0, 1e6);
    walk_.Configure(speed_, params.GetDouble("turn_probability", 0.05, 0, 1),
                    static_cast<int>(params.GetInt("turn_ticks", 20, 1, 1000000)));
    camera_ = &GetSensor<OmnidirectionalCamera>("omnidirectional_camera");
    encoders_ = &GetSensor<WheelEncoders>("wheel_encoders");
    arm_ = &GetSensor<ManipulatorSensor>("manipulator");
    wheels_ = &GetActuator<DifferentialSteering>("differential_steering");
    manipulator_ = &GetActuator<ManipulatorActuator>("manipulator");
    proximity_ = &GetSensor<ProximitySensor>("proximity");
    obstacle_.Bind(*proximity_);
    swarm_ = params.GetBool("swarm", false);
    if (swarm_) {
      lane_gap_ = params.GetDouble("lane_gap", 0.25, 0.17, 1);
      tau_ = params.GetDouble("tau", 0.005, 0, 1);
      follow_distance_ = params.GetDouble("follow_distance", 0.35, 0.17, 2);
      side_length_ = params.GetDouble("side_length", 0.3, 0, 2);
      wait_distance_ = params.GetDouble("wait_distance", 0.6, 0.3, 3);
      wait_time_ = params.GetDouble("wait_time", 2, 0, 1e6);
      max_wait_ = params.GetDouble("max_wait", 20, 1, 1e6);
      rab_ = &GetSensor<RangeAndBearingSensor>("range_and_bearing");
      beacon_ = &GetActuator<RangeAndBearingActuator>("range_and_bearing");
    }
    Carry();
  }

  void ControlStep() override {
    Odometry();
    Look();
    if (swarm_) SeeRobots();
    switch (behaviour_) {
      case Behaviour::kExplore:
        Explore();
        break;
      case Behaviour::kGotoReservoir:
        GotoReservoir();
        break;
      case Behaviour::kApproach:
        Approach();
        break;
      case Behaviour::kPickUp:
        PickUp();
        break;
      case Behaviour::kGotoStructure:
        GotoStructure();
        break;
      case Behaviour::kDeploy:
        Deploy();
        break;
      case Behaviour::kDrop:
        Drop();
        break;
    }
    if (swarm_) beacon_->SetByte(0, static_cast<uint8_t>(Broadcast()));
  }

 private:
  // --- Sensing -------------------------------------------------------------

  // Dead reckoning from the wheel encoders, in the template frame (3.4.1).
  void Odometry() {
    const double dl = encoders_->distance_left(), dr = encoders_->distance_right();
    forward_ = 0.5 * (dl + dr);
    const double dpsi = (dr - dl) / encoders_->wheel_base();
    x_ += forward_ * std::cos(psi_ + 0.5 * dpsi);
    y_ += forward_ * std::sin(psi_ + 0.5 * dpsi);
    psi_ = Wrap(psi_ + dpsi);
  }

  bool Near(double a, double b) const { return std::abs(a - b) <= spacing_tolerance_; }

  void Look() {
    View& v = view_;
    v.landmarks.clear();
    v.pockets.clear();
    v.pockets_p.clear();
    for (const auto& b : camera_->blobs()) {
      if (b.green > 128 && b.red < 100 && b.blue < 100) {
        v.landmarks.push_back(FromPolar(b.distance, b.bearing));
      } else if (b.red > 128 && b.green < 100 && b.blue < 100) {
        v.pockets.push_back(FromPolar(b.distance, b.bearing));
      }
    }
    v.structure = v.reservoir = v.res_pocket = false;
    double best_template = 1e9, best_reservoir = 1e9;
    const auto& l = v.landmarks;
    std::vector<bool> in_template(l.size(), false);
    for (size_t i = 0; i < l.size(); ++i) {
      for (size_t j = i + 1; j < l.size(); ++j) {
        const double sep = std::hypot(l[i].x - l[j].x, l[i].y - l[j].y);
        const double mid = std::hypot(0.5 * (l[i].x + l[j].x), 0.5 * (l[i].y + l[j].y));
        if (Near(sep, template_spacing_)) {
          in_template[i] = in_template[j] = true;
          if (mid < best_template) {
            best_template = mid;
            v.structure = true;
            v.frame = FrameOfLine(l[i], l[j]);
          }
        } else if (Near(sep, reservoir_spacing_) && mid < best_reservoir) {
          best_reservoir = mid;
          v.reservoir = true;
          v.res_a = l[i];
          v.res_b = l[j];
        }
      }
    }
    if (v.structure) {
      v.ahead_min = 1e9;
      v.ahead_max = -1e9;
      for (size_t i = 0; i < l.size(); ++i) {
        if (!in_template[i]) continue;
        const double along = v.frame.ToInstant(l[i]).y;
        v.ahead_min = std::min(v.ahead_min, along);
        v.ahead_max = std::max(v.ahead_max, along);
      }
      for (const Point& q : v.pockets) v.pockets_p.push_back(v.frame.ToInstant(q));
    }
    if (v.reservoir) {
      const Point mid{0.5 * (v.res_a.x + v.res_b.x), 0.5 * (v.res_a.y + v.res_b.y)};
      double best = 0.5 * reservoir_spacing_;
      for (const Point& q : v.pockets) {
        const double d = std::hypot(q.x - mid.x, q.y - mid.y);
        if (d < best) {
          best = d;
          v.res_pocket = true;
          v.pocket = q;
        }
      }
    }
  }

  // What the robot tells the others (one byte of range-and-bearing): it is
  // approaching a pocket, or travelling along a path and in which direction
  // (+y_p or -y_p: the same for every robot, all see the same boundary).
  enum Signal : uint8_t {
    kNothing = 0,
    kApproaching = 1,
    kTravellingLeft = 2,
    kTravellingRight = 3
  };
  Signal Broadcast() const {
    if (behaviour_ == Behaviour::kApproach || behaviour_ == Behaviour::kPickUp) return kApproaching;
    if (behaviour_ != Behaviour::kDeploy || (phase_ != 1 && phase_ != 4)) return kNothing;
    return direction_ > 0 ? kTravellingLeft : kTravellingRight;
  }

  // The other robots the range-and-bearing device hears, in the body frame.
  void SeeRobots() {
    robots_.clear();
    for (const auto& packet : rab_->packets()) {
      const uint8_t signal = packet.data.empty() ? 0 : packet.data[0];
      robots_.push_back({FromPolar(packet.range, packet.bearing), signal});
    }
  }

  // The robot's left side on the double path is free (3.4.4): no robot
  // beside it (within `side_length` along the boundary) on the other path's
  // side, up to one path beyond it. Left of the traffic is away from the
  // boundary on the main path and towards it on the auxiliary path.
  bool LeftFree() const {
    const double left = -direction_;  // along x_p (towards the boundary)
    for (const SeenRobot& r : robots_) {
      const Point q = view_.frame.ToInstant(r.at);
      const double side = q.x * left;
      if (side > 0.05 && side < lane_gap_ + 0.2 && std::abs(q.y) < side_length_) return false;
    }
    return true;
  }

  // Another robot ahead on the same path (within 45 degrees of the direction
  // of travel, less than a robot's width aside), within `follow_distance`:
  // the robots behind a stopped one stop too (3.4.4). A robot beside this
  // one is not ahead, nor one travelling the other way (a robot changing
  // paths meets them head-on): two robots must not wait on each other.
  bool RobotAheadOnPath() const {
    const uint8_t oncoming = direction_ > 0 ? kTravellingRight : kTravellingLeft;
    for (const SeenRobot& r : robots_) {
      if (r.signal == oncoming) continue;  // changing paths: they pass, avoiding each other
      const Point q = view_.frame.ToInstant(r.at);
      const double ahead = q.y * direction_;
      if (ahead > std::abs(q.x) && ahead < follow_distance_ && std::abs(q.x) < 0.19) return true;
    }
    return false;
  }

  // Another robot straight ahead (body frame, within 45 degrees) within
  // `follow_distance`.
  bool RobotInFront() const {
    for (const SeenRobot& r : robots_) {
      if (r.at.x > std::abs(r.at.y) && r.at.x < follow_distance_ && std::abs(r.at.y) < 0.19) {
        return true;
      }
    }
    return false;
  }

  // Another robot approaching the reservoir's pocket (in view) and closer to
  // it than this one (3.4.4); only robots within `wait_distance` of it count,
  // not those at a neighbouring reservoir.
  bool OtherCloserToPocket() const {
    const Point& p = view_.pocket;
    const double mine = std::hypot(p.x, p.y);
    for (const SeenRobot& r : robots_) {
      if (r.signal != kApproaching) continue;
      const double theirs = std::hypot(r.at.x - p.x, r.at.y - p.y);
      if (theirs < mine && theirs < wait_distance_) return true;
    }
    return false;
  }

  // More of the pockets in view lie between the robot and the boundary line
  // than beyond it.
  bool OnStructureSide() const {
    int nearer = 0;
    for (const Point& q : view_.pockets_p) nearer += q.x < view_.frame.distance ? 1 : -1;
    return nearer > 0;
  }

  // The robot's heading in the template frame, from the camera: the template
  // frame's x axis points to the boundary (3.4.1), the body sees it at psi_p.
  double VisualHeading() const { return -view_.frame.psi_p; }

  // A point of the body frame in the template frame.
  Point ToTemplate(const Point& b) const {
    const double c = std::cos(psi_), s = std::sin(psi_);
    return {x_ + c * b.x - s * b.y, y_ + s * b.x + c * b.y};
  }
  // A point of the template frame in the body frame.
  Point ToBody(const Point& t) const {
    const double c = std::cos(psi_), s = std::sin(psi_);
    const double dx = t.x - x_, dy = t.y - y_;
    return {c * dx + s * dy, -s * dx + c * dy};
  }

  // (Re)initialises the template frame at the robot's place, its x axis
  // towards the boundary as the camera sees it; the reservoir location,
  // known in the old frame, is carried over by odometry (3.4.3, drop).
  void ResetTemplateFrame() {
    const Point res_body = ToBody(reservoir_);
    x_ = y_ = 0;
    psi_ = VisualHeading();
    reservoir_ = ToTemplate(res_body);
    have_template_ = true;
  }

  // The height inhibition of eq. 3.3: a front sensor of the proximity ring
  // (6 cm above the floor) sees the structure ahead, so it is higher than
  // 6 cm there. What the sensor sees is not a template landmark if no
  // landmark blob lies near the point it reads.
  bool StructureTooHigh() const {
    for (const auto& r : proximity_->readings()) {
      if (std::abs(Wrap(r.angle)) > M_PI / 6 || r.value <= height_reading_) continue;
      const Point hit = FromPolar(kBodyRadius + 0.01 / r.value, r.angle);
      bool landmark = false;
      for (const Point& l : view_.landmarks) {
        landmark = landmark || std::hypot(l.x - hit.x, l.y - hit.y) < 0.06;
      }
      if (!landmark) return true;
    }
    return false;
  }

  bool Blocked() {
    blocked_ticks_ = forward_ < 0.2 * slow_ * tick_ ? blocked_ticks_ + 1 : 0;
    return blocked_ticks_ * tick_ > 1.5;
  }

  // --- Actions -------------------------------------------------------------

  void Stop() { wheels_->SetLinearVelocity(0, 0); }

  // Towards `angle` (body frame), turning away from obstacles the proximity
  // ring sees ahead.
  void SteerAvoiding(double angle, double speed) {
    const swarm::Vector o = obstacle_.Read();
    if (o.Length() > 0.1 && std::abs(o.Angle()) < M_PI / 2) {
      angle = o.Angle() + (o.Angle() > 0 ? -M_PI / 2 : M_PI / 2);
    }
    swarm::SteerTowards(angle, speed, *wheels_);
  }

  void GoTo(const Point& target, double speed) {
    const Point b = ToBody(target);
    SteerAvoiding(std::atan2(b.y, b.x), speed);
  }

  // Manipulator postures: carrying (magnet face down, raised) and lying on
  // the ground to find a pocket (IR side ahead, lowest, tilted 45 degrees).
  void Carry() {
    manipulator_->SetIrSide();
    manipulator_->SetTilt(M_PI / 2);
    manipulator_->SetElevation(carry_elevation_);
  }
  void LieDown() {
    manipulator_->SetIrSide();
    manipulator_->SetTilt(-M_PI / 4);
    manipulator_->SetElevation(manipulator_->min_elevation());
  }
  bool LyingDown() const {
    return std::abs(Wrap(arm_->rotation() - M_PI)) < 0.05 &&
           std::abs(arm_->tilt() + M_PI / 4) < 0.05 &&
           arm_->elevation() < manipulator_->min_elevation() + 0.005;
  }
  double MiddleIr() const {
    const auto& r = arm_->readings();
    return r.size() < 4 ? 0.0 : std::max(r[2].value, r[3].value);
  }

  void Enter(Behaviour b) {
    behaviour_ = b;
    phase_ = 0;
    phase_ticks_ = 0;
    blocked_ticks_ = 0;
    lost_ticks_ = 0;
    backoff_ticks_ = 0;
  }
  void NextPhase() {
    ++phase_;
    phase_ticks_ = 0;
    blocked_ticks_ = 0;
  }
  double PhaseSeconds() const { return phase_ticks_ * tick_; }

  // --- Behaviours (3.4.3) --------------------------------------------------

  // Random walk until both regions have been seen.
  void Explore() {
    if (view_.structure && !have_template_) ResetTemplateFrame();
    if (view_.reservoir && view_.res_pocket && !have_reservoir_) {
      reservoir_ = ToTemplate(ApproachPoint());
      have_reservoir_ = true;
    }
    if (have_template_ && have_reservoir_) {
      Enter(arm_->holding() ? Behaviour::kGotoStructure : Behaviour::kGotoReservoir);
      return;
    }
    walk_.Step(obstacle_.Read(), rng(), *wheels_);
  }

  void GotoReservoir() {
    if (view_.reservoir && view_.res_pocket) {
      Enter(Behaviour::kApproach);
      Approach();
      return;
    }
    ++phase_ticks_;
    const Point b = ToBody(reservoir_);
    if (std::hypot(b.x, b.y) < 0.05 || PhaseSeconds() > goto_timeout_) {
      have_reservoir_ = false;  // not where odometry said: look for it
      Enter(Behaviour::kExplore);
      return;
    }
    GoTo(reservoir_, speed_);
  }

  // The point in front of the reservoir's pocket, on the structure's side of
  // the line through its two landmarks (by odometry: the template frame's
  // origin is where the robot last left the structure), or on the robot's
  // side before it knows the structure. Not simply the robot's side: a robot
  // that came round a reservoir by a wall would aim between the two.
  Point ApproachPoint() const {
    const View& v = view_;
    const double ux = v.res_b.x - v.res_a.x, uy = v.res_b.y - v.res_a.y;
    const double len = std::hypot(ux, uy);
    double nx = -uy / len, ny = ux / len;
    Point side{-v.pocket.x, -v.pocket.y};  // from the pocket towards the robot
    if (have_template_) {
      const Point origin = ToBody({0, 0});
      side = {origin.x - v.pocket.x, origin.y - v.pocket.y};
    }
    if (nx * side.x + ny * side.y < 0) {
      nx = -nx;
      ny = -ny;
    }
    return {v.pocket.x + approach_distance_ * nx, v.pocket.y + approach_distance_ * ny};
  }

  // Visual navigation to the point in front of the pocket, then towards it
  // with the manipulator lying on the ground.
  void Approach() {
    if (swarm_ && WaitForCloserRobot()) return;
    ++phase_ticks_;
    if (phase_ == 0) {
      LieDown();
      if (!view_.reservoir) {
        Enter(Behaviour::kGotoReservoir);
        return;
      }
      if (!view_.res_pocket) {
        Stop();  // the reservoir is waiting for its refill
        // Several reservoirs (a swarm's arena): one left empty for longer
        // than goto_timeout has run out; look for another.
        if (swarm_ && PhaseSeconds() > goto_timeout_) {
          have_reservoir_ = false;
          Enter(Behaviour::kExplore);
        }
        return;
      }
      const Point q = ApproachPoint();
      if (std::hypot(q.x, q.y) < 0.03) {
        NextPhase();
        return;
      }
      // Pushed against a landmark (or, in a swarm, a robot): back off for 2 s.
      if (backoff_ticks_ > 0 || Blocked()) {
        backoff_ticks_ = backoff_ticks_ > 0 ? backoff_ticks_ - 1 : static_cast<int>(2 / tick_);
        blocked_ticks_ = 0;
        wheels_->SetLinearVelocity(-slow_, -0.5 * slow_);
        return;
      }
      swarm::SteerTowards(std::atan2(q.y, q.x), std::hypot(q.x, q.y) < 0.15 ? slow_ : speed_,
                          *wheels_);
      return;
    }
    if (phase_ == 1) {  // face the pocket, wait for the manipulator
      if (!view_.res_pocket) {
        Enter(Behaviour::kApproach);
        return;
      }
      const double bearing = std::atan2(view_.pocket.y, view_.pocket.x);
      if (std::abs(bearing) < 0.02 && LyingDown()) {
        NextPhase();
        return;
      }
      const double turn = std::clamp(bearing / 0.5, -1.0, 1.0) * slow_;
      wheels_->SetLinearVelocity(-turn, turn);
      return;
    }
    // phase 2: towards the pocket until close enough for the pick-up.
    if (view_.res_pocket) {
      const double d = std::hypot(view_.pocket.x, view_.pocket.y);
      if (d > pickup_distance_) {
        if (Blocked()) {
          Retry();
          return;
        }
        swarm::SteerTowards(std::atan2(view_.pocket.y, view_.pocket.x), slow_, *wheels_);
        return;
      }
    }
    Enter(Behaviour::kPickUp);
    PickUp();
  }

  // A robot stopped by a swarm rule for longer than `max_wait` ignores the
  // rules for `max_wait` / 4 (driving on, avoiding what its proximity ring
  // sees): the rules are local and several robots can wait on each other in a
  // crowd. Call once per step: true while the rules hold.
  bool SwarmRulesHold() {
    if (bypass_ticks_ > 0) {
      --bypass_ticks_;
      return false;
    }
    return true;
  }
  // Counts a step stopped by a rule; past `max_wait` starts the bypass.
  void Stalled() {
    stuck_ticks_ = 0;
    if (++stalled_ticks_ * tick_ > max_wait_) {
      stalled_ticks_ = 0;
      bypass_ticks_ = static_cast<int>(0.25 * max_wait_ / tick_);
    }
  }

  // While another robot closer to the pocket approaches it, wait (at least
  // `wait_time`), backing away to `wait_distance` from the pocket so that the
  // approach point stays clear; then approach from the start.
  bool WaitForCloserRobot() {
    if (!SwarmRulesHold()) {
      wait_ticks_ = 0;
      return false;
    }
    if (wait_ticks_ > 0) {
      --wait_ticks_;
    } else if (view_.res_pocket && OtherCloserToPocket()) {
      wait_ticks_ = static_cast<int>(wait_time_ / tick_);
      Enter(Behaviour::kApproach);
    } else {
      stalled_ticks_ = 0;
      return false;
    }
    Stalled();
    const Point& p = view_.pocket;
    if (view_.res_pocket && std::hypot(p.x, p.y) < wait_distance_) {
      SteerAvoiding(std::atan2(-p.y, -p.x), slow_);
    } else {
      Stop();
    }
    return true;
  }

  // Forwards until the manipulator's IR sensors see the pocket, on until the
  // body touches it, then rise onto its top, engage the magnet and lift it.
  void PickUp() {
    ++phase_ticks_;
    switch (phase_) {
      case 0:  // forwards until the IR sensors see it
        if (MiddleIr() > 0.5) {
          NextPhase();
        } else if (PhaseSeconds() > 8) {
          Retry();
        } else {
          wheels_->SetLinearVelocity(slow_, slow_);
        }
        return;
      case 1:  // creep until touching
        wheels_->SetLinearVelocity(slow_, slow_);
        if (PhaseSeconds() >= 1.0) {
          Stop();
          manipulator_->SetTilt(M_PI / 2);
          NextPhase();
        }
        return;
      case 2:  // magnet face down onto the pocket's top
        Stop();
        if (arm_->tilt() > M_PI / 2 - 0.02) {
          manipulator_->EngageMagnet();
          NextPhase();
        }
        return;
      case 3:  // hold it
        Stop();
        if (arm_->holding()) {
          manipulator_->SetElevation(carry_elevation_);
          NextPhase();
        } else if (PhaseSeconds() > 3) {
          manipulator_->DisengageMagnet();
          Retry();
        }
        return;
      default:  // lifted: this is the reservoir location
        Stop();
        if (PhaseSeconds() > 1.5) {
          reservoir_ = {x_, y_};
          have_reservoir_ = true;
          inhibitions_ = 0;
          Enter(Behaviour::kGotoStructure);
        }
        return;
    }
  }

  // A failed pick-up: back off and approach again.
  void Retry() {
    Enter(Behaviour::kApproach);
    wheels_->SetLinearVelocity(-slow_, -slow_);
    LieDown();
  }

  // Odometry back to the template frame's origin (the last drop), until the
  // structure region is in view (two template landmarks).
  void GotoStructure() {
    if (!arm_->holding()) {  // lost it on the way
      Enter(Behaviour::kGotoReservoir);
      return;
    }
    if (swarm_ && detour_ && view_.structure && OnStructureSide()) detour_ = false;
    const Point goal{detour_ ? -2 * path_distance_ : 0.0, 0};
    if (view_.structure && !detour_) {
      Enter(Behaviour::kDeploy);
      Deploy();
      return;
    }
    ++phase_ticks_;
    const Point b = ToBody(goal);
    if (detour_ && (std::hypot(b.x, b.y) < 0.1 || PhaseSeconds() > goto_timeout_)) {
      detour_ = false;
      Enter(Behaviour::kGotoStructure);
      return;
    }
    if (std::hypot(b.x, b.y) < 0.05 || PhaseSeconds() > goto_timeout_) {
      have_template_ = false;  // not where odometry said: look for it
      Enter(Behaviour::kExplore);
      return;
    }
    // Pushed against a landmark (an end of the boundary on a detour) or a
    // robot: back off on an arc for 1.5 to 3 s, then on.
    if (backoff_ticks_ > 0 || Blocked()) {
      backoff_ticks_ =
          backoff_ticks_ > 0 ? backoff_ticks_ - 1 : static_cast<int>(rng().Uniform(1.5, 3) / tick_);
      blocked_ticks_ = 0;
      wheels_->SetLinearVelocity(-slow_, -0.5 * slow_);
      return;
    }
    GoTo(goal, speed_);
  }

  // Along the boundary at path_distance until eq. 3.3 picks the y-position,
  // then towards the boundary until eq. 3.5 (or the boundary) picks x.
  void Deploy() {
    ++phase_ticks_;
    // The template can vanish for a moment (a heap hides a landmark): carry
    // on as before for up to lost_time, then look for it again.
    if (!view_.structure) {
      if (++lost_ticks_ * tick_ > lost_time_) Enter(Behaviour::kGotoStructure);
      return;
    }
    lost_ticks_ = 0;
    const InstantFrame& f = view_.frame;
    // In a swarm, robots push each other and odometry's heading drifts: the
    // pockets already built, between the robot and the boundary line, show
    // it is on the structure's side; its heading is then the camera's.
    if (swarm_ && OnStructureSide()) psi_ = VisualHeading();
    // The boundary seen from its far side (the template frame's x axis points
    // to it from the structure's side): round the end, back by odometry. So
    // too a robot pushed onto the line beyond an end of the boundary, where
    // the direction to the line means nothing.
    const bool on_line_past_end =
        f.distance < kBodyRadius && (view_.ahead_max < 0 || view_.ahead_min > 0);
    if (std::cos(psi_ + f.psi_p) < 0 || on_line_past_end) {
      detour_ = true;
      Enter(Behaviour::kGotoStructure);
      return;
    }
    if (swarm_ && phase_ != 2) {
      SwarmDeploy();
      return;
    }
    const double offset = f.distance - path_distance_;  // > 0: too far from the boundary
    if (phase_ == 0) {                                  // onto the path
      if (std::abs(offset) < 0.03) {
        direction_ = rng().Bernoulli(0.5) ? 1 : -1;
        NextPhase();
      } else {
        // Towards the path; past an end of the boundary, back along it too.
        const double vx = std::clamp(offset / 0.1, -1.0, 1.0);
        const double vy = view_.ahead_max < 0 ? -1.0 : view_.ahead_min > 0 ? 1.0 : 0.0;
        SteerAvoiding(Wrap(f.psi_p + std::atan2(vy, vx)), speed_);
      }
      return;
    }
    if (phase_ == 1) {                        // along the boundary
      if (AtEnd()) direction_ = -direction_;  // an end of the boundary: turn around
      // Pinned for 3 s (past an end of the boundary, between a wall and the
      // heap): 1.5 to 3 s straight away from the boundary, then on.
      stuck_ticks_ = forward_ < 0.2 * slow_ * tick_ ? stuck_ticks_ + 1 : 0;
      if (stuck_ticks_ * tick_ > 3) {
        stuck_ticks_ = 0;
        backoff_ticks_ = static_cast<int>(rng().Uniform(1.5, 3) / tick_);
      }
      if (backoff_ticks_ > 0) {
        --backoff_ticks_;
        swarm::SteerTowards(Wrap(f.psi_p + M_PI), speed_, *wheels_);
        return;
      }
      // Eq. 3.3, tried at each step of travel along the path (not while
      // turning on the spot at an end).
      const int n_f = CountInfluential(view_.pockets_p, delta1_);
      const bool moving = forward_ > 0.5 * speed_ * tick_;
      if (moving && rng().Bernoulli(YDepositionProbability(n_f, k1_, alpha_))) {
        NextPhase();
        return;
      }
      const double correction = std::clamp(3.0 * offset, -0.6, 0.6);
      SteerAvoiding(Wrap(f.psi_p + direction_ * (M_PI / 2 - correction)), speed_);
      return;
    }
    if (phase_ == 3) {  // inhibited: back onto the path, then on along it
      if (offset > -0.03) {
        phase_ = 1;
        phase_ticks_ = 0;
      } else {
        swarm::SteerTowards(Wrap(f.psi_p + M_PI), speed_, *wheels_);
      }
      return;
    }
    // phase 2: towards the boundary (the point p).
    const double heading_error = Wrap(f.psi_p);
    if (inhibitions_ < max_inhibitions_ && StructureTooHigh()) {
      ++inhibitions_;
      phase_ = 3;
      phase_ticks_ = 0;
      return;
    }
    if (std::abs(heading_error) > 0.1 && phase_ticks_ < 50) {
      const double turn = std::clamp(heading_error / 0.5, -1.0, 1.0) * slow_;
      wheels_->SetLinearVelocity(-turn, turn);
      blocked_ticks_ = 0;
      return;
    }
    int n_f = 0;
    const double mu = MeanInfluentialX(view_.pockets_p, delta2_, d_m_, n_f);
    const bool chosen = n_f > 0 && rng().Bernoulli(XDepositionProbability(mu, k2_, sigma_));
    const bool blocked = Blocked();
    // In a swarm, held up by a robot (not a heap), or pushed past an end of
    // the boundary (the pocket would land outside the structure): back onto
    // the path.
    const bool past_end = view_.ahead_max < -0.05 || view_.ahead_min > 0.05;
    if (swarm_ && ((blocked && RobotInFront()) || past_end)) {
      phase_ = 3;
      phase_ticks_ = 0;
      blocked_ticks_ = 0;
      return;
    }
    if (chosen || f.distance <= force_distance_ || blocked) {
      Stop();
      Enter(Behaviour::kDrop);
      return;
    }
    swarm::SteerTowards(heading_error, slow_, *wheels_);
  }

  // Deploy on the double path (3.4.4). Phases: 0 onto the auxiliary path;
  // 1 along a path (the deposition rule of eq. 3.3 on the main path only);
  // 2 towards the boundary (Deploy, as for one robot); 3 inhibited, back
  // onto the main path; 4 after the drop, on along the main path until the
  // left side is free, then off to the reservoir.
  void SwarmDeploy() {
    const InstantFrame& f = view_.frame;
    const bool rules = SwarmRulesHold();
    if (phase_ == 0) {
      // On the auxiliary path, or nearer the boundary (then the path's
      // steering takes the robot out to it while it travels along).
      const double offset = f.distance - path_distance_ - lane_gap_;
      if (offset < 0.03) {
        lane_ = kAuxiliaryPath;
        lambda_ = kMainPath;  // the main path as soon as the left side is free
        NextPhase();
        return;
      }
      if (rules && RobotInFront()) {
        Stop();
        Stalled();
        return;
      }
      const double vx = std::clamp(offset / 0.1, -1.0, 1.0);
      const double vy = view_.ahead_max < 0 ? -1.0 : view_.ahead_min > 0 ? 1.0 : 0.0;
      SteerAvoiding(Wrap(f.psi_p + std::atan2(vy, vx)), speed_);
      return;
    }
    if (phase_ == 3) {  // inhibited: back onto the main path (a robot there: go on anyway)
      if (f.distance - path_distance_ > -0.03 || Blocked()) {
        phase_ = 1;
        phase_ticks_ = 0;
        blocked_ticks_ = 0;
      } else {
        swarm::SteerTowards(Wrap(f.psi_p + M_PI), speed_, *wheels_);
      }
      return;
    }
    const bool leaving = phase_ == 4;
    if (leaving) lane_ = kMainPath;
    direction_ = lane_ == kMainPath ? 1 : -1;
    if (leaving) {
      if (!rules || LeftFree() || AtEnd()) {
        Enter(Behaviour::kGotoReservoir);
        return;
      }
    } else {
      // The loop mechanism: lambda flips with probability tau per step; at
      // an end of the boundary the robot must take the other path.
      const bool at_end = AtEnd();
      if (at_end) {
        lambda_ = -lane_;
      } else if (rng().Bernoulli(tau_)) {
        lambda_ = -lambda_;
      }
      if (lambda_ != lane_) {
        if (!rules || LeftFree()) {
          lane_ = lambda_;
          direction_ = -direction_;
        } else if (at_end) {
          Stop();  // wait at the end for the other path to clear
          Stalled();
          return;
        }
      }
    }
    if (rules && RobotAheadOnPath()) {
      Stop();
      Stalled();
      return;
    }
    stalled_ticks_ = 0;
    // Held up for 3 s with nothing in the rules against moving (a heap, a
    // landmark, often at an end of the boundary, or a robot coming the other
    // way on the other path): 1.5 to 3 s straight away from the boundary,
    // then on. Two robots head-on must not both back off the same way: the
    // one on the main path (nearer the boundary) moves towards the boundary
    // instead, so the two paths part.
    stuck_ticks_ = forward_ < 0.2 * slow_ * tick_ ? stuck_ticks_ + 1 : 0;
    if (stuck_ticks_ * tick_ > 3) {
      stuck_ticks_ = 0;
      backoff_ticks_ = static_cast<int>(rng().Uniform(1.5, 3) / tick_);
      backoff_inwards_ = lane_ == kMainPath && RobotInFront() && f.distance > path_distance_;
    }
    if (backoff_ticks_ > 0) {
      --backoff_ticks_;
      swarm::SteerTowards(Wrap(f.psi_p + (backoff_inwards_ ? 0 : M_PI)), speed_, *wheels_);
      return;
    }
    const double target = lane_ == kMainPath ? path_distance_ : path_distance_ + lane_gap_;
    const double offset = f.distance - target;
    // Eq. 3.3 on the main path, not before its start (past the boundary's
    // right end, where robots coming off the auxiliary path join it).
    const bool beside = view_.ahead_min < 0;
    if (!leaving && lane_ == kMainPath && beside && std::abs(offset) < 0.05) {
      const int n_f = CountInfluential(view_.pockets_p, delta1_);
      const bool moving = forward_ > 0.5 * speed_ * tick_;
      if (moving && rng().Bernoulli(YDepositionProbability(n_f, k1_, alpha_))) {
        phase_ = 2;
        phase_ticks_ = 0;
        blocked_ticks_ = 0;
        return;
      }
    }
    const double correction = std::clamp(3.0 * offset, -0.6, 0.6);
    SteerAvoiding(Wrap(f.psi_p + direction_ * (M_PI / 2 - correction)), speed_);
  }

  bool AtEnd() const {
    return direction_ > 0 ? view_.ahead_max <= end_margin_ : view_.ahead_min >= -end_margin_;
  }

  // Let go, re-initialise the template frame here, and back off.
  void Drop() {
    ++phase_ticks_;
    if (phase_ == 0) {
      manipulator_->DisengageMagnet();
      // Over a landmark the pocket stays on the magnet: back off until it falls.
      if (arm_->holding() && PhaseSeconds() > 2) {
        wheels_->SetLinearVelocity(-slow_, -slow_);
      } else {
        Stop();
      }
      if (!arm_->holding() && PhaseSeconds() > 0.5) {
        if (view_.structure) ResetTemplateFrame();
        NextPhase();
      }
      return;
    }
    if (phase_ == 1) {
      wheels_->SetLinearVelocity(-slow_, -slow_);
      if (PhaseSeconds() > 2) NextPhase();
      return;
    }
    LieDown();
    if (swarm_ && view_.structure) {
      Enter(Behaviour::kDeploy);
      phase_ = 4;
      return;
    }
    Enter(Behaviour::kGotoReservoir);
  }

  // Parameters (README.md).
  double speed_ = 0, slow_ = 0, tick_ = 0;
  double template_spacing_ = 0, reservoir_spacing_ = 0, spacing_tolerance_ = 0;
  double path_distance_ = 0, end_margin_ = 0;
  double k1_ = 0, alpha_ = 0, delta1_ = 0, height_reading_ = 0;
  int max_inhibitions_ = 0;
  double k2_ = 0, sigma_ = 0, delta2_ = 0, d_m_ = 0, force_distance_ = 0;
  double approach_distance_ = 0, pickup_distance_ = 0, carry_elevation_ = 0;
  double goto_timeout_ = 0, lost_time_ = 0;
  bool swarm_ = false;
  double lane_gap_ = 0, tau_ = 0, follow_distance_ = 0, side_length_ = 0;
  double wait_distance_ = 0, wait_time_ = 0, max_wait_ = 0;

  // Devices.
  const OmnidirectionalCamera* camera_ = nullptr;
  const WheelEncoders* encoders_ = nullptr;
  const ManipulatorSensor* arm_ = nullptr;
  const ProximitySensor* proximity_ = nullptr;
  DifferentialSteering* wheels_ = nullptr;
  ManipulatorActuator* manipulator_ = nullptr;
  const RangeAndBearingSensor* rab_ = nullptr;
  RangeAndBearingActuator* beacon_ = nullptr;
  swarm::ObstacleVector obstacle_;
  swarm::RandomWalk walk_;

  // State: odometry in the template frame, the reservoir location in it.
  double x_ = 0, y_ = 0, psi_ = 0, forward_ = 0;
  Point reservoir_;
  bool have_template_ = false, have_reservoir_ = false;
  View view_;
  Behaviour behaviour_ = Behaviour::kExplore;
  int phase_ = 0, phase_ticks_ = 0, blocked_ticks_ = 0, direction_ = 1;
  int inhibitions_ = 0;  // of the pocket carried
  int lost_ticks_ = 0;   // since the template was last in view, deploying
  bool detour_ = false;  // going round the boundary's end to the structure's side
  // Swarm (3.4.4): the other robots heard this tick; the path the robot is on
  // and the one it has decided for (lambda); ticks still to wait.
  struct SeenRobot {
    Point at;
    uint8_t signal = kNothing;
  };
  std::vector<SeenRobot> robots_;
  int lane_ = kMainPath, lambda_ = kMainPath;
  int wait_ticks_ = 0;
  int stalled_ticks_ = 0;         // consecutive steps stopped by a swarm rule
  int bypass_ticks_ = 0;          // steps left ignoring the swarm rules
  int backoff_ticks_ = 0;         // approach: steps left backing off
  bool backoff_inwards_ = false;  // deploy: backing off towards the boundary
  int stuck_ticks_ = 0;           // consecutive steps on a path without moving, the rules allowing
};

}  // namespace
}  // namespace colony::pocket_builder

COLONY_REGISTER_CONTROLLER(
    colony::pocket_builder::PocketBuilder, "pocket_builder",
    "seed 004's barrier construction with pockets: explore, goto-reservoir, approach, pick-up, "
    "goto-structure, deploy, drop",
    {{"speed", "0.01..0.3 (m/s)", "0.1", "cruising speed (the seed: about 10 cm/s)"},
     {"slow_speed", "0.01..0.3 (m/s)", "0.05", "final approach, pick-up, towards the boundary"},
     {"tick", "0.001..1 (s)", "0.1", "the control period (the experiment's 1 / ticks_per_second)"},
     {"template_spacing", "0.05..5 (m)", "0.333",
      "distance between adjacent template landmarks, d_t1"},
     {"reservoir_spacing", "0.05..5 (m)", "0.24",
      "distance between a reservoir's two landmarks, d_t2"},
     {"spacing_tolerance", "0..1 (m)", "0.04", "how far a seen pair may be from these spacings"},
     {"path_distance", "0.1..2 (m)", "0.35", "distance of the deploy path from the boundary line"},
     {"end_margin", "-1..1 (m)", "0",
      "turn round this far before (> 0) or past (< 0) the last landmark"},
     {"k1", "0..1", "0.02", "eq. 3.3 scaling factor (a probability per control step)"},
     {"alpha", "0..100", "0.5", "eq. 3.3 constant"},
     {"delta1", "0..2 (m)", "0.08", "eq. 3.3 influential range"},
     {"height_reading", "0..1", "0.15",
      "front proximity reading (0.01 m / d) above which the structure ahead counts as higher than "
      "the ring"},
     {"max_inhibitions", "whole number >= 0", "3", "height inhibitions allowed per pocket"},
     {"k2", "0..1", "0.2", "eq. 3.5 scaling factor (per control step)"},
     {"sigma", "0.0001..1 (m)", "0.03", "eq. 3.5 constant"},
     {"delta2", "0..2 (m)", "0.06", "eq. 3.4-3.5 influential range"},
     {"manipulator_distance", "0..0.5 (m)", "0.12",
      "d_m of eq. 3.4: robot's centre to the carried pocket's"},
     {"force_distance", "0..1 (m)", "0.17",
      "forced drop this close to the boundary line (robot's centre)"},
     {"approach_distance", "0.15..1 (m)", "0.3", "the point in front of the reservoir's pocket"},
     {"pickup_distance", "0.05..1 (m)", "0.2", "pick-up starts with the pocket this close"},
     {"carry_elevation", "0.03..0.2 (m)", "0.1", "head's height while carrying"},
     {"goto_timeout", ">= 1 (s)", "60", "give up an odometry leg and explore"},
     {"lost_time", ">= 0 (s)", "2", "how long deploy carries on without the template in view"},
     {"turn_probability", "0..1", "0.05", "explore: probability per step of a random turn"},
     {"turn_ticks", ">= 1", "20", "explore: longest random turn (steps)"},
     {"swarm", "true, false", "false",
      "the inter-robot rules below (3.4.4); needs range_and_bearing"},
     {"lane_gap", "0.17..1 (m)", "0.25",
      "the auxiliary path lies this much farther from the boundary than the main path"},
     {"tau", "0..1", "0.005",
      "tau_lambda of eq. 3.6: probability per step that the path decision lambda flips"},
     {"follow_distance", "0.17..2 (m)", "0.35",
      "stop behind a robot this close ahead on the same path"},
     {"side_length", "0..2 (m)", "0.3",
      "the left side is free when no robot is within this distance along the boundary on the other "
      "path's side"},
     {"wait_distance", "0.3..3 (m)", "0.6",
      "reservoir: only robots this close to the pocket count; the waiting robot backs away to this "
      "distance"},
     {"wait_time", ">= 0 (s)", "2", "reservoir: the shortest wait"},
     {"max_wait", ">= 1 (s)", "20",
      "a robot stopped by the swarm rules this long ignores them for a quarter of it"}});
