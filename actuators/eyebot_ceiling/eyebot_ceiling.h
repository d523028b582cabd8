// Eye-bot ceiling attachment actuator (control interface): the mechanism on
// top of the body that holds the robot to the ceiling, rotors off, so it can
// watch from above without spending energy (seed 003, 5.3). Attach() asks
// it to hold on: it takes hold as soon as the top of the body touches the
// ceiling (the robot must fly up to it), not before. Detach() lets go: the
// robot then flies as its propulsion says (or falls if the rotors are off).
#pragma once

#include "core/control_interface.h"

namespace colony {

class EyebotCeilingActuator : public Actuator {
 public:
  void Attach() { attach_ = true; }
  void Detach() { attach_ = false; }
  // Whether it was last asked to hold on (the eyebot_ceiling sensor says
  // whether it does).
  bool attach_requested() const { return attach_; }

 protected:
  bool attach_ = false;
};

}  // namespace colony
