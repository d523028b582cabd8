// Differential steering (control interface): the speed of the left and right
// wheels (treels). Positive drives forwards. SI units: m/s (ARGoS used cm/s).
#pragma once

#include "core/control_interface.h"

namespace colony {

class DifferentialSteering : public Actuator {
 public:
  void SetLinearVelocity(double left, double right) {
    left_ = left;
    right_ = right;
  }
  double target_left() const { return left_; }
  double target_right() const { return right_; }

 protected:
  double left_ = 0, right_ = 0;
};

}  // namespace colony
