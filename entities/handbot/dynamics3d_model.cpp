// The hand-bot in dynamics3d (engines/dynamics3d): the hull (a cylinder
// standing on the floor, with the rope launcher's tube on top) as one body;
// the head on a hinge about the robot's forward axis, each arm on a hinge
// about the head's vertical axis, each gripper on a hinge about its arm,
// every hinge driven by a motor that gives the torque a DC motor gives at
// the joint's speed (handbot_arms_state.h); claws that, closing on
// something in front of the gripper's tip, hold it with a fixed joint that
// lets go when pulled harder than the claws hold (4 kg); and the rope: a unilateral distance
// constraint between the magnet, held to the ceiling, and the launcher's top. Beyond the rope
// let out the rope pulls like a stiff, critically damped spring (rope_stiffness); it never pushes,
// and lets the robot swing and turn freely about the magnet. Each sub-step the constraint is an ODE
// contact joint at the launcher's top, its normal towards the magnet, its depth how far the robot
// is beyond the rope let out, its ERP and CFM the spring's; ODE's solver keeps the force >= 0. The
// motor coils the rope in (the robot climbs) while the rope pulls less than its force, and stalls
// otherwise. The traction is the constraint's force, averaged over the tick's sub-steps.
//
// Seed 003 (5.2.2) modelled the rope with a ball joint at the anchor and a
// slider joint along the rope. Built that way on ODE's iterative solver (a
// light rope body between the ball and the 2 kg robot, 2 m below), the
// rope stretched by up to 28 cm and the robot bounced while climbing, so the
// rope is the constraint above; what a controller reads (length, traction,
// attached, stalled) is the same.
//
// Launching fires the magnet straight up along the hull's axis: it holds
// where that line first meets something, if that is a ferromagnetic ceiling
// within the rope's length; otherwise the launch fails and the rope is
// coiled back. The magnet's flight (a fraction of a second) is not
// modelled: it holds, or the launch is known to have failed, at the tick
// the launch was asked for.
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string_view>
#include <vector>

#include "actuators/handbot_arms/handbot_arms_state.h"
#include "actuators/handbot_fans/handbot_fans_state.h"
#include "actuators/rope_launcher/rope_state.h"
#include "core/log.h"
#include "core/space.h"
#include "core/text.h"
#include "engines/dynamics3d/dynamics3d.h"
#include "entities/handbot/handbot.h"

namespace colony {
namespace {

using namespace dynamics3d;

constexpr double kHullComHeight =
    0.10;  // m, centre of mass above the base (battery low in the hull)
constexpr double kShortestRope =
    0.02;  // m, the rope fully coiled in with the robot against the ceiling
using handbot::kPartsMass;
// The claws stop on something held at this aperture (rad): a board or a
// book about 2 cm thick between 3 cm claws.
constexpr double kGraspAperture = 0.35;
// Fewest quickstep iterations that hold the arms still (measured: at 20, 30
// and 40 the arms jitter by up to 0.05 rad and the robot creeps 1.5-3 cm in
// 2 s on the floor; at 60 and with worldstep it stays within 0.5 mm).
constexpr int kQuickstepIterations = 60;

// Rotation about x by `a`.
Quat RollBy(double a) { return Quat(Eigen::AngleAxisd(a, Vec3::UnitX())); }

class HandbotDynamics3dModel : public Dynamics3dModel {
 public:
  ~HandbotDynamics3dModel() override {
    if (ropes_) dJointGroupDestroy(ropes_);  // empty between sub-steps
  }

  void Add(Engine& engine, uint32_t s) override {
    using namespace handbot;
    Space& space = engine.entities();
    if (robots_.size() <= s) robots_.resize(s + 1);
    robots_[s] = std::make_unique<Robot>();
    Robot& r = *robots_[s];
    slots_.insert(std::lower_bound(slots_.begin(), slots_.end(), s), s);
    if (!ropes_) ropes_ = dJointGroupCreate(0);
    const dynamics3d::Params& params = engine.params();
    if (params.quickstep && params.iterations < kQuickstepIterations && !warned_) {
      warned_ = true;
      LogWarning("dynamics3d '" + engine.id() +
                 "': the hand-bot's jointed head, arms and grippers need stepper=\"worldstep\" "
                 "or at least " +
                 std::to_string(kQuickstepIterations) + " quickstep iterations (it has " +
                 std::to_string(params.iterations) +
                 "): with fewer its arms jitter and it creeps on the floor");
    }

    const Vec3 com = HullCom(space.mass(s));
    r.com = com;
    dBodyID hull = engine.MakeBody(s, com);
    dMass m;
    dMassSetCylinderTotal(&m, space.mass(s) - kPartsMass, 3, kHullRadius, kHullHeight);
    dBodySetMass(hull, &m);
    dSpaceID parts = engine.MakePartSpace(s);
    dGeomID body = engine.AddGeom(s, dCreateCylinder(parts, kHullRadius, kHullHeight), kBody);
    dGeomSetBody(body, hull);
    dGeomSetOffsetPosition(body, -com.x(), 0, 0.5 * kHullHeight - com.z());
    dGeomID tube =
        engine.AddGeom(s, dCreateCylinder(parts, kLauncherRadius, kLauncherHeight), kBody);
    dGeomSetBody(tube, hull);
    dGeomSetOffsetPosition(tube, -com.x(), 0, kHullHeight + 0.5 * kLauncherHeight - com.z());
    AddArms(engine, s, r, hull, parts);
    // A robot migrating in with its magnet on the ceiling keeps it there.
    RopeState& rope = *space.Get<RopeState>(s);
    if (rope.attached()) {
      r.attached = true;
      r.paid_out = rope.paid_out;
    } else if (rope.start_attached) {
      // rope_anchor: the magnet already holds there, the rope taut.
      rope.start_attached = false;
      const auto& ceiling = space.ceiling();
      const Vec3 top = LauncherTop(engine, s);
      const Vec3 anchor(rope.start_anchor_x, rope.start_anchor_y, ceiling ? ceiling->z : 0.0);
      const double length = (anchor - top).norm();
      if (!ceiling || !ceiling->ferromagnetic || length > rope.max_length) {
        LogWarning("hand-bot '" + space.id(s) + "': rope_anchor " + FormatNumber(anchor.x()) + "," +
                   FormatNumber(anchor.y()) + ": " +
                   (!ceiling                  ? std::string("there is no <ceiling>")
                    : !ceiling->ferromagnetic ? std::string("the ceiling is not ferromagnetic")
                                              : "the ceiling there is " + FormatNumber(length) +
                                                    " m from the launcher, beyond rope_length " +
                                                    FormatNumber(rope.max_length)) +
                   "; the rope starts in its tube");
      } else {
        rope.status = RopeState::Status::kAttached;
        rope.anchor = anchor;
        rope.paid_out = length;
        r.attached = true;
        r.paid_out = length;
      }
    }
  }

  void Remove(Engine& engine, uint32_t s) override {
    if (s >= robots_.size() || !robots_[s]) return;
    Robot& r = *robots_[s];
    for (int k = 0; k < 2; ++k) LetGo(engine, r, k);
    for (Joint* j : r.joints()) dJointDestroy(j->hinge);
    for (dBodyID b : {r.head, r.arm[0], r.arm[1], r.gripper[0], r.gripper[1]}) dBodyDestroy(b);
    robots_[s].reset();
    slots_.erase(std::lower_bound(slots_.begin(), slots_.end(), s));
  }

  void Release(Engine& engine, uint32_t holder, uint32_t held) override {
    Robot& r = *robots_[holder];
    for (int k = 0; k < 2; ++k) {
      if (r.held[k] == held) LetGo(engine, r, k);
    }
  }

  void BeforeStep(Engine& engine, double dt) override {
    Space& space = engine.entities();
    for (uint32_t s : slots_) {
      Robot& r = *robots_[s];
      RopeState& rope = *space.Get<RopeState>(s);
      if (rope.want_retrieve && r.attached) {
        r.attached = false;
        r.paid_out = 0;
        rope.status = RopeState::Status::kStowed;
      }
      rope.want_retrieve = false;
      if (rope.want_launch && !r.attached) Launch(engine, s, r, rope);
      rope.want_launch = false;
      r.tension_sum = 0;
      r.substeps = 0;
      r.substeps_total = 0;
      r.stalled = false;
      HandbotArmsState& arms = *space.Get<HandbotArmsState>(s);
      for (Joint* j : r.joints()) j->torque_sum = 0;
      for (int k = 0; k < 2; ++k) MoveClaws(engine, s, r, arms, k, dt);
    }
  }

  void BeforeSubstep(Engine& engine, double h) override {
    substep_ = h;
    Space& space = engine.entities();
    for (uint32_t s : slots_) {
      Robot& r = *robots_[s];
      HandbotArmsState& arms = *space.Get<HandbotArmsState>(s);
      Drive(r.head_joint, arms.head, h);
      for (int k = 0; k < 2; ++k) {
        Drive(r.arm_joint[k], arms.arm[k], h);
        Drive(r.wrist_joint[k], arms.wrist[k], h);
      }
      Fans(engine, s, *space.Get<HandbotFansState>(s));
      if (!r.attached) continue;
      const RopeState& rope = *space.Get<RopeState>(s);
      const double speed = std::clamp(std::isfinite(rope.climb_speed) ? rope.climb_speed : 0.0,
                                      -rope.max_climb_speed, rope.max_climb_speed);
      if (speed > 0) {
        // Coiling in: only while the rope pulls less than the motor can.
        if (r.tension < rope.motor_force) {
          r.paid_out = std::max(r.paid_out - speed * h, kShortestRope);
        } else {
          r.stalled = true;
        }
      } else if (speed < 0) {
        r.paid_out = std::min(r.paid_out - speed * h, rope.max_length);
      }
      // The rope: a contact at the launcher's top pulling it towards the
      // magnet, as deep as the robot is beyond the rope let out.
      const Vec3 top = LauncherTop(engine, s);
      const Vec3 to_magnet = rope.anchor - top;
      const double length = to_magnet.norm();
      const double depth = length - r.paid_out;
      r.rope_joint = nullptr;
      if (depth < -1e-3 || length < 1e-9) continue;  // slack
      dContact c{};
      c.surface.mode = dContactSoftERP | dContactSoftCFM;
      c.surface.mu = 0;
      // The rope stretches: a spring of the rope's stiffness, damped
      // critically for the robot's mass, as ODE's soft constraint
      // parameters for this sub-step.
      const double k = rope.stiffness, d = 2 * std::sqrt(rope.stiffness * space.mass(s));
      c.surface.soft_erp = h * k / (h * k + d);
      c.surface.soft_cfm = 1 / (h * k + d);
      const Vec3 n = to_magnet / length;
      c.geom.pos[0] = top.x();
      c.geom.pos[1] = top.y();
      c.geom.pos[2] = top.z();
      c.geom.normal[0] = n.x();
      c.geom.normal[1] = n.y();
      c.geom.normal[2] = n.z();
      // ODE lets contacts sink by the world's surface layer before it
      // pushes back: added, the rope pulls from exactly the length let out.
      c.geom.depth = depth + dWorldGetContactSurfaceLayer(engine.world());
      r.normal = n;
      r.rope_joint = dJointCreateContact(engine.world(), ropes_, &c);
      dJointAttach(r.rope_joint, engine.BodyOf(s), nullptr);
      dJointSetFeedback(r.rope_joint, &r.rope_feedback);
    }
  }

  void AfterSubstep(Engine& engine) override {
    const Space& space = engine.entities();
    for (uint32_t s : slots_) {
      Robot& r = *robots_[s];
      for (Joint* j : r.joints()) j->torque_sum += j->Torque();
      ++r.substeps_total;
      // A grasped thing pulled harder than the claws hold slips out.
      const double limit = space.Get<HandbotArmsState>(s)->holding_limit;
      for (int k = 0; k < 2; ++k) {
        if (r.grasp[k] && ToVec(r.grasp_feedback[k].f1).norm() > limit) {
          LetGo(engine, r, k);
          r.slipped[k] = true;  // the claws close on nothing until they open again
        }
      }
      if (!r.attached) continue;
      r.tension = r.rope_joint ? std::max(0.0, ToVec(r.rope_feedback.f1).dot(r.normal)) : 0.0;
      r.tension_sum += r.tension;
      ++r.substeps;
      r.rope_joint = nullptr;
    }
    if (ropes_) dJointGroupEmpty(ropes_);
  }

  void AfterStep(Engine& engine, double dt) override {
    (void)dt;
    Space& space = engine.entities();
    for (uint32_t s : slots_) {
      Robot& r = *robots_[s];
      HandbotArmsState& arms = *space.Get<HandbotArmsState>(s);
      const int substeps = std::max(1, r.substeps_total);
      Write(r.head_joint, arms.head, substeps);
      for (int k = 0; k < 2; ++k) {
        Write(r.arm_joint[k], arms.arm[k], substeps);
        Write(r.wrist_joint[k], arms.wrist[k], substeps);
        arms.claws[k].held = r.held[k];
      }
      RopeState& rope = *space.Get<RopeState>(s);
      if (!r.attached) {
        rope.length = 0;
        rope.paid_out = 0;
        rope.tension = 0;
        rope.stalled = false;
        continue;
      }
      rope.status = RopeState::Status::kAttached;
      rope.length = (rope.anchor - LauncherTop(engine, s)).norm();
      rope.paid_out = r.paid_out;
      rope.tension = r.substeps > 0 ? r.tension_sum / r.substeps : 0.0;
      rope.stalled = r.stalled;
    }
  }

  // "handbot_head": the head's centre; "gripper_left", "gripper_right": the
  // middle of a gripper's tip, its x axis pointing out of the claws.
  bool Anchor(const Space& space, uint32_t s, std::string_view name, Pose& pose) const override {
    (void)space;
    if (s >= robots_.size() || !robots_[s]) return false;
    const Robot& r = *robots_[s];
    if (name == "handbot_head") {
      pose = {BodyPos(r.head), BodyQuat(r.head)};
      return true;
    }
    for (int k = 0; k < 2; ++k) {
      if (name != (k == HandbotArmsState::kLeft ? "gripper_left" : "gripper_right")) continue;
      const Quat q = BodyQuat(r.gripper[k]);
      pose = {BodyPos(r.gripper[k]) + q * Vec3(0.5 * handbot::kGripperLength, 0, 0), q};
      return true;
    }
    return false;
  }

 private:
  // A motorised hinge. Its angle in the state's sense is
  // origin + sign x ODE's hinge angle.
  struct Joint {
    dJointID hinge = nullptr;
    dJointFeedback feedback{};
    double origin = 0, sign = 1;
    double torque_sum = 0;
    double Angle() const { return origin + sign * dJointGetHingeAngle(hinge); }
    double Rate() const { return sign * dJointGetHingeAngleRate(hinge); }
    // The motor's torque on the moving part about the axis, in the state's
    // sense. ODE gives the joint's torque about the part's centre of mass,
    // which includes the moment of the hinge's constraint force about it:
    // taken out, what is left about the axis is the motor's (and a stop's).
    double Torque() const {
      dVector3 axis, anchor;
      dJointGetHingeAxis(hinge, axis);
      dJointGetHingeAnchor(hinge, anchor);
      const Vec3 arm = ToVec(anchor) - BodyPos(dJointGetBody(hinge, 0));
      return sign * (ToVec(feedback.t1) - arm.cross(ToVec(feedback.f1))).dot(ToVec(axis));
    }
  };
  struct Robot {
    Vec3 com = Vec3::Zero();  // the hull body's origin in the robot's frame
    // Rope.
    bool attached = false;   // the magnet holds to the ceiling
    double paid_out = 0;     // m of rope let out
    double tension = 0;      // N, in the last sub-step
    double tension_sum = 0;  // over this tick's sub-steps
    int substeps = 0;
    int substeps_total = 0;
    bool stalled = false;  // during this tick
    Vec3 normal = Vec3::UnitZ();
    dJointID rope_joint = nullptr;  // this sub-step's rope constraint, if taut
    dJointFeedback rope_feedback{};
    // Head, arms, grippers.
    dBodyID head = nullptr, arm[2] = {}, gripper[2] = {};
    Joint head_joint, arm_joint[2], wrist_joint[2];
    dJointID grasp[2] = {};
    dJointFeedback grasp_feedback[2] = {};
    uint32_t held[2] = {HandbotArmsState::kNothing, HandbotArmsState::kNothing};
    bool slipped[2] = {
        false, false};  // a grasped thing slipped out; the claws close on nothing until reopened
    std::array<Joint*, 5> joints() {
      return {&head_joint, &arm_joint[0], &arm_joint[1], &wrist_joint[0], &wrist_joint[1]};
    }
  };

  static dBodyID Part(Engine& engine, uint32_t s, dSpaceID parts, const Vec3& centre, const Quat& q,
                      const Vec3& box, double mass, const Twist& twist, const Vec3& origin) {
    dBodyID b = dBodyCreate(engine.world());
    engine.AddPartBody(s, b);
    PlaceBody(b, centre, q);
    SetBodyVelocity(b, twist.linear + twist.angular.cross(centre - origin), twist.angular);
    dMass m;
    // Inertia of a 10 cm cube of the part's mass, at least: ODE's iterative
    // solver copes badly with thin light bodies chained by motorised joints
    // (with their own inertia the arms flailed and the robot fell over).
    dMassSetBoxTotal(&m, mass, std::max(box.x(), 0.1), std::max(box.y(), 0.1),
                     std::max(box.z(), 0.1));
    dBodySetMass(b, &m);
    dGeomID g = engine.AddGeom(s, dCreateBox(parts, box.x(), box.y(), box.z()), kBody);
    dGeomSetBody(g, b);
    return b;
  }

  static void MakeHinge(Engine& engine, Joint& j, dBodyID moving, dBodyID base, const Vec3& anchor,
                        const Vec3& axis, double origin, double sign, const HandbotJoint& state) {
    j.hinge = dJointCreateHinge(engine.world(), nullptr);
    dJointAttach(j.hinge, moving, base);
    dJointSetHingeAnchor(j.hinge, anchor.x(), anchor.y(), anchor.z());
    dJointSetHingeAxis(j.hinge, axis.x(), axis.y(), axis.z());
    dJointSetFeedback(j.hinge, &j.feedback);
    j.origin = origin;
    j.sign = sign;
    if (state.limited()) {
      // Hinge angles of the state's limits, 1 cm-equivalent beyond them so the
      // motor never pushes on a stop.
      const double a = (state.min - 0.01 - origin) * sign, b = (state.max + 0.01 - origin) * sign;
      dJointSetHingeParam(j.hinge, dParamLoStop, std::min(a, b));
      dJointSetHingeParam(j.hinge, dParamHiStop, std::max(a, b));
    }
  }

  // The head on a hinge about the robot's forward axis, and on it each arm
  // on a hinge about the head's vertical axis, each gripper on a hinge about
  // its arm, from the joints' positions in the state.
  void AddArms(Engine& engine, uint32_t s, Robot& r, dBodyID hull, dSpaceID parts) {
    using namespace handbot;
    Space& space = engine.entities();
    const HandbotArmsState& arms = *space.Get<HandbotArmsState>(s);
    const Pose& pose = space.pose(s);
    const Twist& twist = space.twist(s);
    const Quat& q = pose.orientation;
    const Vec3 head_centre = pose.position + q * Vec3(kHeadX, 0, kHeadZ);
    const Quat qh = q * RollBy(arms.head.position);
    r.head = Part(engine, s, parts, head_centre, qh, Vec3(kHeadDepth, kHeadWidth, kHeadHeight),
                  kHeadMass, twist, pose.position);
    MakeHinge(engine, r.head_joint, r.head, hull, head_centre, q * Vec3::UnitX(),
              arms.head.position, 1, arms.head);
    for (int k = 0; k < 2; ++k) {
      const double side = k == HandbotArmsState::kLeft ? 1.0 : -1.0;
      const double theta = arms.arm[k].position;
      const Vec3 shoulder = head_centre + qh * Vec3(0.5 * kHeadDepth, side * kShoulderY, 0);
      // The arm's direction in the head's frame, and its yaw there.
      const Vec3 along(std::sin(theta), side * std::cos(theta), 0);
      const Quat qa = qh * FromYaw(std::atan2(along.y(), along.x()));
      const Vec3 d = qh * along;
      r.arm[k] =
          Part(engine, s, parts, shoulder + 0.5 * kArmLength * d, qa,
               Vec3(kArmLength, kArmThickness, kArmThickness), kArmMass, twist, pose.position);
      // Extending turns the left arm clockwise about the head's z, the right one anticlockwise.
      MakeHinge(engine, r.arm_joint[k], r.arm[k], r.head, shoulder, qh * Vec3::UnitZ(), theta,
                -side, arms.arm[k]);
      const Vec3 tip = shoulder + kArmLength * d;
      const Quat qg = qa * RollBy(arms.wrist[k].position);
      r.gripper[k] = Part(engine, s, parts, tip + 0.5 * kGripperLength * d, qg,
                          Vec3(kGripperLength, kGripperWidth, kGripperWidth), kGripperMass, twist,
                          pose.position);
      MakeHinge(engine, r.wrist_joint[k], r.gripper[k], r.arm[k], tip, d, arms.wrist[k].position, 1,
                arms.wrist[k]);
    }
  }

  // The fans: a yaw torque about the hull's axis, the one commanded or the
  // heading hold's (PD on the hull's yaw and yaw rate), within their most.
  static void Fans(Engine& engine, uint32_t s, HandbotFansState& fans) {
    dBodyID hull = engine.BodyOf(s);
    const Quat q = BodyQuat(hull);
    const Vec3 axis = q * Vec3::UnitZ();
    double torque = fans.torque;
    if (fans.hold) {
      const double yaw = YawOf(q);
      const double rate = ToVec(dBodyGetAngularVel(hull)).dot(axis);
      torque =
          -handbot::kFanHoldGain * WrapAngle(yaw - fans.heading) - handbot::kFanHoldDamping * rate;
    }
    torque = std::clamp(torque, -fans.max_torque, fans.max_torque);
    fans.applied = torque;
    if (torque != 0) dBodyAddTorque(hull, torque * axis.x(), torque * axis.y(), torque * axis.z());
  }

  // The motor towards the target at the commanded speed, with the torque a
  // DC motor gives at the joint's present speed.
  static void Drive(Joint& j, const HandbotJoint& state, double h) {
    const double position = j.Angle();
    const double error = state.limited() ? std::clamp(state.target, state.min, state.max) - position
                                         : WrapAngle(state.target - position);
    const double speed = std::clamp(error / h, -state.speed, state.speed);
    dJointSetHingeParam(j.hinge, dParamVel, j.sign * speed);
    // The joint's speed in the direction the motor drives (0 holding).
    const double driving = speed > 0 ? j.Rate() : speed < 0 ? -j.Rate() : 0.0;
    dJointSetHingeParam(j.hinge, dParamFMax, state.motor.TorqueAt(driving));
  }

  static void Write(const Joint& j, HandbotJoint& state, int substeps) {
    state.position = state.limited() ? j.Angle() : WrapAngle(j.Angle());
    state.velocity = j.Rate();
    state.torque = j.torque_sum / substeps;
    const double error = state.limited()
                             ? std::clamp(state.target, state.min, state.max) - state.position
                             : WrapAngle(state.target - state.position);
    // Stalled: far from the target, barely moving, giving nearly its stall torque.
    state.stalled = std::abs(error) > 0.01 &&
                    std::abs(state.velocity) < 0.05 * state.motor.no_load_speed &&
                    std::abs(state.torque) > 0.9 * state.motor.stall_torque;
  }

  // The claws open or close towards their target; closing on something in
  // front of the gripper's tip they grasp it (a fixed joint that lets go
  // beyond the holding limit), opening they let go.
  void MoveClaws(Engine& engine, uint32_t s, Robot& r, HandbotArmsState& arms, int k, double dt) {
    HandbotArmsState::Claws& c = arms.claws[k];
    const double target =
        std::clamp(std::isfinite(c.target) ? c.target : c.aperture, 0.0, M_PI / 2);
    if (r.grasp[k] && target > kGraspAperture + 1e-9) LetGo(engine, r, k);
    if (target > kGraspAperture + 1e-9) r.slipped[k] = false;
    const double step = c.speed * dt;
    double next = c.aperture + std::clamp(target - c.aperture, -step, step);
    if (r.grasp[k]) next = std::max(next, kGraspAperture);
    if (!r.grasp[k] && !r.slipped[k] && next < kGraspAperture &&
        c.aperture >= kGraspAperture - 1e-9) {
      // The claws reach an object's thickness: is there one between them?
      const Quat q = BodyQuat(r.gripper[k]);
      const Vec3 centre = BodyPos(r.gripper[k]) +
                          q * Vec3(0.5 * handbot::kGripperLength + 0.5 * handbot::kClawReach, 0, 0);
      Engine::Touch touch;
      if (engine.TouchAt(centre, 0.5 * handbot::kClawReach, s, touch)) {
        r.grasp[k] = dJointCreateFixed(engine.world(), nullptr);
        dJointAttach(r.grasp[k], r.gripper[k], touch.body);
        dJointSetFixed(r.grasp[k]);
        // The claws' pads give: the grasp is a stiff spring (kGraspStiffness
        // per metre and per radian), critically damped for the robot's mass.
        // A rigid joint fought the floor's contacts when the robot gripped
        // something while standing, and its force swung past the holding
        // limit within a few sub-steps.
        const double h = substep_ > 0 ? substep_ : dt;
        const double gk = handbot::kGraspStiffness,
                     gd = 2 * std::sqrt(gk * engine.entities().mass(s));
        dJointSetFixedParam(r.grasp[k], dParamERP, h * gk / (h * gk + gd));
        dJointSetFixedParam(r.grasp[k], dParamCFM, 1 / (h * gk + gd));
        dJointSetFeedback(r.grasp[k], &r.grasp_feedback[k]);
        r.held[k] = touch.owner == kNone ? HandbotArmsState::kFixedThing : touch.owner;
        if (touch.body && touch.owner != kNone) engine.SetHolder(touch.owner, s);
        next = kGraspAperture;
      }
    }
    c.aperture = next;
  }

  static void LetGo(Engine& engine, Robot& r, int k) {
    if (!r.grasp[k]) return;
    dJointDestroy(r.grasp[k]);
    r.grasp[k] = nullptr;
    const uint32_t held = r.held[k];
    if (held != HandbotArmsState::kFixedThing && engine.BodyOf(held) &&
        engine.HolderOf(held) != kNone) {
      engine.SetHolder(held, kNone);
    }
    r.held[k] = HandbotArmsState::kNothing;
  }

  // The hull's centre of mass (its body's origin) in the robot's frame:
  // low, and set back so that with the arms folded the whole robot's
  // centre of mass lies on its axis, under the rope.
  static Vec3 HullCom(double mass) {
    using namespace handbot;
    const double parts_moment =
        kHeadMass * kHeadX + 2 * (kArmMass + kGripperMass) * (kHeadX + 0.5 * kHeadDepth);
    return Vec3(-parts_moment / (mass - kPartsMass), 0, kHullComHeight);
  }

  // Where the rope leaves the launcher (world frame).
  Vec3 LauncherTop(Engine& engine, uint32_t s) const {
    dBodyID hull = engine.BodyOf(s);
    const Vec3& com = robots_[s]->com;
    return BodyPos(hull) + BodyQuat(hull) * Vec3(-com.x(), 0, handbot::kHeight - com.z());
  }

  void Launch(Engine& engine, uint32_t s, Robot& r, RopeState& rope) {
    const Vec3 from = LauncherTop(engine, s);
    const Vec3 up = BodyQuat(engine.BodyOf(s)) * Vec3::UnitZ();
    Engine::RayHit hit;
    const Space& space = engine.entities();
    const bool holds = engine.CastRay(from, up, rope.max_length, s, hit) &&
                       hit.material == kCeiling && space.ceiling() &&
                       space.ceiling()->ferromagnetic;
    if (!holds) {
      rope.status = RopeState::Status::kFailed;
      return;
    }
    rope.anchor = hit.point;
    rope.status = RopeState::Status::kAttached;
    r.attached = true;
    r.paid_out = hit.distance;  // taut: the fast motor took up the slack
  }

  double substep_ = 0;
  bool warned_ = false;
  dJointGroupID ropes_ = nullptr;               // this sub-step's rope constraints
  std::vector<std::unique_ptr<Robot>> robots_;  // per space slot
  std::vector<uint32_t> slots_;                 // this model's robots, in slot order
};

COLONY_REGISTER_PHYSICS_MODEL(
    HandbotDynamics3dModel, "dynamics3d:handbot",
    "hull on the floor; the rope: a unilateral distance constraint from the ceiling magnet to the "
    "launcher, coiled in by a force-limited motor; head, arms and grippers on motorised "
    "hinges (DC motor torque-speed lines), claws that grasp with a breakable joint",
    (std::vector<std::string>{"rope", "handbot_arms", "handbot_fans"}));

}  // namespace
}  // namespace colony
