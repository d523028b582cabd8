// construction: a marXbot with the magnetic manipulator finds cubes with its
// front camera, grasps them in two stages aligning with the manipulator's IR
// sensors, and either drops them side by side into a ditch to make a bridge
// it then drives over, or stacks them into a tower, or both: a bridge to
// reach remote cubes, then a tower of those (EXPERIMENTS.md E3; seed 001,
// 7.2.2-7.2.4).
//
// What the robot is given is the map the seed's SLAM and planner provided:
// its own pose (positioning sensor), which region holds the cubes (a
// rectangle), roughly where the ditch lies and where to build. Never where a
// cube is: cubes are found in the camera image (bright tops), their place and
// lie estimated by back-projecting the top's pixels onto the plane of the
// cube tops.
//
// Stacking (seed 001, 7.2.4: "an orientation using the camera", then forward
// until the manipulator's two middle IR sensors' sum passes a threshold, and
// let go): the `site` is only the map's rough place of the tower. Holding
// the next cube lowered (out of the camera's way), the robot finds the
// tower's top in the image, its bright pixels back-projected onto the plane
// of the top (as many cubes up as the tower has), the blob about a cube's
// top nearest where the tower was thought to stand; it lines up on that
// (the third cube: looked at again from 25 cm, the top 12 cm up being seen
// at a glancing angle from farther), raises the cube over the top and
// creeps on. It lets go when the front proximity ring says the tower is
// there, not the manipulator's IR sensors: those are on the head's side
// opposite the magnet, so while the magnet holds a cube in front they face
// the robot's body and read 0 (sensors/manipulator/README.md; the seed's
// robot scanned with them while holding a cube, so on its head they must
// have looked ahead there, on "another side" than the magnet's, which the
// seed does not describe further). The ring's two
// sensors flanking the front, 6 cm up, see the tower's lower cube below the
// held one; when the larger of their readings puts the tower's face half a
// cube short of the held cube's centre, the held cube is over the tower's
// middle. The camera's place (1 cm further on) is the backstop if the ring
// sees nothing.
//
// After letting a cube go on the tower, the manipulator's IR side is turned
// forwards (nothing held now) and reads the face of the cube below, then of
// the new one: not one plane, or not across the same sensors, is a cube not
// stacked straight, counted (not mended).
//
// Each bridge cube let go is checked with the robot's own sensors (the
// manipulator's IR sensors, lowest, then the camera): a cube jammed across
// the ditch's edge is gone for again with the magnet (up to twice), and a
// bridge still not whole is not crossed.
//
// params:
//   task         "bridge", "tower" or "remote" (bridge, cross, then a tower
//                of the cubes found in the other region)
//   cube_region  "x0,y0,x1,y1"  the rectangle where the cubes to use lie
//                (bridge, tower; remote: the bridge's cubes)
//   tower_region "x0,y0,x1,y1"  remote: where the tower's cubes lie
//   site         "x,y"  bridge, remote: the middle of the bridge, on the
//                ditch's centre line; tower: where the tower stands
//   tower_site   "x,y"  remote: where the tower stands
//   tower_built  0, 1 or 2: cubes the tower already has, standing about
//                the site (the map's rough place; the robot finds them with
//                its camera) (0)
//   heading      degrees: the direction across the ditch from the robot's
//                side (default 0: +x)
//   goal         "x,y"  bridge, remote: where to drive once across
//   ditch_width  m (0.07)
//   speed        m/s (0.1)
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "actuators/differential_steering/differential_steering.h"
#include "actuators/manipulator/manipulator.h"
#include "core/registry.h"
#include "sensors/camera/camera.h"
#include "sensors/ground/ground.h"
#include "sensors/manipulator/manipulator.h"
#include "sensors/positioning/positioning.h"
#include "sensors/proximity/proximity.h"

namespace {

struct Point {
  double x = 0, y = 0;
};

struct Rect {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool Contains(const Point& p) const { return p.x > x0 && p.x < x1 && p.y > y0 && p.y < y1; }
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

Rect ParseRect(const colony::Params& params, const char* key) {
  const std::string text = params.GetString(key);
  Rect r;
  char extra = 0;
  if (std::sscanf(text.c_str(), "%lf,%lf,%lf,%lf%c", &r.x0, &r.y0, &r.x1, &r.y1, &extra) != 4 ||
      !std::isfinite(r.x0) || !std::isfinite(r.y0) || !std::isfinite(r.x1) ||
      !std::isfinite(r.y1) || r.x0 >= r.x1 || r.y0 >= r.y1) {
    throw colony::ParamError(key, text,
                             std::string("parameter '") + key + "': '" + text +
                                 "' is not \"x0,y0,x1,y1\" with x0 < x1 and y0 < y1");
  }
  return r;
}

// Geometry of the marXbot with its manipulator (engines/dynamics3d README):
// the magnet face is 0.115 m ahead of the robot's axis with the magnet side
// forwards, so a held 6 cm cube's centre is 0.145 m ahead.
constexpr double kHeldAhead = 0.145;      // m
constexpr double kCubeSide = 0.06;        // m
constexpr double kGroundAhead = 0.065;    // m: the front ground sensor
constexpr double kLowElevation = 0.03;    // m: the magnet level with a cube's lower half
constexpr double kCarryElevation = 0.10;  // m
// Looking for the tower while holding a cube: the held cube low (its top
// 7 cm up), below the camera's rays to the tower's top.
constexpr double kLookElevation = 0.04;  // m
// Where the robot looks at the tower from: its axis this far back from the
// tower's centre (the second cube's top, 12 cm up, is looked at again from
// nearer).
constexpr double kFarLook = 0.35, kNearLook = 0.25;  // m
// The proximity ring's radius (the body's surface the readings are measured
// from).
constexpr double kRingRadius = 0.085;  // m
// Front proximity reading (0.01 m / d) with a cube face 3.3 cm from the ring:
// the cube's face then touches the magnet's.
constexpr double kTouching = 0.22;

// The front camera as the marxbot_front_camera preset mounts it
// (sensors/camera/README.md): level, 15.1 cm up, 8.5 cm ahead of the axis,
// tan of the half-angles 0.671 (horizontal) and 0.503 (vertical).
constexpr double kCameraHeight = 0.151, kCameraAhead = 0.085;
constexpr double kTanVertical = 0.151 / 0.30;
constexpr double kTanHorizontal = kTanVertical * 4.0 / 3.0;
// Image processing: a cube's top, lit from above, is the brightest surface
// (grey 231 for the 240 grey cube; the gray80 floor is 204, cube sides
// 108-170, the ditch 20-45).
constexpr int kBrightGrey = 218;
constexpr int kDarkGrey = 60;

// A cube seen in the image.
struct Sighting {
  Point center;      // estimated from the top's pixels
  double yaw = 0;    // its lie, modulo 90 degrees (valid when `near`)
  double range = 0;  // from the robot's axis (m)
  bool near = false;
};

// IR alignment (seed 001, 7.2.2): rotate when the two middle IR sensors
// differ by more than kTurnOn, at a speed proportional to the difference,
// until they differ by less than kTurnOff; otherwise go straight.
constexpr double kTurnOn = 0.08, kTurnOff = 0.03;
// Both middle IR sensors' sum with a cube face about 4.4 cm ahead of the head:
// far enough for the head to turn (its corners sweep 2.9 cm from its pivot).
constexpr double kIrClose = 0.45;
// Checking a bridge cube: the head lowest, its IR rays 3 cm above the floor; a reading
// above kJammedSeen (a face within about 8 cm) is a cube sticking up.
constexpr double kCheckElevation = kLowElevation;
constexpr double kJammedSeen = 0.12;
// Below this sum the face is at the edge of the sensors' range.
constexpr double kIrFaint = 0.15;
// Checking a cube put on the tower: its face and the face of the cube below
// it, seen by the manipulator's IR sensors, more than this apart is a cube
// not stacked straight.
constexpr double kStackedFace = 0.008;  // m

class Construction : public colony::Controller {
 public:
  void Init(const colony::Params& params) override {
    task_ = params.GetString("task");
    if (task_ != "bridge" && task_ != "tower" && task_ != "remote") {
      throw colony::ParamError(
          "task", task_,
          "parameter 'task': '" + task_ + "' is not accepted; accepted: bridge, tower, remote");
    }
    region_ = ParseRect(params, "cube_region");
    site_ = ParsePoint(params, "site");
    const double heading = params.GetDouble("heading", 0, -360, 360) * M_PI / 180;
    across_ = {std::cos(heading), std::sin(heading)};
    if (task_ != "tower") goal_ = ParsePoint(params, "goal");
    if (task_ == "remote") {
      tower_region_ = ParseRect(params, "tower_region");
      tower_site_ = ParsePoint(params, "tower_site");
    }
    ditch_width_ = params.GetDouble("ditch_width", 0.07, kCubeSide, 0.2);
    speed_ = params.GetDouble("speed", 0.1, 0.01, 0.3);
    building_tower_ = task_ == "tower";
    tower_built_ = static_cast<int>(params.GetInt("tower_built", 0, 0, 2));
    if (building_tower_) {
      placed_ = tower_built_;
      tower_ = site_;
    }
    position_ = &GetSensor<colony::PositioningSensor>("positioning");
    proximity_ = &GetSensor<colony::ProximitySensor>("proximity");
    ground_ = &GetSensor<colony::GroundSensor>("ground");
    arm_ = &GetSensor<colony::ManipulatorSensor>("manipulator");
    camera_ = &GetSensor<colony::CameraSensor>("camera");
    wheels_ = &GetActuator<colony::DifferentialSteering>("differential_steering");
    manipulator_ = &GetActuator<colony::ManipulatorActuator>("manipulator");
    manipulator_->SetMagnetSide();
    manipulator_->SetElevation(kCarryElevation);
  }

  // The per-robot table's values (<output trajectories_every>): grasps that
  // failed (the magnet engaged on a cube met by a corner or askew, nothing
  // held), and the IR approaches given up (no cube nearer).
  void RecordValues(colony::RobotValues& values) const override {
    values.Set("failed_grasps", failed_grasps_);
    values.Set("lost_approaches", lost_approaches_);
    values.Set("repairs", repair_count_);
    values.Set("unrepaired", unrepaired_);
    values.Set("tower_unseen", tower_unseen_);
    values.Set("tower_misplaced", tower_misplaced_);
  }

  void ControlStep() override {
    x_ = position_->x();
    y_ = position_->y();
    last_yaw_ = ticks_ > 0 ? yaw_ : position_->yaw();
    yaw_ = position_->yaw();
    ++ticks_;
    ++ticks_in_phase_;
    if (repairing_ && !arm_->holding() &&
        (phase_ == Phase::kIrApproach || phase_ == Phase::kCreep || phase_ == Phase::kGrab) &&
        ground_->readings()[0].value < 0.05f) {
      // Going for a jammed bridge cube, the front ground sensor lost the
      // floor: the ditch's edge, not the cube, is ahead.
      manipulator_->DisengageMagnet();
      manipulator_->SetMagnetSide();
      Next(Phase::kRetreatAndRetry);
    }
    switch (phase_) {
      case Phase::kSearch: {
        if (repairing_) {
          // A repair's grasp failed: look at the cube again from here.
          start_ = {x_, y_};
          Next(Phase::kCheckLook);
          break;
        }
        // Turn on the spot until the camera shows a cube in the region.
        manipulator_->SetElevation(kCarryElevation);
        if (ticks_in_phase_ == 1) {
          turned_ = 0;
          // Cubes seen before (the resource map): to the nearest.
          if (scanned_ && !seen_.empty()) {
            auto nearest = std::min_element(seen_.begin(), seen_.end(), [&](auto& a, auto& b) {
              return Distance(a) < Distance(b);
            });
            target_ = Sighting{*nearest, 0, Distance(*nearest), false};
            seen_.erase(nearest);
            Next(Phase::kToCube);
            break;
          }
        }
        turned_ += std::abs(std::remainder(yaw_ - last_yaw_, 2 * M_PI));
        if (ticks_in_phase_ < 3) {
          Stop();  // a fresh image
          break;
        }
        const auto seen = Look();
        if (!scanned_) {
          // The first look round in a region: a whole turn, remembering
          // every cube seen, then to the nearest.
          wheels_->SetLinearVelocity(-0.04, 0.04);
          if (turned_ > 2 * M_PI) {
            scanned_ = true;
            Stop();
            Next(Phase::kSearch);
          }
          break;
        }
        if (seen) {
          target_ = *seen;
          Stop();
          Next(seen->near ? Phase::kToLineup : Phase::kToCube);
          break;
        }
        wheels_->SetLinearVelocity(-0.04, 0.04);
        // A whole turn and nothing: a cube may lie in the blind zone, too
        // close to see; look from elsewhere in the region.
        if (turned_ > 2 * M_PI + 0.3) {
          Next(Phase::kWander);
          vantage_ = NextVantage();
        }
        break;
      }
      case Phase::kWander:
        if (Steer(vantage_, 0.03) || ticks_in_phase_ > 300) Next(Phase::kSearch);
        break;
      case Phase::kToCube: {
        // To 45 cm from a cube seen far or remembered, on the robot's side
        // (nearer, it would be in the camera's blind zone), facing it; then
        // look again.
        if (ticks_in_phase_ == 1) {
          const double d = std::max(1e-9, Distance(target_.center));
          vantage_ = {target_.center.x + 0.45 * (x_ - target_.center.x) / d,
                      target_.center.y + 0.45 * (y_ - target_.center.y) / d};
          reached_ = false;
        }
        if (!reached_) {
          reached_ = Steer(vantage_, 0.03) || ticks_in_phase_ > 300;
        } else if (Face(target_.center)) {
          Next(Phase::kSearch);
        }
        break;
      }
      case Phase::kToLineup: {
        // 32 cm out from the cube face nearest to the robot, on its normal:
        // the magnet holds a face it meets about parallel.
        if (ticks_in_phase_ == 1) {
          lineup_ = Lineup(target_);
        }
        if (Steer(lineup_, 0.01)) Next(Phase::kFaceCube);
        break;
      }
      case Phase::kFaceCube:
        if (Face(target_.center)) {
          if (ticks_in_phase_ < 4) break;  // let the image settle
          // Look again from here (nearer, so better); line up again if the
          // cube is not where it was thought to be.
          const auto seen = Look();
          if (seen && seen->near && Distance(seen->center) < 0.45) {
            const Point again = Lineup(*seen);
            target_ = *seen;
            if (std::hypot(again.x - x_, again.y - y_) > 0.03 && lineups_ < 3) {
              ++lineups_;
              Next(Phase::kToLineup);
              break;
            }
          }
          lineups_ = 0;
          stage_ = 1;
          StartIrApproach();
        }
        break;
      case Phase::kHeadToIr:
        Stop();
        manipulator_->DisengageMagnet();
        manipulator_->SetIrSide();
        manipulator_->SetElevation(kLowElevation);
        if (std::abs(std::remainder(arm_->rotation() - M_PI, 2 * M_PI)) < 0.03 &&
            std::abs(arm_->elevation() - kLowElevation) < 0.005) {
          Next(Phase::kIrApproach);
          start_ = {x_, y_};
          turning_ = false;
        }
        break;
      case Phase::kIrApproach: {
        // The P controller with hysteresis on the two middle IR sensors
        // (seed 001, 7.2.2), until the cube's face is about 3 cm ahead.
        const auto& ir = arm_->readings();
        const double right = ir[2].value, left = ir[3].value;
        const double difference = left - right;
        if (left + right >= kIrClose) {
          Stop();
          Next(Phase::kHeadToMagnet);
          break;
        }
        if (std::abs(difference) > kTurnOn) turning_ = true;
        if (std::abs(difference) < kTurnOff) turning_ = false;
        // Faint, at the edge of the sensors' range, the face shows to one
        // sensor at a time and turning swaps them back and forth: straight on
        // (the robot lined up facing the cube) until it shows to both.
        if (left + right < kIrFaint) turning_ = false;
        if (turning_) {
          const double turn = std::clamp(0.05 * difference, -0.02, 0.02);
          wheels_->SetLinearVelocity(-turn, turn);
        } else {
          wheels_->SetLinearVelocity(0.02, 0.02);
        }
        // Lost it: no cube where it should be (or no nearer in 40 s).
        if (std::hypot(x_ - start_.x, y_ - start_.y) > 0.3 || ticks_in_phase_ > 400) {
          ++lost_approaches_;
          manipulator_->SetMagnetSide();
          Next(Phase::kSearch);
        }
        break;
      }
      case Phase::kHeadToMagnet:
        Stop();
        manipulator_->SetMagnetSide();
        if (std::abs(std::remainder(arm_->rotation(), 2 * M_PI)) < 0.03) {
          // A jammed bridge cube may stick up less than the front proximity
          // sensors' 6 cm: close in with the magnet engaged instead.
          if (repairing_) manipulator_->EngageMagnet();
          Next(repairing_ ? Phase::kGrab : Phase::kCreep);
        }
        break;
      case Phase::kCreep:
        // Forwards until the front proximity sensors say the cube's face is
        // at the magnet's; engage the magnet.
        if (FrontProximity() >= kTouching || ticks_in_phase_ > 60) {
          Stop();
          manipulator_->EngageMagnet();
          Next(Phase::kGrab);
        } else {
          wheels_->SetLinearVelocity(0.015, 0.015);
        }
        break;
      case Phase::kGrab:
        manipulator_->EngageMagnet();
        if (arm_->holding()) {
          Stop();
          Next(stage_ == 1 ? Phase::kWiggle : Phase::kLift);
          if (stage_ == 2) {
            manipulator_->SetElevation(kCarryElevation);
            Forget(target_.center);
          }
        } else if (arm_->magnet_engaged()) {
          // Engaged but not touching: close the last millimetres.
          wheels_->SetLinearVelocity(0.01, 0.01);
          if (ticks_in_phase_ > (repairing_ ? 70 : 40)) {
            // The magnet met the cube off a face (by a corner, or askew) and
            // does not hold it.
            if (!repairing_) ++failed_grasps_;
            manipulator_->DisengageMagnet();
            Next(Phase::kRetreatAndRetry);
          }
        } else {
          Stop();
        }
        break;
      case Phase::kWiggle: {
        // Left, then right (seed 001, 7.2.2, steps 6-7): a cube held by a
        // corner turns to lie flat on the magnet.
        const double turn = 0.015;
        if (ticks_in_phase_ <= 5) {
          wheels_->SetLinearVelocity(-turn, turn);
        } else if (ticks_in_phase_ <= 15) {
          wheels_->SetLinearVelocity(turn, -turn);
        } else if (ticks_in_phase_ <= 20) {
          wheels_->SetLinearVelocity(-turn, turn);
        } else {
          Stop();
          // Let go and back off (8), then approach again aligning on the IR
          // sensors (9-10) and grasp again (11-13).
          manipulator_->DisengageMagnet();
          Next(Phase::kLetGo);
        }
        break;
      }
      case Phase::kLetGo:
        Stop();
        manipulator_->DisengageMagnet();
        if (!arm_->holding() && arm_->magnet() <= 0) {
          start_ = {x_, y_};
          Next(Phase::kBackForRegrab);
        }
        break;
      case Phase::kBackForRegrab:
        wheels_->SetLinearVelocity(-0.02, -0.02);
        if (std::hypot(x_ - start_.x, y_ - start_.y) >= 0.04) {
          stage_ = 2;
          StartIrApproach();
        }
        break;
      case Phase::kRetreatAndRetry:
        staging_back_ = kFarLook;  // a cube dropped on the way: the next looks from afar first
        manipulator_->DisengageMagnet();
        manipulator_->SetMagnetSide();
        wheels_->SetLinearVelocity(-0.05, -0.05);
        if (ticks_in_phase_ > 20) Next(Phase::kSearch);
        break;
      case Phase::kLift:
        Stop();
        if (!arm_->holding()) {
          Next(Phase::kRetreatAndRetry);  // dropped it
        } else if (std::abs(arm_->elevation() - kCarryElevation) < 0.005) {
          if (ticks_in_phase_ < 3) break;  // an image with the cube up
          MeasureHeld();
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
        if (!Face(ahead)) break;
        if (building_tower_ && placed_ > 0) {
          Next(Phase::kLookTower);
        } else {
          Next(Phase::kApproachSite);
          if (building_tower_) {
            // Over the tower's top with a centimetre to spare.
            manipulator_->SetElevation(kLowElevation +
                                       (placed_ == 0 ? 0.005 : placed_ * kCubeSide + 0.01));
          }
        }
        break;
      }
      case Phase::kLookTower: {
        // build2, build3 (seed 001, 7.2.4): find the tower with the camera.
        // The held cube lowered (carried higher it hides the tower's top from
        // here), then the tower's top back-projected onto its plane; lined up
        // again on where it stands (at most 3 times).
        Stop();
        manipulator_->SetElevation(kLookElevation);
        if (std::abs(arm_->elevation() - kLookElevation) > 0.005) {
          ticks_in_phase_ = 0;
          break;
        }
        if (ticks_in_phase_ < 3) {  // an image from here
          looked_ = {};
          looks_seen_ = 0;
          break;
        }
        // Five images: the pose's noise (0.005 rad of heading is 2 mm aside
        // at 37 cm) averaged out.
        if (const auto seen = LocateTower()) {
          looked_.x += seen->x;
          looked_.y += seen->y;
          ++looks_seen_;
        }
        if (ticks_in_phase_ < 7) break;
        std::optional<Point> top;
        if (looks_seen_ > 0) top = Point{looked_.x / looks_seen_, looked_.y / looks_seen_};
        if (!top) {
          // Not seen (hidden, or off the image): on where it was thought to be.
          ++tower_unseen_;
        } else {
          tower_ = *top;
          // Aside of the line to it: line up again. Along the line the
          // estimate matters less (the ring stops the approach).
          const Point st = Staging();
          const double aside = -(st.x - x_) * across_.y + (st.y - y_) * across_.x;
          if (std::abs(aside) > 0.006 && tower_looks_ < 3) {
            ++tower_looks_;
            Next(Phase::kToSite);
            break;
          }
          if (placed_ == 2 && staging_back_ > kNearLook) {
            // The second cube's top, 3 cm below the camera, is seen at a
            // glancing angle from 35 cm: look again from 25 cm.
            staging_back_ = kNearLook;
            Next(Phase::kToSite);
            break;
          }
        }
        tower_looks_ = 0;
        staging_back_ = kFarLook;
        manipulator_->SetElevation(kLowElevation + placed_ * kCubeSide + 0.01);
        Next(Phase::kApproachSite);
        break;
      }
      case Phase::kApproachSite:
        if (!building_tower_) {
          // Forwards until the front ground sensor loses the floor: the
          // ditch's edge is then kGroundAhead ahead of the axis (seed 001,
          // 7.2.3, scans the edge with the manipulator's IR sensors; here
          // they look level and cannot see it, the ground sensors can).
          if (ground_->readings()[0].value < 0.05f) {
            Stop();
            edge_ = {x_ + kGroundAhead * std::cos(yaw_), y_ + kGroundAhead * std::sin(yaw_)};
            Next(Phase::kAlignOverDitch);
          } else {
            DriveOnLine(0.02);
          }
        } else if (placed_ == 0) {
          // The first cube goes where the tower stands (build1).
          if (Ahead(Place()) <= held_ahead_) {
            Stop();
            manipulator_->SetElevation(kLowElevation + 0.005);
            Next(Phase::kLower);
          } else {
            DriveOnLine(0.03);
          }
        } else {
          // build2, build3: forwards over the tower until the front
          // proximity sensors see its base close.
          const double level = kLowElevation + placed_ * kCubeSide + 0.01;
          if (std::abs(arm_->elevation() - level) > 0.005) {
            Stop();
          } else if (FrontProximity() >= RingReadingAt(held_ahead_ - 0.5 * kCubeSide) ||
                     Ahead(Place()) < held_ahead_ - 0.01) {
            Stop();
            Next(Phase::kRelease);
          } else {
            DriveOnLine(0.02);
          }
        }
        break;
      case Phase::kAlignOverDitch: {
        // Back off until the held cube is over the ditch's middle.
        const double want = held_ahead_ - 0.5 * ditch_width_;  // the edge's distance ahead
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
        if (!arm_->holding() && arm_->magnet() <= 0) {
          manipulator_->SetElevation(arm_->elevation() + 0.01);  // well detached
          start_ = {x_, y_};
          if (!building_tower_) {
            Next(Phase::kCheckBack);
          } else {
            Next(placed_ > 0 ? Phase::kTowerCheckBack : Phase::kBackOff);
          }
        }
        break;
      case Phase::kTowerCheckBack:
        // A cube put on the tower: back off 3 cm, for the head to turn clear
        // of the tower.
        wheels_->SetLinearVelocity(-0.02, -0.02);
        if (std::hypot(x_ - start_.x, y_ - start_.y) >= 0.03) {
          Stop();
          below_face_.reset();
          Next(Phase::kTowerCheck);
        }
        break;
      case Phase::kTowerCheck: {
        // Does the cube sit level on the tower? The manipulator's IR side
        // turned forwards, at the height of the cube below, then of the new
        // one: stacked straight, the two faces are one plane, seen at the
        // same distance by the two middle sensors and across the same
        // sensors of the six; half on, or fallen, the new cube's face is
        // nearer or farther, 2 cm or more aside (two sensors more or fewer
        // see it), or not there.
        Stop();
        const bool below = !below_face_;
        const double level = (placed_ - (below ? 1 : 0)) * kCubeSide + 0.5 * kCubeSide;
        if (!IrSideSettledAt(level, 0.003)) break;
        const double face = IrFace();
        const auto& ir = arm_->readings();
        if (below) {
          below_face_ = face;
          for (size_t i = 0; i < ir.size() && i < below_sees_.size(); ++i) {
            below_sees_[i] = ir[i].value > 0.1;
          }
          ticks_in_phase_ = 0;
          break;
        }
        int differ = 0;
        for (size_t i = 0; i < ir.size() && i < below_sees_.size(); ++i) {
          differ += (ir[i].value > 0.1) != below_sees_[i];
        }
        if (*below_face_ > 0 &&
            (face <= 0 || std::abs(face - *below_face_) > kStackedFace || differ >= 2)) {
          ++tower_misplaced_;
        }
        manipulator_->SetMagnetSide();
        manipulator_->SetElevation(kCarryElevation);
        Next(Phase::kBackOff);
        break;
      }
      case Phase::kCheckBack:
        // A bridge cube let go: back off 4 cm, clear of it, to check it.
        wheels_->SetLinearVelocity(-0.02, -0.02);
        if (std::hypot(x_ - start_.x, y_ - start_.y) >= 0.04) {
          Stop();
          Next(Phase::kCheckLook);
        }
        break;
      case Phase::kCheckLook: {
        // Does it lie flat in the ditch? Its top is then at the floor's level
        // and the manipulator's IR sensors, turned forwards and lowered to
        // 3 cm, see nothing ahead; a cube jammed across the ditch's edge, or
        // on its side, sticks up through their rays.
        Stop();
        if (!IrSideSettledAt(kCheckElevation, 0.005)) break;
        const auto& ir = arm_->readings();
        double seen = 0;
        for (const auto& r : ir) seen = std::max(seen, static_cast<double>(r.value));
        const bool jammed = seen > kJammedSeen;
        if (jammed && repairs_ < 2) {
          // Grasp it again where it is (the magnet meets its face towards
          // the robot), lift it and drop it again.
          ++repairs_;
          ++repair_count_;
          repairing_ = true;
          target_ = Sighting{Place(), 0, Distance(Place()), false};
          stage_ = 2;
          StartIrApproach();
          break;
        }
        manipulator_->SetMagnetSide();
        manipulator_->SetElevation(kCarryElevation);
        repairing_ = false;
        repairs_ = 0;
        if (jammed) {
          // Still jammed: the bridge is not whole; the robot does not cross it.
          ++unrepaired_;
          Next(Phase::kDone);
          break;
        }
        Next(Phase::kBackOff);
        break;
      }
      case Phase::kBackOff: {
        // Back off; after a bridge cube, far enough for the camera to see
        // where it lies in the ditch (the second goes beside the first) and
        // whether it lies flat there.
        const bool look = !building_tower_;
        const int back = look ? 22 : 10;
        if (ticks_in_phase_ <= back) {
          wheels_->SetLinearVelocity(-speed_, -speed_);
          break;
        }
        Stop();
        if (look && ticks_in_phase_ < back + 3) break;  // an image from here
        if (look && !FlatInDitch()) {
          // Not flat (on its side, or across an edge, and the IR check
          // above missed it or could not mend it): the bridge is not whole,
          // and the robot does not cross it.
          ++unrepaired_;
          Next(Phase::kDone);
          break;
        }
        if (look && placed_ == 0) LocateFirstBridgeCube();
        {
          manipulator_->SetElevation(kCarryElevation);
          ++placed_;
          if (building_tower_) {
            Next(placed_ < 3 ? Phase::kSearch : Phase::kDone);
          } else {
            Next(placed_ < 2 ? Phase::kSearch : Phase::kToBridge);
          }
        }
        break;
      }
      case Phase::kToBridge: {
        // Straight over the middle of the two cubes (where they are, not
        // where they were meant to be), then to the goal.
        const Point mid = BridgeMiddle();
        if (Steer({mid.x - 0.35 * across_.x, mid.y - 0.35 * across_.y}, 0.01)) {
          Next(Phase::kFaceGoal);
        }
        break;
      }
      case Phase::kFaceGoal: {
        const Point mid = BridgeMiddle();
        if (Face({mid.x + 0.35 * across_.x, mid.y + 0.35 * across_.y})) {
          reached_ = false;
          Next(Phase::kCross);
        }
        break;
      }
      case Phase::kCross: {
        const Point mid = BridgeMiddle(), over{mid.x + 0.2 * across_.x, mid.y + 0.2 * across_.y};
        if (!reached_) {
          reached_ = Steer(over, 0.02);
          break;
        }
        if (Steer(goal_, 0.02)) {
          if (task_ == "remote" && !building_tower_) {
            // Across: now the tower, with the cubes of the other region.
            building_tower_ = true;
            placed_ = 0;
            region_ = tower_region_;
            scanned_ = false;
            seen_.clear();
            site_ = tower_site_;
            tower_ = tower_site_;
            placed_ = tower_built_;
            Next(Phase::kSearch);
          } else {
            Next(Phase::kDone);
          }
        }
        break;
      }
      case Phase::kDone:
        Stop();
        break;
    }
  }

 private:
  enum class Phase {
    kSearch,
    kWander,
    kToCube,
    kToLineup,
    kFaceCube,
    kHeadToIr,
    kIrApproach,
    kHeadToMagnet,
    kCreep,
    kGrab,
    kWiggle,
    kLetGo,
    kBackForRegrab,
    kRetreatAndRetry,
    kLift,
    kBackOffHolding,
    kToSite,
    kFaceSite,
    kLookTower,
    kTowerCheckBack,
    kTowerCheck,
    kApproachSite,
    kAlignOverDitch,
    kLower,
    kRelease,
    kCheckBack,
    kCheckLook,
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
  void StartIrApproach() { Next(Phase::kHeadToIr); }

  // The next place to look from: the centre and the quarter points of the
  // region in turn, skipping those within 25 cm of the robot.
  Point NextVantage() {
    const Rect& r = Region();
    const double qx = 0.25 * (r.x1 - r.x0), qy = 0.25 * (r.y1 - r.y0);
    const Point points[5] = {{r.x0 + qx, r.y0 + qy},
                             {r.x0 + qx, r.y1 - qy},
                             {r.x1 - qx, r.y1 - qy},
                             {r.x1 - qx, r.y0 + qy},
                             Center(r)};
    for (int k = 0; k < 5; ++k) {
      const Point p = points[vantage_index_++ % 5];
      if (Distance(p) > 0.25) return p;
    }
    return Center(r);
  }

  const Rect& Region() const { return region_; }
  static Point Center(const Rect& r) { return {0.5 * (r.x0 + r.x1), 0.5 * (r.y0 + r.y1)}; }

  // The nearest cube the image shows standing in the region (and not in the
  // tower being built), if any.
  //
  // Bright pixels in the lower half of the image (below the horizon) are
  // grouped into blobs; each blob's pixels are back-projected onto the plane
  // of the cube tops (6 cm up). A blob is a standing cube's top when it lies
  // in the region and, near enough to judge (within 70 cm), the smallest
  // rectangle around its back-projected pixels is about a cube's top. A cube
  // sunk flush in the ditch (its top at the floor's level) back-projects
  // nearer and smaller, and lies in the dark band; a top higher up (a tower)
  // back-projects farther and larger.
  std::optional<Sighting> Look() {
    std::optional<Sighting> best;
    ForEachBlob([&](const std::vector<std::pair<int, int>>& blob, int w, int h, auto grey) {
      if (blob.size() < 3) return;
      const auto seen = Judge(blob, w, h, grey);
      if (seen) Remember(seen->center);
      if (seen && (!best || seen->range < best->range)) best = seen;
    });
    return best;
  }

  // Calls f(blob, w, h, grey) for each blob of bright pixels below the
  // horizon (4-connected), bottom rows first.
  template <class F>
  void ForEachBlob(F f) const {
    const int w = camera_->width(), h = camera_->height();
    if (w < 8 || h < 8) return;
    const int top_row = h / 2;
    std::vector<int> label(static_cast<size_t>(w) * h, -1);
    auto grey = [&](int u, int v) {
      const colony::Color c = camera_->At(u, v);
      return (c.r + c.g + c.b) / 3;
    };
    std::vector<std::pair<int, int>> stack, blob;
    int blobs = 0;
    for (int v = h - 1; v >= top_row; --v) {
      for (int u = 0; u < w; ++u) {
        const size_t at = static_cast<size_t>(v) * w + u;
        if (label[at] >= 0 || grey(u, v) < kBrightGrey) continue;
        // Flood the blob.
        blob.clear();
        stack.assign(1, {u, v});
        label[at] = blobs;
        while (!stack.empty()) {
          const auto [pu, pv] = stack.back();
          stack.pop_back();
          blob.push_back({pu, pv});
          const int du[4] = {1, -1, 0, 0}, dv[4] = {0, 0, 1, -1};
          for (int k = 0; k < 4; ++k) {
            const int nu = pu + du[k], nv = pv + dv[k];
            if (nu < 0 || nu >= w || nv < top_row || nv >= h) continue;
            const size_t n = static_cast<size_t>(nv) * w + nu;
            if (label[n] >= 0 || grey(nu, nv) < kBrightGrey) continue;
            label[n] = blobs;
            stack.push_back({nu, nv});
          }
        }
        ++blobs;
        f(blob, w, h, grey);
      }
    }
  }

  template <typename Grey>
  std::optional<Sighting> Judge(const std::vector<std::pair<int, int>>& blob, int w, int h,
                                Grey grey) const {
    // Touching the bottom of the image (the cube held, or one too close to see
    // whole) or its sides: not judged.
    int lowest = 0, lowest_u = 0;
    std::vector<Point> points;
    for (const auto& [u, v] : blob) {
      if (u == 0 || u == w - 1) return std::nullopt;  // cut by the image's side
      if (v > lowest) {
        lowest = v;
        lowest_u = u;
      }
      // The pixel's corners: the rectangle around them covers the top.
      for (const double du : {0.0, 1.0}) {
        for (const double dv : {0.0, 1.0}) {
          const auto p = BackProject(u + du, v + dv, kCubeSide, w, h);
          if (!p) return std::nullopt;
          points.push_back(*p);
        }
      }
    }
    if (lowest + 2 >= h) return std::nullopt;
    // Below a standing cube's top: its side, shaded (grey 108-183 for the
    // light cube); below a cube sunk in the ditch, the dark ditch or the
    // floor (204).
    const int below = grey(lowest_u, lowest + 2);
    if (below < 80 || below > 195) return std::nullopt;
    Point mean;
    for (const Point& p : points) {
      mean.x += p.x / points.size();
      mean.y += p.y / points.size();
    }
    Sighting s;
    s.range = Distance(mean);
    s.center = mean;
    s.near = s.range < 0.7;
    if (s.near) {
      const Rectangle r = Fit(points);
      // The pixels' corners lie a little outside the top's edges.
      if (std::max(r.a, r.b) > 0.1 || std::min(r.a, r.b) < 0.04) return std::nullopt;
      s.yaw = r.yaw;
      s.center = r.mid;
    }
    if (!Region().Contains(s.center)) return std::nullopt;
    if (building_tower_ && placed_ > 0) {
      // The tower itself (where it was last seen): its top, higher than a
      // cube's, back-projects beyond it on the same line of sight.
      if (Distance(s.center, tower_) < 0.15) return std::nullopt;
      const double to_site = Distance(tower_);
      const double apart = std::abs(std::remainder(
          std::atan2(s.center.y - y_, s.center.x - x_) - std::atan2(tower_.y - y_, tower_.x - x_),
          2 * M_PI));
      if (s.range > to_site - 0.05 && apart < std::atan2(0.08, to_site) + 0.05) return std::nullopt;
    }
    return s;
  }

  // The smallest rectangle around `points` (1 degree steps over 90): its
  // middle, the direction of its first side, and its sides.
  struct Rectangle {
    Point mid;
    double yaw = 0, a = 0, b = 0;
  };
  static Rectangle Fit(const std::vector<Point>& points) {
    Rectangle best;
    double best_area = 1e9;
    for (int k = 0; k < 90; ++k) {
      const double a = k * M_PI / 180, c = std::cos(a), sn = std::sin(a);
      double lo1 = 1e9, hi1 = -1e9, lo2 = 1e9, hi2 = -1e9;
      for (const Point& p : points) {
        const double q1 = c * p.x + sn * p.y, q2 = -sn * p.x + c * p.y;
        lo1 = std::min(lo1, q1);
        hi1 = std::max(hi1, q1);
        lo2 = std::min(lo2, q2);
        hi2 = std::max(hi2, q2);
      }
      const double area = (hi1 - lo1) * (hi2 - lo2);
      if (area < best_area) {
        best_area = area;
        const double m1 = 0.5 * (lo1 + hi1), m2 = 0.5 * (lo2 + hi2);
        best = {{c * m1 - sn * m2, sn * m1 + c * m2}, a, hi1 - lo1, hi2 - lo2};
      }
    }
    return best;
  }

  // Where the tower stands, from its top in the image (seed 001, 7.2.4:
  // "an orientation using the camera"): the blobs of bright pixels, each
  // back-projected onto the plane of the tower's top (`placed_` cubes up);
  // the tower's top is the one whose smallest rectangle there is about a
  // cube's top, nearest to where the tower is thought to stand (the map's
  // site, or where it was seen last) and within 20 cm of it. A lower cube's
  // top back-projects onto that plane smaller and nearer (and one as high,
  // for the second cube, farther from the map's site); the held cube, low,
  // is out of the image. Nothing if no blob fits.
  std::optional<Point> LocateTower() const {
    const double z = placed_ * kCubeSide;
    std::optional<Point> best;
    double best_off = 0.2;
    ForEachBlob([&](const std::vector<std::pair<int, int>>& blob, int w, int h, auto) {
      if (blob.size() < 3) return;
      std::vector<Point> points;
      for (const auto& [u, v] : blob) {
        if (u == 0 || u == w - 1 || v + 1 >= h) return;  // cut by the image's edge
        for (const double du : {0.0, 1.0}) {
          for (const double dv : {0.0, 1.0}) {
            const auto p = BackProject(u + du, v + dv, z, w, h);
            if (!p) return;
            points.push_back(*p);
          }
        }
      }
      const Rectangle r = Fit(points);
      if (std::max(r.a, r.b) > 0.1 || std::min(r.a, r.b) < 0.04) return;
      const double off = Distance(r.mid, tower_);
      if (off < best_off) {
        best_off = off;
        best = r.mid;
      }
    });
    return best;
  }

  // Turns the manipulator's IR side forwards at `level` (within
  // `tolerance`): true once it is there and its readings have had three
  // ticks to settle; the phase's tick count restarts while it moves.
  bool IrSideSettledAt(double level, double tolerance) {
    manipulator_->SetIrSide();
    manipulator_->SetElevation(level);
    if (std::abs(std::remainder(arm_->rotation() - M_PI, 2 * M_PI)) > 0.03 ||
        std::abs(arm_->elevation() - level) > tolerance) {
      ticks_in_phase_ = 0;
      return false;
    }
    return ticks_in_phase_ >= 3;
  }

  // The resource map: where cubes were seen, one entry per cube.
  void Remember(const Point& p) {
    for (Point& q : seen_) {
      if (Distance(p, q) < 0.08) {
        q = p;
        return;
      }
    }
    seen_.push_back(p);
  }
  void Forget(const Point& p) {
    seen_.erase(std::remove_if(seen_.begin(), seen_.end(),
                               [&](const Point& q) { return Distance(p, q) < 0.1; }),
                seen_.end());
  }

  // Where the held cube's centre is: how far ahead of the axis and how far
  // to the left of it (the magnet holds a cube up to 1 cm off its face, and
  // off its middle), from where its top shows at the bottom of the image:
  // the far edge's row, and the middle of the bright run in the row that
  // sees the top's middle.
  // Unknown (it does not show): kHeldAhead + 0.005 and 0.
  void MeasureHeld() {
    held_ahead_ = kHeldAhead + 0.005;
    held_left_ = 0;
    const int w = camera_->width(), h = camera_->height();
    const double top = arm_->elevation() + 0.5 * kCubeSide;
    auto bright = [&](int u, int v) {
      const colony::Color c = camera_->At(u, v);
      return (c.r + c.g + c.b) / 3 >= kBrightGrey;
    };
    if (h < 8 || !bright(w / 2, h - 1) || top >= kCameraHeight) return;
    int v = h - 1;
    while (v > h / 2 && bright(w / 2, v - 1)) --v;
    const double down = (v - h / 2.0) / (h / 2.0) * kTanVertical;  // the edge: v's upper side
    if (down <= 1e-6) return;
    const double ahead = kCameraAhead + (kCameraHeight - top) / down - 0.5 * kCubeSide;
    held_ahead_ = std::clamp(ahead, kHeldAhead - 0.005, kHeldAhead + 0.02);
    // The bright run through the middle of the image in the row that sees
    // the top's middle (at the bottom row the top is wider than the image),
    // seen at the distance where that row meets the plane of the top.
    const double middle_ahead = held_ahead_ - kCameraAhead;
    const int row = std::clamp(
        static_cast<int>(h / 2.0 + (kCameraHeight - top) / middle_ahead / kTanVertical * h / 2.0),
        h / 2 + 1, h - 1);
    if (!bright(w / 2, row)) return;
    int lo = w / 2, hi = w / 2;
    while (lo > 0 && bright(lo - 1, row)) --lo;
    while (hi + 1 < w && bright(hi + 1, row)) ++hi;
    if (lo == 0 || hi == w - 1) return;
    const double middle = 0.5 * (lo + hi + 1);
    const double t = (kCameraHeight - top) / ((row + 0.5 - h / 2.0) / (h / 2.0) * kTanVertical);
    held_left_ = std::clamp(-(middle - w / 2.0) / (w / 2.0) * kTanHorizontal * t, -0.02, 0.02);
  }

  // Where the ray through image point (u, v) meets the plane `z` up (world
  // frame), or nothing above the horizon.
  std::optional<Point> BackProject(double u, double v, double z, int w, int h) const {
    const double down = (v - h / 2.0) / (h / 2.0) * kTanVertical;
    if (down <= 1e-6) return std::nullopt;
    const double left = -(u - w / 2.0) / (w / 2.0) * kTanHorizontal;
    const double t = (kCameraHeight - z) / down;
    const double fx = kCameraAhead + t, fy = t * left;
    const double c = std::cos(yaw_), s = std::sin(yaw_);
    return Point{x_ + c * fx - s * fy, y_ + s * fx + c * fy};
  }

  // 32 cm out from the cube's face nearest to the robot.
  Point Lineup(const Sighting& s) const {
    double best = -2, normal = 0;
    for (int k = 0; k < 4; ++k) {
      const double a = s.yaw + k * M_PI / 2;
      const double toward = (std::cos(a) * (x_ - s.center.x) + std::sin(a) * (y_ - s.center.y)) /
                            std::max(1e-9, Distance(s.center));
      if (toward > best) {
        best = toward;
        normal = a;
      }
    }
    return {s.center.x + 0.32 * std::cos(normal), s.center.y + 0.32 * std::sin(normal)};
  }

  // Where the current cube goes: bridge cubes side by side along the ditch.
  Point Place() const {
    if (building_tower_) return tower_;
    const double along =
        placed_ == 0 ? -0.5 * (kCubeSide + 0.012) : first_along_ + kCubeSide + 0.012;
    return {site_.x - along * across_.y, site_.y + along * across_.x};
  }

  // The middle of the bridge: between the first cube and the second beside it.
  Point BridgeMiddle() const {
    const double along = first_along_ + 0.5 * (kCubeSide + 0.012);
    return {site_.x - along * across_.y, site_.y + along * across_.x};
  }

  // Where the first cube of the bridge lies along the ditch (from the site,
  // along the ditch's direction), from its top in the dark band: the bright
  // pixels whose rays meet the floor's plane within 4 cm of the ditch's
  // centre line. Unchanged (where it was put) if it does not show.
  // Calls f(off, along) for each bright pixel below the horizon, its place
  // back-projected onto the floor's plane, across and along the ditch from
  // the site.
  template <class F>
  void ForEachBrightFloorPoint(F f) const {
    const int w = camera_->width(), h = camera_->height();
    for (int v = h / 2 + 1; v < h; ++v) {
      for (int u = 0; u < w; ++u) {
        const colony::Color c = camera_->At(u, v);
        if ((c.r + c.g + c.b) / 3 < kBrightGrey) continue;
        const auto p = BackProject(u + 0.5, v + 0.5, 0, w, h);
        if (!p) continue;
        f((p->x - site_.x) * across_.x + (p->y - site_.y) * across_.y,
          -(p->x - site_.x) * across_.y + (p->y - site_.y) * across_.x);
      }
    }
  }
  void LocateFirstBridgeCube() {
    double sum = 0;
    int n = 0;
    ForEachBrightFloorPoint([&](double off, double along) {
      if (std::abs(off) > 0.04) return;
      sum += along;
      ++n;
    });
    if (n >= 10) first_along_ = std::clamp(sum / n, -0.08, 0.02);
  }
  // Whether the cube just put at Place() lies flat in the ditch, from the
  // image: the bright pixels about its place along the ditch, back-projected
  // onto the floor's plane, fall in the ditch's band for a top at the
  // floor's level; a top raised (a cube on its side, or across an edge)
  // back-projects beyond the ditch. Flat unless more fall beyond than in it.
  bool FlatInDitch() const {
    const Point place = Place();
    const double place_along = -(place.x - site_.x) * across_.y + (place.y - site_.y) * across_.x;
    int in = 0, beyond = 0;
    ForEachBrightFloorPoint([&](double off, double along) {
      if (std::abs(along - place_along) > 0.05) return;
      if (std::abs(off) <= 0.04) {
        ++in;
      } else if (off > 0.04 && off < 0.2) {
        ++beyond;
      }
    });
    return beyond <= in;
  }

  // The line the robot's axis follows to put the held cube on the bridge's
  // place: shifted by how far off the middle the magnet holds it.
  Point RobotLine() const {
    const Point p = Place();
    return {p.x + held_left_ * across_.y, p.y - held_left_ * across_.x};
  }
  // How far `p` lies ahead of the robot's axis along the approach direction.
  double Ahead(const Point& p) const { return (p.x - x_) * across_.x + (p.y - y_) * across_.y; }
  // Forwards along the robot's line to the place, at `speed`.
  void DriveOnLine(double speed) {
    const Point p = RobotLine();
    Drive({p.x + 0.3 * across_.x, p.y + 0.3 * across_.y}, speed);
  }
  // Where the robot lines up before the final approach to the site: back
  // from the place against the approach direction.
  Point Staging() const {
    const Point line = RobotLine();
    const double back = building_tower_ ? staging_back_ : 0.30;
    return {line.x - back * across_.x, line.y - back * across_.y};
  }

  double Distance(const Point& p) const { return std::hypot(p.x - x_, p.y - y_); }
  static double Distance(const Point& a, const Point& b) {
    return std::hypot(a.x - b.x, a.y - b.y);
  }
  double Bearing(const Point& p) const {
    return std::remainder(std::atan2(p.y - y_, p.x - x_) - yaw_, 2 * M_PI);
  }
  // The front proximity sensors' reading (the pair either side of the
  // front, 7.5 degrees off it, kRingRadius from the axis) with a face
  // `ahead` of the robot's axis, square to it.
  static double RingReadingAt(double ahead) {
    return 0.01 / std::max(0.002, (ahead - kRingRadius) / std::cos(7.5 * M_PI / 180));
  }
  // How far ahead of the manipulator's IR face a face square to it is, from
  // the two middle IR sensors (both must see it; rays 7.5 degrees off the
  // face's normal), or 0 when either sees nothing.
  double IrFace() const {
    const auto& ir = arm_->readings();
    const double right = ir[2].value, left = ir[3].value;
    if (right < 0.05 || left < 0.05) return 0;
    return 0.5 * (0.01 / right + 0.01 / left) * std::cos(7.5 * M_PI / 180);
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
  Rect region_, tower_region_;
  Point site_, tower_site_, tower_, goal_, across_{1, 0}, edge_, lineup_, start_;
  Sighting target_;
  std::vector<Point> seen_;
  double ditch_width_ = 0.07, speed_ = 0.1, held_ahead_ = kHeldAhead, held_left_ = 0;
  double x_ = 0, y_ = 0, yaw_ = 0;
  bool building_tower_ = false, turning_ = false, scanned_ = false, reached_ = false;
  int failed_grasps_ = 0, lost_approaches_ = 0, repairs_ = 0, repair_count_ = 0, unrepaired_ = 0;
  bool repairing_ = false;
  int tower_built_ = 0, tower_looks_ = 0, tower_unseen_ = 0;
  double staging_back_ = kFarLook;
  Point looked_;
  std::optional<double> below_face_;
  std::array<bool, 6> below_sees_{};
  int tower_misplaced_ = 0;
  int looks_seen_ = 0;
  int placed_ = 0, stage_ = 1, lineups_ = 0, vantage_index_ = 0, ticks_ = 0;
  double turned_ = 0, last_yaw_ = 0, first_along_ = -0.5 * (kCubeSide + 0.012);
  Point vantage_;
  Phase phase_ = Phase::kSearch;
  int ticks_in_phase_ = 0;
  const colony::PositioningSensor* position_ = nullptr;
  const colony::ProximitySensor* proximity_ = nullptr;
  const colony::GroundSensor* ground_ = nullptr;
  const colony::ManipulatorSensor* arm_ = nullptr;
  const colony::CameraSensor* camera_ = nullptr;
  colony::DifferentialSteering* wheels_ = nullptr;
  colony::ManipulatorActuator* manipulator_ = nullptr;
};

COLONY_REGISTER_CONTROLLER(
    Construction, "construction",
    "find cubes with the front camera, grasp them with the magnetic manipulator aligning on its "
    "IR sensors, and build a bridge over a ditch (then cross it), a tower, or both (remote cubes)",
    {{"task", "bridge, tower, remote", "", "what to build"},
     {"cube_region", "\"x0,y0,x1,y1\" (m)", "", "the rectangle of the map where the cubes lie"},
     {"tower_region", "\"x0,y0,x1,y1\" (m)", "required when task is remote",
      "where the tower's cubes lie"},
     {"site", "\"x,y\" (m)", "",
      "where to build: the bridge's middle on the ditch's centre line, or the tower's place"},
     {"tower_site", "\"x,y\" (m)", "required when task is remote", "where the tower stands"},
     {"tower_built", "0, 1 or 2", "0",
      "how many cubes the tower already has (standing about the site; the robot finds them)"},
     {"heading", "a number in [-360, 360] (degrees)", "0", "direction across the ditch"},
     {"goal", "\"x,y\" (m)", "required when task is bridge or remote",
      "where to drive once across the bridge"},
     {"ditch_width", "a number in [0.06, 0.2] (m)", "0.07", "width of the ditch to bridge"},
     {"speed", "a number in [0.01, 0.3] (m/s)", "0.1", "driving speed"}});

}  // namespace
