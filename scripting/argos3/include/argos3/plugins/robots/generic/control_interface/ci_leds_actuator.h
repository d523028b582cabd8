// ARGoS compatibility layer (Colony): the robot's LEDs (on the foot-bot: 12
// on the ring, counter-clockwise from the front, and the beacon, index 12).
// An index beyond GetNumLEDs() throws CARGoSException.
#pragma once

#include <vector>

#include "argos3/core/control_interface/ci_actuator.h"
#include "argos3/core/utility/datatypes/color.h"

namespace argos {

class CCI_LEDsActuator : public CCI_Actuator {
 public:
  using TSettings = std::vector<CColor>;

  ~CCI_LEDsActuator() override = default;
  size_t GetNumLEDs() const { return settings_.size(); }
  virtual void SetSingleColor(UInt32 index, const CColor& color) = 0;
  virtual void SetAllColors(const CColor& color) = 0;
  // One colour per LED; throws CARGoSException when the count differs.
  virtual void SetAllColors(const TSettings& colors) = 0;
  // The alpha channel of one or every LED.
  virtual void SetSingleIntensity(UInt32 index, UInt8 intensity) = 0;
  virtual void SetAllIntensities(UInt8 intensity) = 0;

 protected:
  TSettings settings_;
};

}  // namespace argos
