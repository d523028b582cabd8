// The marXbot in dynamics3d (engines/dynamics3d): one rigid body (the round
// body, a low central belly, the battery, and two treels of two wheels
// each) whose treads move at the treels' commanded speeds (parts.h), up to
// the motors' torque; with manipulator="true" a head on a piston joint in
// front of the body (slides up and down, turns about its vertical axis),
// both motions motor-driven at the ManipulatorState's speeds, carrying a
// magnet on its outer face; and the gripper on its docking ring, which
// fixes what it closes on (another robot's ring, an object) to the chassis.
// engines/dynamics3d/README.md gives the figures and their reasons.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string_view>
#include <vector>

#include "actuators/gripper/gripper_state.h"
#include "actuators/manipulator/manipulator_state.h"
#include "core/log.h"
#include "core/space.h"
#include "core/text.h"
#include "engines/dynamics3d/dynamics3d.h"
#include "engines/dynamics3d/parts.h"
#include "entities/marxbot/marxbot.h"

namespace colony {
namespace {

using namespace dynamics3d;

// Robot frame: x forward, y left, z up, origin at the centre of the base on
// the floor. Figures not in the sources are choices, explained in the
// engine's README.md (they were tuned so that the robot falls into a ditch
// one cube wide and deep, and crosses it over two cubes).
struct MarxbotGeometry {
  double treel_wheel_radius = 0.025;  // m, the spheres the treels touch the ground with
  double treel_y = 0.06;              // m, treel contact lines at y = +-0.06
  double treel_half_span = 0.03;      // m, wheels at x = +-0.03
  double belly_half_length = 0.03;    // m, the central belly (battery) box: 6 cm long,
  double belly_half_width = 0.04;     // 8 cm wide,
  double belly_bottom = 0.006;        // 6 mm above the floor,
  double belly_top = 0.04;            // up to 4 cm
  double body_bottom = 0.05;          // m, bottom of the round body
  double com_height = 0.05;           // m, centre of mass (battery low in the base)
  double com_height_manipulator = 0.07;
};
constexpr MarxbotGeometry kMarxbot3d;
using marxbot::kHeadPivotX;
constexpr double kHeadMaxForce = 50.0;  // N, elevation motor
constexpr double kHeadMaxTorque = 2.0;  // N m, rotation motor
// Sideways yield of a treel's tread: sliding speed per newton (m/s / N).
constexpr double kTreelSideSlip = 0.005;
// Part tags of the treels' wheels.
constexpr uint8_t kLeftTreel = 0, kRightTreel = 1;

class MarxbotDynamics3dModel : public Dynamics3dModel {
 public:
  void Add(Engine& engine, uint32_t s) override {
    using namespace marxbot;
    const MarxbotGeometry& geo = kMarxbot3d;
    Space& space = engine.entities();
    const DriveState* drive = space.drive(s);
    if (!drive) {  // no treels: a solid of its mass
      engine.AddSolid(s, kObject);
      return;
    }
    const Geometry& g = space.geometry(s);
    const ManipulatorState* manip = space.Get<ManipulatorState>(s);
    const Pose& pose = space.pose(s);
    const Twist& twist = space.twist(s);
    const double total = space.mass(s) > 0 ? space.mass(s) : kMass;
    const double com = manip ? geo.com_height_manipulator : geo.com_height;
    const double height = g.height();
    const double radius = g.radius;

    if (robots_.size() <= s) robots_.resize(s + 1);
    robots_[s] = std::make_unique<Robot>();
    Robot* r = robots_[s].get();
    r->wheel_base = drive->wheel_base > 0 ? drive->wheel_base : kWheelBase;
    const double wheel_radius = drive->wheel_radius > 0 ? drive->wheel_radius : kWheelRadius;
    r->pull_limit = engine.params().treel_max_torque / wheel_radius /
                    (0.5 * total * std::max(engine.params().gravity.norm(), 1e-9));
    slots_.insert(std::lower_bound(slots_.begin(), slots_.end(), s), s);

    // Chassis: the round body, the belly and the treels' wheels, one body.
    const double chassis_mass = total - (manip ? kHeadMass : 0.0);
    dBodyID chassis = engine.MakeBody(s, com);
    dMass m;
    dMassSetCylinderTotal(&m, chassis_mass, 3, radius, height);
    dBodySetMass(chassis, &m);
    dSpaceID parts = engine.MakePartSpace(s);
    dGeomID body =
        engine.AddGeom(s, dCreateCylinder(parts, radius, height - geo.body_bottom), kBody);
    dGeomSetBody(body, chassis);
    dGeomSetOffsetPosition(body, 0, 0, 0.5 * (height + geo.body_bottom) - com);
    dGeomID belly =
        engine.AddGeom(s,
                       dCreateBox(parts, 2 * geo.belly_half_length, 2 * geo.belly_half_width,
                                  geo.belly_top - geo.belly_bottom),
                       kBody);
    dGeomSetBody(belly, chassis);
    dGeomSetOffsetPosition(belly, 0, 0, 0.5 * (geo.belly_top + geo.belly_bottom) - com);
    // Treels: two wheels each (front and rear), whose tread moves at the
    // treel's speed.
    for (int k = 0; k < 4; ++k) {
      const int side = k / 2;  // 0 left (+y), 1 right (-y)
      dGeomID w = engine.AddGeom(s, dCreateSphere(parts, geo.treel_wheel_radius), kTread,
                                 side == 0 ? kLeftTreel : kRightTreel);
      dGeomSetBody(w, chassis);
      dGeomSetOffsetPosition(w, k % 2 == 0 ? geo.treel_half_span : -geo.treel_half_span,
                             side == 0 ? geo.treel_y : -geo.treel_y, geo.treel_wheel_radius - com);
    }
    if (!manip) return;
    const Quat& q = pose.orientation;
    // The manipulator: the head on a vertical piston joint through its centre
    // (slides up and down, turns about it), both motions motor-driven.
    const Vec3 up = q * Vec3::UnitZ();
    r->elevation0 = std::clamp(manip->elevation, manip->min_elevation, manip->max_elevation);
    r->rotation0 = manip->rotation;
    const Vec3 arm = q * Vec3(kHeadPivotX, 0, r->elevation0);
    const Vec3 centre = pose.position + arm;
    r->head = dBodyCreate(engine.world());
    engine.AddPartBody(s, r->head);
    PlaceBody(r->head, centre, q * FromYaw(r->rotation0));
    SetBodyVelocity(r->head, twist.linear + twist.angular.cross(arm), twist.angular);
    dMass hm;
    // Inertia of a 10 cm cube of the head's mass: ODE's iterative solver
    // copes badly with a tiny body jointed to a large one.
    dMassSetBoxTotal(&hm, kHeadMass, 0.1, 0.1, 0.1);
    dBodySetMass(r->head, &hm);
    dGeomID head = engine.AddGeom(s, dCreateBox(parts, kHeadDepth, kHeadWidth, kHeadHeight), kBody);
    dGeomSetBody(head, r->head);
    r->piston = dJointCreatePiston(engine.world(), nullptr);
    dJointAttach(r->piston, r->head, chassis);
    dJointSetPistonAnchor(r->piston, centre.x(), centre.y(), centre.z());
    dJointSetPistonAxis(r->piston, up.x(), up.y(), up.z());
    dJointSetPistonParam(r->piston, dParamFMax, kHeadMaxForce);
    dJointSetPistonParam(r->piston, dParamFMax2, kHeadMaxTorque);
  }

  void Remove(Engine& engine, uint32_t s) override {
    if (s >= robots_.size() || !robots_[s]) return;
    Robot& r = *robots_[s];
    r.magnet.Release(engine);
    Ungrip(engine, s, r);
    if (r.head) {
      dJointDestroy(r.piston);
      dBodyDestroy(r.head);
    }
    robots_[s].reset();
    slots_.erase(std::lower_bound(slots_.begin(), slots_.end(), s));
  }

  void Release(Engine& engine, uint32_t holder, uint32_t held) override {
    Robot& r = *robots_[holder];
    if (r.magnet.held() == held) r.magnet.Release(engine);
    if (r.gripped == held) Ungrip(engine, holder, r);
  }

  void BeforeStep(Engine& engine, double dt) override {
    Space& space = engine.entities();
    for (uint32_t s : slots_) {
      Robot& r = *robots_[s];
      SetTreads(space, s, r);
      if (r.head) {
        UpdateMagnet(engine, space, s, r, dt);
        RefuseTilt(space, s, r);
      }
      if (GripperState* g = space.Get<GripperState>(s)) UpdateGrip(engine, s, r, *g);
    }
  }

  void BeforeSubstep(Engine& engine, double h) override {
    const Space& space = engine.entities();
    for (uint32_t s : slots_) {
      Robot& r = *robots_[s];
      if (r.head) DriveHead(space, s, r, h);
    }
  }

  void AfterSubstep(Engine& engine) override {
    for (uint32_t s : slots_) robots_[s]->magnet.BreakIfOverloaded(engine);
  }

  void AfterStep(Engine& engine, double dt) override {
    Space& space = engine.entities();
    for (uint32_t s : slots_) {
      const Robot& r = *robots_[s];
      // The motors hold the treads at their speed (slip happens between
      // tread and ground), so the encoders count the commanded wheel speeds.
      DriveState& d = *space.drive(s);
      d.travelled_left = (std::isfinite(d.left) ? d.left : 0.0) * dt;
      d.travelled_right = (std::isfinite(d.right) ? d.right : 0.0) * dt;
      if (GripperState* g = space.Get<GripperState>(s)) g->held = r.gripped;
      if (!r.head) continue;
      ManipulatorState& m = *space.Get<ManipulatorState>(s);
      m.elevation = Elevation(r);
      m.rotation = Rotation(r);
      m.held = r.magnet.held();
    }
  }

  bool Anchor(const Space&, uint32_t s, std::string_view name, Pose& pose) const override {
    if (name != ManipulatorState::kHeadAnchor || s >= robots_.size() || !robots_[s] ||
        !robots_[s]->head)
      return false;
    pose.position = BodyPos(robots_[s]->head);
    pose.orientation = BodyQuat(robots_[s]->head);
    return true;
  }

  // A treel's wheel touches something: its tread drives the robot. The
  // motor's torque bounds the pull along the tread: with the treel's share
  // of the robot's weight, F <= min(mu N, torque / wheel radius).
  void ModifyContacts(Engine& engine, dGeomID wheel, bool wheel_first, double mu,
                      dContact* contacts, int n) override {
    const Robot& r = *robots_[Engine::OwnerOf(wheel)];
    const double tread = r.tread[Engine::PartOf(wheel) == kRightTreel ? 1 : 0];
    (void)engine;
    DriveTreadContacts(wheel, wheel_first, tread, std::min(mu, r.pull_limit), mu, kTreelSideSlip,
                       contacts, n);
  }

 private:
  struct Robot {
    double wheel_base = 0.14;
    double tread[2] = {0, 0};  // left, right treel tread speed this tick (m/s)
    double pull_limit = 1;     // treel_max_torque / wheel radius / (half the robot's weight)
    // Manipulator (head == nullptr: none).
    dBodyID head = nullptr;
    dJointID piston = nullptr;
    double elevation0 = 0, rotation0 = 0;  // joint positions when the joints were made
    Magnet magnet;
    bool tilt_refused = false;  // the warning about the tilt was given
    // Gripper: the joint fixing what it holds to the chassis.
    dJointID grip = nullptr;
    uint32_t gripped = kNone;
  };

  // Releases what the gripper no longer wants to hold; closes on what is in
  // front of the jaws when it wants to hold something: the lowest-slot
  // movable thing at the docking ring's height within reach, probed at four
  // points out to the reach, nearest first (as in dynamics2d).
  static void UpdateGrip(Engine& engine, uint32_t s, Robot& r, GripperState& g) {
    if (!g.want_grip) {
      Ungrip(engine, s, r);
      return;
    }
    if (r.grip) return;
    dBodyID chassis = engine.BodyOf(s);
    const Quat q = BodyQuat(chassis);
    const Space& space = engine.entities();
    const Pose& pose = space.pose(s);
    const double radius = space.geometry(s).radius;
    const Vec3 dir = q * Vec3(std::cos(g.turret), std::sin(g.turret), 0);
    const Vec3 ring = pose.position + q * Vec3(0, 0, marxbot::kLedRingElevation);
    for (int step = 1; step <= 4; ++step) {
      const Vec3 p = ring + (radius + g.reach * step / 4) * dir;
      Engine::Touch touch;
      if (!engine.TouchAt(p, 0.002, s, touch) || !touch.body || touch.owner == kNone) continue;
      if (engine.HolderOf(touch.owner) != kNone) continue;  // held by something else
      r.grip = dJointCreateFixed(engine.world(), nullptr);
      dJointAttach(r.grip, chassis, touch.body);
      dJointSetFixed(r.grip);
      r.gripped = touch.owner;
      engine.SetHolder(touch.owner, s);
      return;
    }
  }

  static void Ungrip(Engine& engine, uint32_t s, Robot& r) {
    (void)s;
    if (!r.grip) return;
    dJointDestroy(r.grip);
    r.grip = nullptr;
    if (engine.HolderOf(r.gripped) != kNone) engine.SetHolder(r.gripped, kNone);
    r.gripped = kNone;
  }

  // The commanded wheel speeds ask for forwards speed (l + r) / 2 and turn
  // rate (r - l) / wheel_base; the treads at y = +-treel_y give exactly that.
  static void SetTreads(const Space& space, uint32_t s, Robot& r) {
    const DriveState& d = *space.drive(s);
    const double left = std::isfinite(d.left) ? d.left : 0.0;
    const double right = std::isfinite(d.right) ? d.right : 0.0;
    const double v = 0.5 * (left + right), w = (right - left) / r.wheel_base;
    r.tread[0] = v - w * kMarxbot3d.treel_y;
    r.tread[1] = v + w * kMarxbot3d.treel_y;
  }

  static double Elevation(const Robot& r) {
    return r.elevation0 + dJointGetPistonPosition(r.piston);
  }
  static double Rotation(const Robot& r) {
    return WrapAngle(r.rotation0 + dJointGetPistonAngle(r.piston));
  }

  static void DriveHead(const Space& space, uint32_t s, Robot& r, double h) {
    const ManipulatorState& m = *space.Get<ManipulatorState>(s);
    const double lo = std::min(m.min_elevation, m.max_elevation),
                 hi = std::max(m.min_elevation, m.max_elevation);
    const double target =
        std::clamp(std::isfinite(m.target_elevation) ? m.target_elevation : lo, lo, hi);
    const double e = Elevation(r);
    dJointSetPistonParam(r.piston, dParamVel,
                         std::clamp((target - e) / h, -m.elevation_speed, m.elevation_speed));
    // Stops 1 cm beyond the range, so the motor never pushes against them (at
    // a stop ODE would add the motor's full force explicitly).
    dJointSetPistonParam(r.piston, dParamLoStop, lo - 0.01 - r.elevation0);
    dJointSetPistonParam(r.piston, dParamHiStop, hi + 0.01 - r.elevation0);
    const double aim = std::isfinite(m.target_rotation) ? m.target_rotation : Rotation(r);
    const double error = WrapAngle(aim - Rotation(r));
    dJointSetPistonParam(r.piston, dParamVel2,
                         std::clamp(error / h, -m.rotation_speed, m.rotation_speed));
  }

  // The head's tilt is not simulated here (it would need a third joint): the
  // head stays upright, and a tilt command is refused with a warning, once
  // per robot.
  static void RefuseTilt(const Space& space, uint32_t s, Robot& r) {
    const ManipulatorState& m = *space.Get<ManipulatorState>(s);
    if (m.target_tilt == 0 || r.tilt_refused) return;
    r.tilt_refused = true;
    LogWarning("robot '" + space.id(s) +
               "': dynamics3d does not simulate the manipulator's tilt; " +
               "the head stays upright (tilt 0), not " + FormatNumber(m.target_tilt) +
               " rad (said once per robot; kinematics2d simulates the tilt)");
  }

  // Switches the magnet over, lets go when it is no longer fully engaged,
  // and holds what it touches when it is.
  static void UpdateMagnet(Engine& engine, Space& space, uint32_t s, Robot& r, double dt) {
    ManipulatorState& m = *space.Get<ManipulatorState>(s);
    m.SwitchMagnet(dt);
    if (m.magnet < 1.0) {
      r.magnet.Release(engine);
      return;
    }
    r.magnet.Grab(engine, s, r.head, 0.5 * marxbot::kHeadDepth, marxbot::kHeadHeight);
  }

  std::vector<std::unique_ptr<Robot>> robots_;  // per space slot
  std::vector<uint32_t> slots_;                 // this model's robots, in slot order
};

COLONY_REGISTER_PHYSICS_MODEL(
    MarxbotDynamics3dModel, "dynamics3d:marxbot",
    "one body on two treels of two wheels each, whose treads move at the wheel speeds "
    "(torque-limited, slip); the gripper fixes what it closes on to the body; with "
    "manipulator=\"true\" a motor-driven head carrying a magnet",
    (std::vector<std::string>{"drive", "manipulator", "gripper"}));

}  // namespace
}  // namespace colony
