// The rope component (core/component.h): the hand-bot's rope launcher
// (seed 000, 2.3; seed 003, 5.2.2). A spring fires a magnet on a rope
// straight up; if it meets a ferromagnetic ceiling within the rope's length
// it holds there, and a strong motor coils or lets out the rope to climb or
// go down. Commands are written by the rope launcher actuator; the state
// below them by the physics models that simulate the rope (dynamics3d),
// read by the rope traction sensor.
#pragma once

#include <cstdint>

#include "core/math.h"
#include "core/state_hash.h"

namespace colony {

struct RopeState {
  static constexpr const char* kComponentName = "rope";
  enum class Status : uint8_t {
    kStowed,    // the magnet is in its tube
    kAttached,  // the magnet holds to the ceiling
    kFailed,  // the last launch met no ferromagnetic ceiling within reach; the rope was coiled back
  };
  // Commands.
  bool want_launch = false;    // fire the magnet (the model takes the request and clears it)
  bool want_retrieve = false;  // release the magnet and coil the rope back in
  double climb_speed = 0;      // m/s: > 0 coils the rope in (up), < 0 lets it out (down)
  // Limits (set by the entity; the actuator may override from XML).
  double max_length = 2.7;  // m of rope: the magnet reaches at most this far above the launcher
  double max_climb_speed = 0.1;  // m/s, the motor's fastest coiling
  double motor_force = 50;       // N, the most the motor pulls
  double stiffness = 5000;       // N/m: how much the rope pulls per metre it is stretched
  // Where the magnet already holds to the ceiling when the run starts
  // (x, y; the entity's rope_anchor attribute), if start_attached.
  bool start_attached = false;
  double start_anchor_x = 0, start_anchor_y = 0;
  // State, written by the model.
  Status status = Status::kStowed;
  double length = 0;           // m from the magnet to the launcher's top (0 stowed)
  double paid_out = 0;         // m of rope let out: the length cannot exceed it
  double tension = 0;          // N, the rope's pull on the robot (0 when slack)
  bool stalled = false;        // coiling in, the motor pulls its most and the rope does not shorten
  Vec3 anchor = Vec3::Zero();  // where the magnet holds (world frame)

  bool attached() const { return status == Status::kAttached; }
  void Hash(StateHasher& h) const {
    const double v[8] = {static_cast<double>(status), length,     paid_out,   tension,
                         stalled ? 1.0 : 0.0,         anchor.x(), anchor.y(), anchor.z()};
    h.Add(v, sizeof v);
  }
};

}  // namespace colony
