// ARGoS compatibility layer (Colony): the omnidirectional camera's coloured
// blobs (Colony's omnidirectional_camera sensor). Distance in cm from the
// camera's axis, angle in radians counter-clockwise from the front. As in
// ARGoS the camera starts disabled: until Enable() the list stays empty, and
// while disabled it keeps the last blobs seen and Counter stands still.
#pragma once

#include <iostream>
#include <vector>

#include "argos3/core/control_interface/ci_sensor.h"
#include "argos3/core/utility/datatypes/color.h"
#include "argos3/core/utility/logging/argos_log.h"
#include "argos3/core/utility/math/angles.h"

namespace argos {

class CCI_ColoredBlobOmnidirectionalCameraSensor : public CCI_Sensor {
 public:
  struct SBlob {
    CColor Color = CColor::BLACK;
    CRadians Angle;
    Real Distance = 0;  // cm
    SBlob() = default;
    SBlob(const CColor& color, const CRadians& angle, Real distance)
        : Color(color), Angle(angle), Distance(distance) {}
    friend std::ostream& operator<<(std::ostream& os, const SBlob& blob) {
      return os << "(Color = " << blob.Color << ",Angle = " << ToDegrees(blob.Angle)
                << ",Distance = " << blob.Distance << ")";
    }
  };
  using TBlobList = std::vector<SBlob*>;
  struct SReadings {
    TBlobList BlobList;
    UInt64 Counter = 0;  // updates so far
  };

  ~CCI_ColoredBlobOmnidirectionalCameraSensor() override = default;
  const SReadings& GetReadings() const { return readings_; }

 protected:
  SReadings readings_;
};

}  // namespace argos
