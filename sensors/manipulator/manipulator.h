// Manipulator sensor (control interface): where the marXbot's construction
// manipulator is (head elevation, rotation and tilt), the state of its magnet,
// whether it holds something, and the 6 IR proximity sensors on the head's
// IR side (the side opposite the magnet).
#pragma once

#include <vector>

#include "core/control_interface.h"

namespace colony {

class ManipulatorSensor : public Sensor {
 public:
  struct Reading {
    float value;  // 0: nothing in range; rises as an object nears; 1: touching (within 1 cm)
    float angle;  // direction of the sensor from the IR side's facing direction, counter-clockwise
                  // (rad)
  };
  // Height of the magnet's centre above the floor under the robot (m).
  double elevation() const { return elevation_; }
  // Head rotation, counter-clockwise from "magnet side to the front", in (-pi, pi] (rad).
  double rotation() const { return rotation_; }
  // Head pitch about its horizontal axis (rad): 0 upright, > 0 the magnet face
  // turned down (pi/2: looking straight down), < 0 the IR face turned down.
  double tilt() const { return tilt_; }
  // Magnet: 0 disengaged .. 1 engaged (it switches over about 1 s).
  double magnet() const { return magnet_; }
  // Fully engaged: it holds a ferromagnetic face it touches.
  bool magnet_engaged() const { return magnet_ >= 1; }
  // The magnet holds an object.
  bool holding() const { return holding_; }
  // The 6 IR sensors of the IR side, from its right (clockwise-most) to its left.
  const std::vector<Reading>& readings() const { return readings_; }

 protected:
  double elevation_ = 0, rotation_ = 0, tilt_ = 0, magnet_ = 0;
  bool holding_ = false;
  std::vector<Reading> readings_;
};

}  // namespace colony
