// Light sensors (control interface): a ring of sensors reading the light
// entities around the robot; a reading rises as a light nears the direction
// the sensor faces and falls with distance.
#pragma once

#include <vector>

#include "core/control_interface.h"

namespace colony {

class LightSensor : public Sensor {
 public:
  struct Reading {
    float value;  // 0: no light seen; larger: more light (see the sensor's README for the curve)
    float angle;  // direction of the sensor in the robot's frame, ccw from the front (rad)
  };
  // One reading per sensor, in ring order.
  const std::vector<Reading>& readings() const { return readings_; }

 protected:
  std::vector<Reading> readings_;
};

}  // namespace colony
