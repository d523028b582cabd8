// Eye-bot ceiling sensor (control interface): whether the ceiling
// attachment holds, and how far the top of the body is under the ceiling.
#pragma once

#include <limits>

#include "core/control_interface.h"

namespace colony {

class EyebotCeilingSensor : public Sensor {
 public:
  // Whether the robot holds to the ceiling (rotors off).
  bool attached() const { return attached_; }
  // From the top of the body up to the ceiling (m): 0 when touching;
  // +infinity when the arena has no ceiling.
  double ceiling_distance() const { return ceiling_distance_; }

 protected:
  bool attached_ = false;
  double ceiling_distance_ = std::numeric_limits<double>::infinity();
};

}  // namespace colony
