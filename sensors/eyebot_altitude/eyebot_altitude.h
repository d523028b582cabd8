// Eye-bot altitude sensor (control interface): a rangefinder under the body
// looking straight down, as a flying robot's altimeter.
#pragma once

#include <limits>

#include "core/control_interface.h"

namespace colony {

class EyebotAltitudeSensor : public Sensor {
 public:
  // From the bottom of the body (the feet) down to what is under the
  // robot's axis, the floor or the top of a solid entity (m): 0 when
  // standing on it. +infinity when nothing is within the sensor's range
  // (its `range` attribute), or the reading was lost.
  double altitude() const { return altitude_; }
  // Farthest it measures (m).
  double range() const { return range_; }

 protected:
  double altitude_ = std::numeric_limits<double>::infinity();
  double range_ = 0;
};

}  // namespace colony
