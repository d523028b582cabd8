// Pieces of robots that dynamics3d models compose: treads that drive a
// chassis through their contacts, and a switchable magnet that holds
// construction cubes.
#pragma once

#include "engines/dynamics3d/dynamics3d.h"

namespace colony::dynamics3d {

// A tread (or a wheel's rim) turning about the y axis of its geom's body at
// `speed` (m/s): sets the surface motion of contacts[0..n) between `wheel`
// (a sphere on that body) and something else, so that the ground pushes the
// body as a turning wheel would, up to `pull` x the normal force along the
// tread (the motor's torque bound, or friction `mu` if lower) before it
// slips. Sideways the tread yields a little under load (force-dependent
// slip `side_slip`, m/s per N): with Coulomb friction alone, which of a
// treel's front and rear wheels slides when the robot turns would be
// arbitrary (the robot would turn about its front or rear axle); this makes
// it turn about its middle, as differential drive kinematics have it.
void DriveTreadContacts(dGeomID wheel, bool wheel_first, double speed, double pull, double mu,
                        double side_slip, dContact* contacts, int n);

// A magnet on the +x face of a body (the face's centre `face_offset` along
// the body's x axis, `face_height` tall). Fully engaged, it holds the
// nearest construction cube whose ferromagnetic plate (the lower half of a
// side) the face touches, within the engine's magnet_reach, with a fixed
// joint that breaks beyond magnet_max_force.
class Magnet {
 public:
  bool holding() const { return held_ != kNone; }
  uint32_t held() const { return held_; }
  // Holds what the face touches, if anything (`owner` is the entity the
  // body belongs to).
  void Grab(Engine& engine, uint32_t owner, dBodyID body, double face_offset, double face_height);
  void Release(Engine& engine);
  // Lets go if pulled harder than magnet_max_force in the last solve.
  void BreakIfOverloaded(Engine& engine);

 private:
  dJointID joint_ = nullptr;
  dJointFeedback feedback_{};
  uint32_t held_ = kNone;
};

}  // namespace colony::dynamics3d
