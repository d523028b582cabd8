// Wheel encoders (control interface): how far each wheel (treel) moved during
// the last tick, the raw material of odometry.
#pragma once

#include "core/control_interface.h"

namespace colony {

class WheelEncoders : public Sensor {
 public:
  double distance_left() const { return left_; }     // m, negative when turning backwards
  double distance_right() const { return right_; }   // m
  double wheel_base() const { return wheel_base_; }  // m, between the wheels

 protected:
  double left_ = 0, right_ = 0, wheel_base_ = 0;
};

}  // namespace colony
