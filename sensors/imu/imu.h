// IMU (control interface): gyroscope and accelerometer, in the robot's frame
// (x forwards, y to the left, z up).
#pragma once

#include <array>

#include "core/control_interface.h"

namespace colony {

class Imu : public Sensor {
 public:
  // Angular velocity about x, y, z (rad/s); turning left is +z.
  const std::array<double, 3>& angular_velocity() const { return gyro_; }
  // Proper acceleration along x, y, z (m/s^2): what an accelerometer feels,
  // so a robot at rest on the floor reads +9.81 on z.
  const std::array<double, 3>& acceleration() const { return accel_; }

 protected:
  std::array<double, 3> gyro_{};
  std::array<double, 3> accel_{};
};

}  // namespace colony
