// The eye-bot in dynamics3d (engines/dynamics3d): one rigid body, an upright
// cylinder of the entity's geometry and mass (origin at the feet, centre of
// mass half-way up), that collides with the floor, the ceiling, walls,
// objects and robots as any body does.
//
// Flight: each sub-step the flight computer (flight.h, shared with
// pointmass3d) gives the force the rotors should give, world frame; it is
// applied at the centre of mass as it is, so the robot flies as in
// pointmass3d whatever its tilt. The attitude is a second loop, as on a real
// flight computer: torques that turn the body back to level (tilt to an
// angular velocity, that to an angular acceleration) and turn it about the
// vertical at the commanded yaw rate, each at most what a diagonal pair of
// rotors can give. The tilt with which a real quadrotor steers its thrust
// sideways (at most 17 degrees at the default 3 m/s^2) is not modelled: the
// body, and the camera under it, stay level. Rotors off (mode off or
// attached): no force, no torque.
//
// The ceiling attachment: when asked to hold and the top of the body is
// within eyebot::kAttachDistance under the ceiling (the engine's ceiling
// slab stops a climbing robot), a fixed joint to the world holds the body
// where it is, stopped, rotors off; asked to let go, the joint goes.
#include <ode/ode.h>

#include <algorithm>
#include <cmath>
#include <string_view>
#include <vector>

#include "core/space.h"
#include "engines/dynamics3d/dynamics3d.h"
#include "entities/eyebot/eyebot.h"
#include "entities/eyebot/flight.h"

namespace colony {
namespace {

using namespace dynamics3d;

// Attitude loop (1/s): tilt to the angular velocity that levels the body,
// angular velocity error to angular acceleration (together a damping ratio
// of about 1.1 at 18 rad/s). The rate gain is at most 1/h: beyond, an
// explicit torque over a sub-step of h seconds would overshoot.
constexpr double kLevelGain = 8.0;
constexpr double kRateGain = 40.0;

// Rotation matrix of ODE's row-major 3x4 layout.
Eigen::Matrix3d ToMatrix(const dReal* m) {
  Eigen::Matrix3d r;
  r << m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10];
  return r;
}

// `v` scaled down to a norm of `limit` at most.
template <class V>
V Capped(const V& v, double limit) {
  const double n = v.norm();
  return n > limit ? V(v * (limit / n)) : v;
}

class EyebotDynamics3dModel : public Dynamics3dModel {
 public:
  void Add(Engine& engine, uint32_t s) override {
    engine.AddSolid(s, kBody);
    if (robots_.size() <= s) robots_.resize(s + 1);
    robots_[s] = Robot{};
    slots_.insert(std::lower_bound(slots_.begin(), slots_.end(), s), s);
    if (!stepped_) WarnIfHeldAwayFromCeiling(engine.entities(), s);  // at load
  }

  void Remove(Engine& engine, uint32_t s) override {
    (void)engine;
    if (robots_[s].hold) dJointDestroy(robots_[s].hold);
    robots_[s] = Robot{};
    slots_.erase(std::lower_bound(slots_.begin(), slots_.end(), s));
  }

  // Attaches or lets go as asked.
  void BeforeStep(Engine& engine, double dt) override {
    (void)dt;
    stepped_ = true;
    Space& space = engine.entities();
    for (uint32_t s : slots_) {
      Robot& r = robots_[s];
      r.thrust_sum = 0;
      r.substeps = 0;
      CeilingAttachmentState& c = *space.Get<CeilingAttachmentState>(s);
      if (!c.attach && r.hold) {
        dJointDestroy(r.hold);
        r.hold = nullptr;
      } else if (c.attach && !r.hold && UnderCeiling(engine, s)) {
        Hold(engine, s);
      }
      c.attached = r.hold != nullptr;
    }
  }

  void BeforeSubstep(Engine& engine, double h) override {
    const Space& space = engine.entities();
    for (uint32_t s : slots_) {
      Robot& r = robots_[s];
      ++r.substeps;
      const QuadrotorState& q = *space.Get<QuadrotorState>(s);
      if (r.hold || q.mode == QuadrotorState::Mode::kOff) continue;
      dBodyID b = engine.BodyOf(s);
      const Quat rot = BodyQuat(b);
      const Vec3 feet = BodyPos(b) - rot * Vec3(0, 0, 0.5 * space.geometry(s).height());
      const eyebot::FlightOutput out = eyebot::Fly(q, feet, ToVec(dBodyGetLinearVel(b)), YawOf(rot),
                                                   space.mass(s), -engine.params().gravity.z());
      dBodyAddForce(b, out.force.x(), out.force.y(), out.force.z());
      r.thrust_sum += out.thrust;
      const Vec3 torque = AttitudeTorque(b, rot, out.yaw_rate, h, q.max_thrust);
      dBodyAddTorque(b, torque.x(), torque.y(), torque.z());
    }
  }

  void AfterStep(Engine& engine, double dt) override {
    (void)dt;
    Space& space = engine.entities();
    for (uint32_t s : slots_) {
      const Robot& r = robots_[s];
      space.Get<QuadrotorState>(s)->thrust = r.substeps > 0 ? r.thrust_sum / r.substeps : 0.0;
    }
  }

  // "pan_tilt": the pan-tilt head's frame (eyebot.h, PanTiltFrame).
  bool Anchor(const Space& space, uint32_t s, std::string_view name, Pose& pose) const override {
    return PanTiltAnchor(space, s, name, pose);
  }

 private:
  bool stepped_ = false;  // the run has started
  struct Robot {
    dJointID hold = nullptr;  // the fixed joint to the ceiling, if attached
    double thrust_sum = 0;    // N, over this tick's sub-steps
    int substeps = 0;
  };

  // Whether the top of the body is within eyebot::kAttachDistance of the
  // ceiling (or pressed into it).
  static bool UnderCeiling(Engine& engine, uint32_t s) {
    const Space& space = engine.entities();
    if (!space.ceiling()) return false;
    dBodyID b = engine.BodyOf(s);
    const Vec3 top = BodyPos(b) + BodyQuat(b) * Vec3(0, 0, 0.5 * space.geometry(s).height());
    return space.ceiling()->z - top.z() <= eyebot::kAttachDistance;
  }

  // Holds the body still where it is.
  void Hold(Engine& engine, uint32_t s) {
    dBodyID b = engine.BodyOf(s);
    SetBodyVelocity(b, Vec3::Zero(), Vec3::Zero());
    dJointID j = dJointCreateFixed(engine.world(), nullptr);
    dJointAttach(j, b, nullptr);
    dJointSetFixed(j);
    robots_[s].hold = j;
  }

  // The torque that levels body `b` (orientation `rot`) and turns it about
  // the vertical at `yaw_rate`, each part at most what the rotors on one
  // diagonal can give against the other (max_thrust / 4 on each rotor,
  // eyebot::kRotorArm out).
  static Vec3 AttitudeTorque(dBodyID b, const Quat& rot, double yaw_rate, double h,
                             double max_thrust) {
    const Vec3 up = rot * Vec3::UnitZ();
    const Vec3 target = kLevelGain * up.cross(Vec3::UnitZ()) + yaw_rate * Vec3::UnitZ();
    const Vec3 accel = std::min(kRateGain, 1.0 / h) * (target - ToVec(dBodyGetAngularVel(b)));
    dMass m;
    dBodyGetMass(b, &m);
    const Eigen::Matrix3d r = ToMatrix(dBodyGetRotation(b));
    const Vec3 torque = r * (ToMatrix(m.I) * (r.transpose() * accel));
    const double limit = std::sqrt(2.0) * eyebot::kRotorArm * max_thrust / eyebot::kRotorCount;
    const Vec2 level = Capped(Vec2(torque.head<2>()), limit);
    return Vec3(level.x(), level.y(), std::clamp(torque.z(), -limit, limit));
  }

  std::vector<Robot> robots_;    // per space slot
  std::vector<uint32_t> slots_;  // this model's robots, in slot order
};

COLONY_REGISTER_PHYSICS_MODEL(
    EyebotDynamics3dModel, "dynamics3d:eyebot",
    "one body, a cylinder, pushed by the rotors' force from the flight computer (position or "
    "speed control, thrust-limited) and held level by attitude torques; holds to the ceiling "
    "with a fixed joint when asked and touching it; the pan-tilt head as anchor \"pan_tilt\"",
    (std::vector<std::string>{"quadrotor", "ceiling_attachment", "pan_tilt"}));

}  // namespace
}  // namespace colony
