#include "engines/dynamics3d/parts.h"

#include <cmath>

#include "core/space.h"

namespace colony::dynamics3d {
namespace {

// The magnet holds a cube's side only facing it squarely enough.
constexpr double kMagnetAlignment = 0.866;

}  // namespace

void DriveTreadContacts(dGeomID wheel, bool wheel_first, double speed, double pull, double mu,
                        double side_slip, dContact* contacts, int n) {
  const dReal* R = dBodyGetRotation(dGeomGetBody(wheel));
  const Vec3 axle(R[1], R[5], R[9]);
  const Vec3 hub = ToVec(dGeomGetPosition(wheel));
  for (int i = 0; i < n; ++i) {
    dContact& c = contacts[i];
    const Vec3 normal = ToVec(c.geom.normal);
    Vec3 dir = axle.cross(normal);
    if (dir.squaredNorm() < 1e-12) continue;  // touching the wheel's side
    dir.normalize();
    // Velocity of the tread at the contact, relative to the body: the rim
    // turning about its axle at the tread's speed.
    const Vec3 arm = (ToVec(c.geom.pos) - hub).normalized();
    const double surface = speed * axle.cross(arm).dot(dir);
    c.surface.mode |= dContactFDir1 | dContactMu2 | dContactMotion1 | dContactSlip2;
    c.surface.mu = pull;
    c.surface.mu2 = mu;
    c.surface.slip2 = side_slip;
    c.fdir1[0] = dir.x();
    c.fdir1[1] = dir.y();
    c.fdir1[2] = dir.z();
    // The constraint sets (velocity of body 1 - velocity of body 2) along
    // fdir1; a tread that does not slip moves the body against its own
    // motion.
    c.surface.motion1 = wheel_first ? -surface : surface;
  }
}

void Magnet::Grab(Engine& engine, uint32_t owner, dBodyID body, double face_offset,
                  double face_height) {
  if (joint_) return;
  const Space& space = engine.entities();
  const Quat q = BodyQuat(body);
  const Vec3 normal = q * Vec3::UnitX();
  const Vec3 centre = BodyPos(body) + face_offset * normal;
  const double reach = engine.params().magnet_reach;
  uint32_t best = kNone;
  double best_gap = 0;
  for (uint32_t c : engine.cubes()) {
    dBodyID cube = engine.BodyOf(c);
    if (engine.HolderOf(c) != kNone || !cube) continue;
    const double side = space.geometry(c).size.x();
    const Quat qc = BodyQuat(cube);
    const Vec3 p = qc.conjugate() * (centre - BodyPos(cube));  // cube frame, from its centre
    const Vec3 n = qc.conjugate() * normal;
    // The side face the magnet is in front of.
    const int axis = std::abs(p.x()) >= std::abs(p.y()) ? 0 : 1;
    const double sign = p[axis] >= 0 ? 1.0 : -1.0;
    const double gap = sign * p[axis] - 0.5 * side;
    if (gap < -0.005 || gap > reach) continue;
    if (-sign * n[axis] < kMagnetAlignment) continue;  // faces about parallel, facing each other
    if (std::abs(p[1 - axis]) > 0.5 * side) continue;  // over the face
    // Overlapping the plate: the lower half of the side.
    if (p.z() - 0.5 * face_height > 0 || p.z() + 0.5 * face_height < -0.5 * side) continue;
    if (best == kNone || gap < best_gap) {
      best = c;
      best_gap = gap;
    }
  }
  if (best == kNone) return;
  joint_ = dJointCreateFixed(engine.world(), nullptr);
  dJointAttach(joint_, body, engine.BodyOf(best));
  dJointSetFixed(joint_);
  dJointSetFeedback(joint_, &feedback_);
  held_ = best;
  engine.SetHolder(best, owner);
}

void Magnet::Release(Engine& engine) {
  if (joint_) dJointDestroy(joint_);
  joint_ = nullptr;
  if (held_ != kNone) engine.SetHolder(held_, kNone);
  held_ = kNone;
}

void Magnet::BreakIfOverloaded(Engine& engine) {
  if (joint_ && ToVec(feedback_.f2).norm() > engine.params().magnet_max_force) Release(engine);
}

}  // namespace colony::dynamics3d
