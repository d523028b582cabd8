// ARGoS compatibility layer (Colony): the messages heard by the
// range-and-bearing receiver this tick. Range in cm, as in ARGoS; bearings in
// radians.
#pragma once

#include <vector>

#include "argos3/core/control_interface/ci_sensor.h"
#include "argos3/core/utility/datatypes/byte_array.h"
#include "argos3/core/utility/datatypes/datatypes.h"
#include "argos3/core/utility/math/angles.h"
#include "argos3/core/utility/math/quaternion.h"

namespace argos {

class CCI_RangeAndBearingSensor : public CCI_Sensor {
 public:
  struct SPacket {
    Real Range = 0;              // cm between the sender's and the receiver's centres
    CRadians HorizontalBearing;  // direction of the sender, counter-clockwise from the front
    CRadians VerticalBearing;    // angle of the sender above the receiver's horizontal plane
    CByteArray Data;             // the sender's payload
  };
  using TReadings = std::vector<SPacket>;

  ~CCI_RangeAndBearingSensor() override = default;
  const TReadings& GetReadings() const { return readings_; }

 protected:
  TReadings readings_;
};

}  // namespace argos
