// Battery (control interface): how much energy the robot has left. On the
// marXbot: a 38 Wh lithium polymer battery, up to 7 h of driving.
#pragma once

#include "core/control_interface.h"

namespace colony {

class Battery : public Sensor {
 public:
  // Charge left, from 0 (empty) to 1 (full), as the robot reads it (noise included).
  double level() const { return level_; }
  // Energy left as the robot reads it: level() x capacity() (J).
  double remaining_energy() const { return level_ * capacity_; }
  // Energy of a full battery (J; 38 Wh = 136,800 J on the marXbot).
  double capacity() const { return capacity_; }
  // Whether the battery is exhausted (the true charge, without noise, is 0).
  // With stop_when_empty (the default) the robot's wheels are then stopped.
  bool empty() const { return empty_; }

 protected:
  double level_ = 1;
  double capacity_ = 0;
  bool empty_ = false;
};

}  // namespace colony
