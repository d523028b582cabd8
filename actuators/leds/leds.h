// LEDs (control interface): the robot's RGB LEDs. On the marXbot: 12 on the
// docking ring (indices 0..11, counter-clockwise from the front) and the
// beacon on top (index 12).
#pragma once

#include <vector>

#include "core/color.h"
#include "core/control_interface.h"

namespace colony {

class Leds : public Actuator {
 public:
  size_t count() const { return colors_.size(); }
  // Out-of-range indices are ignored.
  void SetSingleColor(size_t index, Color color) {
    if (index < colors_.size()) colors_[index] = color;
  }
  void SetAllColors(Color color) {
    for (auto& c : colors_) c = color;
  }
  const std::vector<Color>& colors() const { return colors_; }

 protected:
  std::vector<Color> colors_;
};

}  // namespace colony
