// Rope traction sensor (control interface): the state of the hand-bot's
// rope (stowed, attached to the ceiling, or the last launch failed), its
// length from the magnet to the launcher, and the traction on it: about the
// robot's weight while it hangs, more while it lifts a load, 0 while the
// rope is slack (the robot stands or holds on with its grippers).
#pragma once

#include "core/control_interface.h"

namespace colony {

class RopeTractionSensor : public Sensor {
 public:
  enum class Status { kStowed, kAttached, kLaunchFailed };
  Status status() const { return status_; }
  bool attached() const { return status_ == Status::kAttached; }
  bool launch_failed() const { return status_ == Status::kLaunchFailed; }
  // m from the magnet to the launcher's top (0 unless attached).
  double length() const { return length_; }
  // N, the rope's pull on the robot (0 unless attached; noise may be added).
  double traction() const { return traction_; }
  // Climbing, the motor pulls its most and the rope does not shorten.
  bool stalled() const { return stalled_; }

 protected:
  Status status_ = Status::kStowed;
  double length_ = 0, traction_ = 0;
  bool stalled_ = false;
};

}  // namespace colony
