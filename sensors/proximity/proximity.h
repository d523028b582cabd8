// Proximity sensors (control interface): a ring of short-range IR sensors.
// On the marXbot: 24 sensors, 15 degrees apart, 6 cm above the floor.
#pragma once

#include <span>

#include "core/control_interface.h"

namespace colony {

class ProximitySensor : public Sensor {
 public:
  struct Reading {
    float value;  // 0: nothing in range; rises as an object nears; 1: touching (within 1 cm)
    float angle;  // direction of the sensor in the robot's frame, counter-clockwise from the front
                  // (rad)
  };
  // One reading per sensor, in ring order. Reading them is a poll of the
  // ring, counted on the robot's bus when it has bus accounting (docs/events.md).
  // The view stays valid as long as the robot (the readings live in one
  // array of the simulated sensor's, not in a vector of each robot's).
  std::span<const Reading> readings() const {
    read_ = true;
    return readings_;
  }
  bool TakeRead() override {
    const bool read = read_;
    read_ = false;
    return read;
  }
  // Watch (Sensor::Watch): events when a reading's value crosses a
  // threshold; `reading` is the sensor's index in ring order.

 protected:
  std::span<Reading> readings_;

 private:
  mutable bool read_ = false;  // readings() was called since TakeRead
};

}  // namespace colony
