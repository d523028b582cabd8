// The hand-bot in dynamics3d (engines/dynamics3d): the hull (a cylinder
// standing on the floor, with the rope launcher's tube on top) as one body,
// and the rope: a unilateral distance constraint between the magnet, held
// to the ceiling, and the launcher's top. The rope holds the robot no
// farther from the magnet than the rope let out, never pushes it, and lets
// it swing and turn freely about the magnet. Each sub-step the constraint
// is an ODE contact joint at the launcher's top, its normal towards the
// magnet, its depth how far the robot is beyond the rope let out; ODE's
// solver keeps the force >= 0. The motor coils the rope in (the robot
// climbs) while the rope pulls less than its force, and stalls otherwise.
// The traction is the constraint's force, averaged over the tick's
// sub-steps.
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
#include <cmath>
#include <string_view>
#include <vector>

#include "actuators/rope_launcher/rope_state.h"
#include "core/space.h"
#include "engines/dynamics3d/dynamics3d.h"
#include "entities/handbot/handbot.h"

namespace colony {
namespace {

using namespace dynamics3d;

constexpr double kHullComHeight = 0.10;  // m, centre of mass above the base (battery low in the hull)
constexpr double kShortestRope = 0.02;   // m, the rope fully coiled in with the robot against the ceiling

class HandbotDynamics3dModel : public Dynamics3dModel {
 public:
  ~HandbotDynamics3dModel() override {
    if (ropes_) dJointGroupDestroy(ropes_);  // empty between sub-steps
  }

  void Add(Engine& engine, uint32_t s) override {
    using namespace handbot;
    Space& space = engine.entities();
    const Geometry& g = space.geometry(s);
    if (robots_.size() <= s) robots_.resize(s + 1);
    robots_[s] = Robot{};
    robots_[s].present = true;
    slots_.insert(std::lower_bound(slots_.begin(), slots_.end(), s), s);
    if (!ropes_) ropes_ = dJointGroupCreate(0);

    dBodyID hull = engine.MakeBody(s, kHullComHeight);
    dMass m;
    dMassSetCylinderTotal(&m, space.mass(s), 3, g.radius, g.height());
    dBodySetMass(hull, &m);
    dSpaceID parts = engine.MakePartSpace(s);
    dGeomID body = engine.AddGeom(s, dCreateCylinder(parts, kHullRadius, kHullHeight), kBody);
    dGeomSetBody(body, hull);
    dGeomSetOffsetPosition(body, 0, 0, 0.5 * kHullHeight - kHullComHeight);
    dGeomID tube = engine.AddGeom(s, dCreateCylinder(parts, kLauncherRadius, kLauncherHeight), kBody);
    dGeomSetBody(tube, hull);
    dGeomSetOffsetPosition(tube, 0, 0, kHullHeight + 0.5 * kLauncherHeight - kHullComHeight);
    // A robot migrating in with its magnet on the ceiling keeps it there.
    const RopeState& rope = *space.Get<RopeState>(s);
    if (rope.attached()) {
      robots_[s].attached = true;
      robots_[s].paid_out = rope.paid_out;
    }
  }

  void Remove(Engine& engine, uint32_t s) override {
    (void)engine;
    if (s >= robots_.size() || !robots_[s].present) return;
    robots_[s] = Robot{};
    slots_.erase(std::lower_bound(slots_.begin(), slots_.end(), s));
  }

  void BeforeStep(Engine& engine, double dt) override {
    (void)dt;
    Space& space = engine.entities();
    for (uint32_t s : slots_) {
      Robot& r = robots_[s];
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
      r.stalled = false;
    }
  }

  void BeforeSubstep(Engine& engine, double h) override {
    Space& space = engine.entities();
    for (uint32_t s : slots_) {
      Robot& r = robots_[s];
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
      r.joint = nullptr;
      if (depth < -1e-3 || length < 1e-9) continue;  // slack
      dContact c{};
      c.surface.mode = dContactSoftERP | dContactSoftCFM;
      c.surface.mu = 0;
      c.surface.soft_erp = engine.params().erp;
      c.surface.soft_cfm = engine.params().cfm;
      const Vec3 n = to_magnet / length;
      c.geom.pos[0] = top.x();
      c.geom.pos[1] = top.y();
      c.geom.pos[2] = top.z();
      c.geom.normal[0] = n.x();
      c.geom.normal[1] = n.y();
      c.geom.normal[2] = n.z();
      c.geom.depth = depth;
      r.normal = n;
      r.joint = dJointCreateContact(engine.world(), ropes_, &c);
      dJointAttach(r.joint, engine.BodyOf(s), nullptr);
      dJointSetFeedback(r.joint, &r.feedback);
    }
  }

  void AfterSubstep(Engine& engine) override {
    (void)engine;
    for (uint32_t s : slots_) {
      Robot& r = robots_[s];
      if (!r.attached) continue;
      r.tension = r.joint ? std::max(0.0, ToVec(r.feedback.f1).dot(r.normal)) : 0.0;
      r.tension_sum += r.tension;
      ++r.substeps;
      r.joint = nullptr;
    }
    if (ropes_) dJointGroupEmpty(ropes_);
  }

  void AfterStep(Engine& engine, double dt) override {
    (void)dt;
    Space& space = engine.entities();
    for (uint32_t s : slots_) {
      const Robot& r = robots_[s];
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

 private:
  struct Robot {
    bool present = false;
    bool attached = false;  // the magnet holds to the ceiling
    double paid_out = 0;    // m of rope let out
    double tension = 0;     // N, in the last sub-step
    double tension_sum = 0; // over this tick's sub-steps
    int substeps = 0;
    bool stalled = false;   // during this tick
    Vec3 normal = Vec3::UnitZ();
    dJointID joint = nullptr;  // this sub-step's rope constraint, if taut
    dJointFeedback feedback{};
  };

  // Where the rope leaves the launcher (world frame).
  static Vec3 LauncherTop(Engine& engine, uint32_t s) {
    dBodyID hull = engine.BodyOf(s);
    return BodyPos(hull) + BodyQuat(hull) * Vec3(0, 0, handbot::kHeight - kHullComHeight);
  }

  static void Launch(Engine& engine, uint32_t s, Robot& r, RopeState& rope) {
    const Vec3 from = LauncherTop(engine, s);
    const Vec3 up = BodyQuat(engine.BodyOf(s)) * Vec3::UnitZ();
    Engine::RayHit hit;
    const Space& space = engine.entities();
    const bool holds = engine.CastRay(from, up, rope.max_length, s, hit) && hit.material == kCeiling &&
                       space.ceiling() && space.ceiling()->ferromagnetic;
    if (!holds) {
      rope.status = RopeState::Status::kFailed;
      return;
    }
    rope.anchor = hit.point;
    rope.status = RopeState::Status::kAttached;
    r.attached = true;
    r.paid_out = hit.distance;  // taut: the fast motor took up the slack
  }

  dJointGroupID ropes_ = nullptr;  // this sub-step's rope constraints
  std::vector<Robot> robots_;      // per space slot (dJointFeedback must not move while a joint uses it:
                                   // joints live within a sub-step, when robots_ does not grow)
  std::vector<uint32_t> slots_;    // this model's robots, in slot order
};

COLONY_REGISTER_PHYSICS_MODEL(HandbotDynamics3dModel, "dynamics3d:handbot",
                              "hull on the floor; the rope: a unilateral distance constraint from the ceiling magnet "
                              "to the launcher, coiled in by a force-limited motor",
                              (std::vector<std::string>{"rope"}));

}  // namespace
}  // namespace colony
