// ARGoS compatibility layer (Colony): the wheel encoders (Colony's
// wheel_encoders sensor, which ARGoS's differential_steering sensor stands
// for). Distances in cm. Colony's encoders measure distances only, so the
// wheel velocities of ARGoS's reading are not provided (VelocityLeftWheel and
// VelocityRightWheel do not exist: code reading them does not compile).
#pragma once

#include "argos3/core/control_interface/ci_sensor.h"

namespace argos {

class CCI_DifferentialSteeringSensor : public CCI_Sensor {
 public:
  struct SReading {
    Real CoveredDistanceLeftWheel = 0;   // cm moved during the last tick, negative backwards
    Real CoveredDistanceRightWheel = 0;  // cm
    Real WheelAxisLength = 0;            // cm between the wheels
  };

  ~CCI_DifferentialSteeringSensor() override = default;
  const SReading& GetReading() const { return reading_; }

 protected:
  SReading reading_;
};

}  // namespace argos
