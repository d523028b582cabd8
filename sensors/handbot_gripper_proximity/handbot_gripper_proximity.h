// Hand-bot gripper proximity sensor (control interface): the IR proximity
// sensors in each gripper's tip (seed 003, 5.2.4: 12 per gripper, 12 cm
// range; the seed also simulated 3 and 24, offered as implementations).
// They look out of the claws in a cone around the gripper's axis, so a
// gripper sees a board or a book it is about to grasp.
#pragma once

#include <vector>

#include "core/control_interface.h"

namespace colony {

class HandbotGripperProximitySensor : public Sensor {
 public:
  static constexpr int kLeft = 0, kRight = 1;
  struct Reading {
    float value;   // 0: nothing within range; rises as something nears; 1: within 1 cm
    float around;  // the sensor's direction: angle about the gripper's axis (rad, 0: the
                   // gripper's +y side at wrist rotation 0, counter-clockwise seen from behind)
    float tilt;    // and its angle from the gripper's axis (rad; 0 straight out of the claws)
  };
  // The readings of gripper `g` (kLeft, kRight).
  const std::vector<Reading>& readings(int g) const {
    return readings_[g == kRight ? kRight : kLeft];
  }

 protected:
  std::vector<Reading> readings_[2];
};

}  // namespace colony
