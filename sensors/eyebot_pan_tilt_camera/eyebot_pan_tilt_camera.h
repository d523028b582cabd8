// Eye-bot pan-tilt camera (control interface): the colour camera in the
// eye-bot's pan-tilt head, as coloured blobs (other robots' lit LEDs,
// landmarks, laser spots, its own laser's spot included) inside its field of
// view, each with its distance from the head and its direction in the
// robot's frame. To point the head at a blob (eyebot_pan_tilt actuator):
//   SetPan(blob.bearing); SetTilt(M_PI / 2 + blob.elevation);
#pragma once

#include <cstdint>
#include <vector>

#include "core/control_interface.h"

namespace colony {

class EyebotPanTiltCamera : public Sensor {
 public:
  struct Blob {
    uint8_t red, green, blue;
    float distance;   // from the head's centre (m, 3D)
    float bearing;    // in the robot's horizontal plane, ccw from its front (rad, (-pi, pi])
    float elevation;  // above the robot's horizontal plane (rad, [-pi/2, pi/2]; below: < 0)
  };
  // The blobs seen this tick, in a deterministic order.
  const std::vector<Blob>& blobs() const { return blobs_; }
  // The head's pan and tilt (rad) when the blobs were taken (as
  // EyebotPanTiltActuator::pan() and tilt()).
  double pan() const { return pan_; }
  double tilt() const { return tilt_; }

 protected:
  std::vector<Blob> blobs_;
  double pan_ = 0, tilt_ = 0;
};

}  // namespace colony
