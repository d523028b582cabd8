// Ground sensors (control interface): downward IR sensors under the base
// that read the floor's grey level, and see holes (a ditch under a sensor
// reads 0). On the marXbot: 8 sensors, 45 degrees apart.
#pragma once

#include <vector>

#include "core/control_interface.h"

namespace colony {

class GroundSensor : public Sensor {
 public:
  struct Reading {
    float value;  // grey level of the floor under the sensor: 0 black, 1 white; 0 over a hole (no
                  // ground)
    float angle;  // direction of the sensor from the robot's centre, robot frame (rad)
  };
  const std::vector<Reading>& readings() const { return readings_; }

 protected:
  std::vector<Reading> readings_;
};

}  // namespace colony
