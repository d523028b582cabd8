// Omnidirectional camera (control interface): the coloured blobs around the
// robot (LEDs of other robots, coloured objects such as landmarks), each with
// its distance and bearing in the robot's frame. On the marXbot a camera
// looking at a conic mirror on top of the robot.
#pragma once

#include <cstdint>
#include <vector>

#include "core/control_interface.h"

namespace colony {

class OmnidirectionalCamera : public Sensor {
 public:
  struct Blob {
    uint8_t red, green, blue;
    float distance;  // horizontal distance from the camera's axis (m)
    float bearing;   // direction in the robot's frame, ccw from the front (rad, (-pi, pi])
  };
  // The blobs seen this tick, in a deterministic order.
  const std::vector<Blob>& blobs() const { return blobs_; }

 protected:
  std::vector<Blob> blobs_;
};

}  // namespace colony
