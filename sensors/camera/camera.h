// Camera (control interface): a perspective colour camera on the robot. On
// the marXbot: the front camera, looking forwards.
#pragma once

#include <cstdint>
#include <vector>

#include "core/color.h"
#include "core/control_interface.h"

namespace colony {

class CameraSensor : public Sensor {
 public:
  int width() const { return width_; }
  int height() const { return height_; }
  // The image: 3 bytes per pixel (red, green, blue, 0..255), rows from the
  // top, pixels from the left.
  const std::vector<uint8_t>& rgb() const { return rgb_; }
  // The pixel in column x (from the left) and row y (from the top).
  Color At(int x, int y) const {
    const uint8_t* p = rgb_.data() + (static_cast<size_t>(y) * width_ + x) * 3;
    return {p[0], p[1], p[2], 255};
  }

 protected:
  int width_ = 0, height_ = 0;
  std::vector<uint8_t> rgb_;
};

}  // namespace colony
