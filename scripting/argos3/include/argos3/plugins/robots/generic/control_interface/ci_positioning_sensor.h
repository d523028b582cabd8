// ARGoS compatibility layer (Colony): the robot's pose in the arena.
// Position in metres (as in ARGoS); orientation a quaternion (on the floor a
// rotation about z: the heading).
#pragma once

#include "argos3/core/control_interface/ci_sensor.h"
#include "argos3/core/utility/math/quaternion.h"
#include "argos3/core/utility/math/vector3.h"

namespace argos {

class CCI_PositioningSensor : public CCI_Sensor {
 public:
  struct SReading {
    CVector3 Position;        // m
    CQuaternion Orientation;  // heading about z
  };

  ~CCI_PositioningSensor() override = default;
  const SReading& GetReading() const { return reading_; }

 protected:
  SReading reading_;
};

}  // namespace argos
