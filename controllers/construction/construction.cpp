// construction: a marXbot with the magnetic manipulator fetches cubes one by
// one and either drops them side by side into a ditch to make a bridge it
// then drives over, or stacks them into a tower (EXPERIMENTS.md E3).
//
// Mapping is not the point (seed 001 used SLAM and a planner): the cubes'
// starting places, the site and the goal come from <params>, and the robot
// navigates with its positioning sensor. The final approaches use the real
// sensors: the front proximity sensors stop the robot against a cube or the
// tower's base, the magnet is engaged and the manipulator sensor says when it
// holds, and the front ground sensor finds the ditch's edge.
//
// params:
//   task       "bridge" or "tower"
//   cubes      "x,y;x,y;..."  where the cubes to use lie, in the order to fetch them
//   site       "x,y"  bridge: the middle of the bridge, on the ditch's centre
//                     line; tower: where the tower stands
//   heading    degrees: the direction the robot faces when it places a cube;
//              bridge: across the ditch, from the robot's side to the far
//              side (default 0: +x)
//   goal       "x,y"  bridge: where to drive once the bridge is built
//   ditch_width  m (0.07): bridge only
//   speed      m/s (0.1)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "actuators/differential_steering/differential_steering.h"
#include "actuators/manipulator/manipulator.h"
#include "core/registry.h"
#include "sensors/ground/ground.h"
#include "sensors/manipulator/manipulator.h"
#include "sensors/positioning/positioning.h"
#include "sensors/proximity/proximity.h"

namespace {

struct Point {
  double x = 0, y = 0;
};

bool ReadPoint(const std::string& text, Point& p) {
  char extra = 0;
  return std::sscanf(text.c_str(), "%lf,%lf%c", &p.x, &p.y, &extra) == 2 && std::isfinite(p.x) &&
         std::isfinite(p.y);
}

Point ParsePoint(const colony::Params& params, const char* key) {
  const std::string text = params.GetString(key);
  Point p;
  if (!ReadPoint(text, p)) {
    throw colony::ParamError(key, text,
                             std::string("parameter '") + key + "': '" + text + "' is not \"x,y\"");
  }
  return p;
}

// Geometry of the marXbot with its manipulator (engines/dynamics3d README):
// the magnet face is 0.115 m ahead of the robot's axis with the magnet side
// forwards, so a held 6 cm cube's centre is 0.145 m ahead, level with the
// magnet's centre.
constexpr double kHeldAhead = 0.145;      // m
constexpr double kCubeSide = 0.06;        // m
constexpr double kGroundAhead = 0.065;    // m: the front ground sensor
constexpr double kLowElevation = 0.03;    // m: the magnet level with a cube's lower half
constexpr double kCarryElevation = 0.10;  // m
// Front proximity reading (0.01 m / d) with a cube face 3.3 cm from the ring:
// the cube's face then touches the magnet's.
constexpr double kTouching = 0.22;

class Construction : public colony::Controller {
 public:
  void Init(const colony::Params& params) override {
    task_ = params.GetString("task");
    if (task_ != "bridge" && task_ != "tower") {
      throw colony::ParamError(
          "task", task_,
          "parameter 'task': '" + task_ + "' is not accepted; accepted: bridge, tower");
    }
    const std::string cubes = params.GetString("cubes");
    std::stringstream list(cubes);
    for (std::string item; std::getline(list, item, ';');) {
      Point p;
      if (!ReadPoint(item, p)) {
        throw colony::ParamError(
            "cubes", cubes, "parameter 'cubes': '" + item + "' is not \"x,y\" (list: \"x,y;x,y\")");
      }
      cubes_.push_back(p);
    }
    const size_t needed = task_ == "bridge" ? 2 : 3;
    if (cubes_.size() != needed) {
      throw colony::ParamError("cubes", cubes,
                               "parameter 'cubes': a " + task_ + " takes " +
                                   std::to_string(needed) + " cubes, the list has " +
                                   std::to_string(cubes_.size()));
    }
    site_ = ParsePoint(params, "site");
    const double heading = params.GetDouble("heading", 0, -360, 360) * M_PI / 180;
    across_ = {std::cos(heading), std::sin(heading)};
    if (task_ == "bridge") goal_ = ParsePoint(params, "goal");
    ditch_width_ = params.GetDouble("ditch_width", 0.07, kCubeSide, 0.2);
    speed_ = params.GetDouble("speed", 0.1, 0.01, 0.3);
    position_ = &GetSensor<colony::PositioningSensor>("positioning");
    proximity_ = &GetSensor<colony::ProximitySensor>("proximity");
    ground_ = &GetSensor<colony::GroundSensor>("ground");
    arm_ = &GetSensor<colony::ManipulatorSensor>("manipulator");
    wheels_ = &GetActuator<colony::DifferentialSteering>("differential_steering");
    manipulator_ = &GetActuator<colony::ManipulatorActuator>("manipulator");
    manipulator_->SetMagnetSide();
    manipulator_->SetElevation(kCarryElevation);
  }

  void ControlStep() override {
    x_ = position_->x();
    y_ = position_->y();
    yaw_ = position_->yaw();
    ++ticks_in_phase_;
    switch (phase_) {
      case Phase::kToCube: {
        // Line up 0.3 m out from the cube's face nearest to the robot
        // (cubes lie square to the arena), then face the cube: the magnet
        // holds a face it meets about parallel.
        const Point cube = cubes_[index_];
        if (ticks_in_phase_ == 1) {
          const double dx = x_ - cube.x, dy = y_ - cube.y;
          face_normal_ = std::abs(dx) >= std::abs(dy) ? Point{std::copysign(1.0, dx), 0}
                                                      : Point{0, std::copysign(1.0, dy)};
        }
        if (Steer({cube.x + 0.30 * face_normal_.x, cube.y + 0.30 * face_normal_.y}, 0.01))
          Next(Phase::kFaceCube);
        break;
      }
      case Phase::kFaceCube:
        manipulator_->SetElevation(kLowElevation);
        manipulator_->DisengageMagnet();
        if (Face(cubes_[index_]) && std::abs(arm_->elevation() - kLowElevation) < 0.005)
          Next(Phase::kApproachCube);
        break;
      case Phase::kApproachCube: {
        // Creep forwards, aimed at the cube, until the front sensors say its
        // face is at the magnet's.
        if (FrontProximity() >= kTouching) {
          Stop();
          manipulator_->EngageMagnet();
          Next(Phase::kGrab);
          break;
        }
        Drive(cubes_[index_], 0.03);
        if (Distance(cubes_[index_]) < kHeldAhead - 0.01) Next(Phase::kGrab);  // sensors missed it
        break;
      }
      case Phase::kGrab:
        manipulator_->EngageMagnet();
        if (arm_->holding()) {
          Stop();
          // How far ahead the held cube's centre is: where the map puts it.
          held_ahead_ = std::clamp(Distance(cubes_[index_]), kHeldAhead, kHeldAhead + 0.015);
          manipulator_->SetElevation(kCarryElevation);
          Next(Phase::kLift);
        } else if (arm_->magnet_engaged()) {
          // Engaged but not touching: close the last millimetres.
          wheels_->SetLinearVelocity(0.01, 0.01);
          if (ticks_in_phase_ > 40) {
            // Give up this try: back off and approach again.
            manipulator_->DisengageMagnet();
            Next(Phase::kRetreatAndRetry);
          }
        } else {
          Stop();
        }
        break;
      case Phase::kRetreatAndRetry:
        manipulator_->DisengageMagnet();
        wheels_->SetLinearVelocity(-0.05, -0.05);
        if (ticks_in_phase_ > 20) Next(Phase::kToCube);
        break;
      case Phase::kLift:
        Stop();
        if (!arm_->holding()) {
          Next(Phase::kRetreatAndRetry);  // dropped it
        } else if (std::abs(arm_->elevation() - kCarryElevation) < 0.005) {
          Next(Phase::kBackOffHolding);
        }
        break;
      case Phase::kBackOffHolding:
        // Clear of walls and other cubes before turning with the cube.
        wheels_->SetLinearVelocity(-speed_, -speed_);
        if (!arm_->holding()) {
          Next(Phase::kRetreatAndRetry);
        } else if (ticks_in_phase_ > 10) {
          Stop();
          Next(Phase::kToSite);
        }
        break;
      case Phase::kToSite:
        if (!arm_->holding()) {
          Next(Phase::kRetreatAndRetry);
          break;
        }
        if (Steer(Staging(), 0.01)) Next(Phase::kFaceSite);
        break;
      case Phase::kFaceSite: {
        const Point ahead{x_ + across_.x, y_ + across_.y};
        if (Face(task_ == "bridge" ? ahead : Place())) {
          Next(Phase::kApproachSite);
          if (task_ == "tower") {
            // Over the tower's top with a centimetre to spare.
            manipulator_->SetElevation(kLowElevation +
                                       (index_ == 0 ? 0.005 : index_ * kCubeSide + 0.01));
          }
        }
        break;
      }
      case Phase::kApproachSite:
        if (task_ == "bridge") {
          // Forwards until the front ground sensor loses the floor: the
          // ditch's edge is then kGroundAhead ahead of the axis.
          if (ground_->readings()[0].value < 0.05f) {
            Stop();
            edge_ = {x_ + kGroundAhead * std::cos(yaw_), y_ + kGroundAhead * std::sin(yaw_)};
            Next(Phase::kAlignOverDitch);
          } else {
            // Aimed through the place, to correct a sideways offset.
            const Point p = Place();
            Drive({p.x + 0.3 * across_.x, p.y + 0.3 * across_.y}, 0.02);
          }
        } else if (index_ == 0) {
          // The first cube goes where the tower stands.
          if (Steer(Place(), held_ahead_)) {
            manipulator_->SetElevation(kLowElevation + 0.005);
            Next(Phase::kLower);
          }
        } else {
          if (std::abs(arm_->elevation() - (kLowElevation + index_ * kCubeSide + 0.01)) > 0.005) {
            Stop();
          } else if (FrontProximity() >= 0.35 || Distance(site_) < held_ahead_) {
            Stop();
            Next(Phase::kRelease);
          } else {
            Drive(site_, 0.02);
          }
        }
        break;
      case Phase::kAlignOverDitch: {
        // Back off until the held cube is over the ditch's middle.
        const double want = held_ahead_ - 0.5 * ditch_width_;  // edge's distance ahead of the axis
        const double now = (edge_.x - x_) * std::cos(yaw_) + (edge_.y - y_) * std::sin(yaw_);
        if (now >= want) {
          Stop();
          manipulator_->SetElevation(kLowElevation);
          Next(Phase::kLower);
        } else {
          wheels_->SetLinearVelocity(-0.02, -0.02);
        }
        break;
      }
      case Phase::kLower:
        Stop();
        if (std::abs(arm_->elevation() - manipulator_->elevation_target()) < 0.005 ||
            ticks_in_phase_ > 50) {
          Next(Phase::kRelease);
        }
        break;
      case Phase::kRelease:
        Stop();
        manipulator_->DisengageMagnet();
        if (!arm_->holding() && arm_->magnet() <= 0) Next(Phase::kBackOff);
        break;
      case Phase::kBackOff:
        wheels_->SetLinearVelocity(-speed_, -speed_);
        if (ticks_in_phase_ > 10) {
          manipulator_->SetElevation(kCarryElevation);
          Stop();
          ++index_;
          Next(index_ < cubes_.size() ? Phase::kToCube
                                      : (task_ == "bridge" ? Phase::kToBridge : Phase::kDone));
        }
        break;
      case Phase::kToBridge: {
        const Point start{site_.x - 0.35 * across_.x, site_.y - 0.35 * across_.y};
        if (Steer(start, 0.01)) Next(Phase::kFaceGoal);
        break;
      }
      case Phase::kFaceGoal:
        if (Face(goal_)) Next(Phase::kCross);
        break;
      case Phase::kCross:
        if (Steer(goal_, 0.02)) Next(Phase::kDone);
        break;
      case Phase::kDone:
        Stop();
        break;
    }
  }

 private:
  enum class Phase {
    kToCube,
    kFaceCube,
    kApproachCube,
    kGrab,
    kRetreatAndRetry,
    kLift,
    kBackOffHolding,
    kToSite,
    kFaceSite,
    kApproachSite,
    kAlignOverDitch,
    kLower,
    kRelease,
    kBackOff,
    kToBridge,
    kFaceGoal,
    kCross,
    kDone
  };

  void Next(Phase p) {
    phase_ = p;
    ticks_in_phase_ = 0;
  }
  // Where the current cube goes: bridge cubes side by side along the ditch.
  Point Place() const {
    if (task_ == "tower") return site_;
    const double along = (index_ == 0 ? -0.5 : 0.5) * (kCubeSide + 0.008);
    return {site_.x - along * across_.y, site_.y + along * across_.x};
  }
  // Where the robot lines up before the final approach to the site: back
  // from the place against the approach direction.
  Point Staging() const {
    const Point p = Place();
    const double back = task_ == "bridge" ? 0.30 : 0.35;
    return {p.x - back * across_.x, p.y - back * across_.y};
  }

  double Distance(const Point& p) const { return std::hypot(p.x - x_, p.y - y_); }
  double Bearing(const Point& p) const {
    return std::remainder(std::atan2(p.y - y_, p.x - x_) - yaw_, 2 * M_PI);
  }
  double FrontProximity() const {
    const auto& r = proximity_->readings();
    return std::max(r.front().value, r.back().value);  // the two sensors either side of the front
  }
  void Stop() { wheels_->SetLinearVelocity(0, 0); }

  // Turns on the spot towards `p`; true once facing it within 1 degree.
  bool Face(const Point& p) {
    const double error = Bearing(p);
    if (std::abs(error) < 0.0175) {
      Stop();
      return true;
    }
    const double turn = std::clamp(error * 0.15, -0.05, 0.05);
    const double minimum = 0.004;
    const double t = std::abs(turn) < minimum ? std::copysign(minimum, turn) : turn;
    wheels_->SetLinearVelocity(-t, t);
    return false;
  }
  // Drives towards `p` at `speed`, correcting the heading.
  void Drive(const Point& p, double speed) {
    const double turn = std::clamp(Bearing(p) * 0.2, -0.03, 0.03);
    wheels_->SetLinearVelocity(speed - turn, speed + turn);
  }
  // Turns towards `p`, then drives until `stop_at` from it; true once there.
  bool Steer(const Point& p, double stop_at) {
    const double distance = Distance(p);
    if (distance <= stop_at) {
      Stop();
      return true;
    }
    const double error = Bearing(p);
    const double turn = std::clamp(error * 0.3, -0.08, 0.08);
    const double forward =
        std::abs(error) > 0.2 ? 0.0 : std::min(speed_, distance - stop_at + 0.01);
    wheels_->SetLinearVelocity(forward - turn, forward + turn);
    return false;
  }

  std::string task_;
  std::vector<Point> cubes_;
  Point site_, goal_, across_{1, 0}, edge_, face_normal_{1, 0};
  double held_ahead_ = kHeldAhead;
  double ditch_width_ = 0.07, speed_ = 0.1;
  double x_ = 0, y_ = 0, yaw_ = 0;
  size_t index_ = 0;
  Phase phase_ = Phase::kToCube;
  int ticks_in_phase_ = 0;
  const colony::PositioningSensor* position_ = nullptr;
  const colony::ProximitySensor* proximity_ = nullptr;
  const colony::GroundSensor* ground_ = nullptr;
  const colony::ManipulatorSensor* arm_ = nullptr;
  colony::DifferentialSteering* wheels_ = nullptr;
  colony::ManipulatorActuator* manipulator_ = nullptr;
};

COLONY_REGISTER_CONTROLLER(
    Construction, "construction",
    "fetch cubes with the magnetic manipulator and build a bridge over a ditch (then cross it) or "
    "a tower",
    {{"task", "bridge, tower", "", "what to build"},
     {"cubes", "\"x,y;x,y...\" (m): 2 for a bridge, 3 for a tower", "", "where the cubes lie"},
     {"site", "\"x,y\" (m)", "", "where to build: the ditch's edge (bridge) or the tower's place"},
     {"heading", "a number in [-360, 360] (degrees)", "0",
      "direction across the ditch, or the tower's approach"},
     {"goal", "\"x,y\" (m)", "required when task is bridge",
      "where to drive once across the bridge"},
     {"ditch_width", "a number in [0.06, 0.2] (m)", "0.07", "width of the ditch to bridge"},
     {"speed", "a number in [0.01, 0.3] (m/s)", "0.1", "driving speed"}});

}  // namespace
