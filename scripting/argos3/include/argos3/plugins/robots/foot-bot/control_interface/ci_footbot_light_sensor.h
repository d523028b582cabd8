// ARGoS compatibility layer (Colony): the foot-bot's ring of light sensors
// (Colony's light sensor). Value 0 when no light is seen, larger with more
// light; Angle of the sensor in the robot's frame (radians).
#pragma once

#include <iostream>
#include <vector>

#include "argos3/core/control_interface/ci_sensor.h"
#include "argos3/core/utility/math/angles.h"

namespace argos {

class CCI_FootBotLightSensor : public CCI_Sensor {
 public:
  struct SReading {
    Real Value = 0;
    CRadians Angle;
    SReading() = default;
    SReading(Real value, const CRadians& angle) : Value(value), Angle(angle) {}
  };
  using TReadings = std::vector<SReading>;

  ~CCI_FootBotLightSensor() override = default;
  const TReadings& GetReadings() const { return readings_; }

 protected:
  TReadings readings_;
};

std::ostream& operator<<(std::ostream& os, const CCI_FootBotLightSensor::SReading& reading);
std::ostream& operator<<(std::ostream& os, const CCI_FootBotLightSensor::TReadings& readings);

}  // namespace argos
