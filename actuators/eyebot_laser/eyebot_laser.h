// Eye-bot laser actuator (control interface): the red laser pointer in the
// pan-tilt head, along the camera's axis. Where its beam meets the floor or
// a body, a red spot shows that cameras (the robot's own pan-tilt camera,
// other robots' omnidirectional cameras) see as a blob.
#pragma once

#include "core/control_interface.h"

namespace colony {

class EyebotLaserActuator : public Actuator {
 public:
  void On() { on_ = true; }
  void Off() { on_ = false; }
  void Set(bool on) { on_ = on; }
  bool is_on() const { return on_; }

 protected:
  bool on_ = false;
};

}  // namespace colony
