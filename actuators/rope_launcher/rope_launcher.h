// Rope launcher actuator (control interface): the hand-bot's rope. Launch()
// fires a magnet on a rope straight up; it holds to a ferromagnetic ceiling
// within the rope's length (2.7 m), or the launch fails and the rope is
// coiled back: read which with the rope traction sensor. Once attached,
// SetClimbSpeed() coils the rope in (up) or lets it out (down); Retrieve()
// releases the magnet and coils the rope back in (a hanging robot falls).
#pragma once

#include "core/control_interface.h"

namespace colony {

class RopeLauncherActuator : public Actuator {
 public:
  // Fires the magnet (ignored while it holds to the ceiling).
  void Launch() { launch_ = true; }
  // Releases the magnet and coils the rope in.
  void Retrieve() { retrieve_ = true; }
  // Rope speed (m/s): > 0 climbs (coils the rope in), < 0 goes down (lets it
  // out), 0 holds. Beyond the motor's fastest (max_climb_speed()) it moves at
  // that speed, with a warning; a value that is not a finite number holds.
  void SetClimbSpeed(double speed) { climb_speed_ = speed; }

  double climb_speed() const { return climb_speed_; }
  double max_climb_speed() const { return max_climb_speed_; }

 protected:
  bool launch_ = false, retrieve_ = false;
  double climb_speed_ = 0, max_climb_speed_ = 0;
};

}  // namespace colony
