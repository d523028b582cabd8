// ARGoS compatibility layer (Colony): the foot-bot's ring of 24 proximity
// sensors (Colony's proximity sensor). Value 0 when nothing is in range,
// rising as an obstacle nears, 1 in contact; Angle of the sensor in the
// robot's frame, counter-clockwise from the front (radians).
#pragma once

#include <iostream>
#include <vector>

#include "argos3/core/control_interface/ci_sensor.h"
#include "argos3/core/utility/math/angles.h"

namespace argos {

class CCI_FootBotProximitySensor : public CCI_Sensor {
 public:
  struct SReading {
    Real Value = 0;
    CRadians Angle;
    SReading() = default;
    SReading(Real value, const CRadians& angle) : Value(value), Angle(angle) {}
  };
  using TReadings = std::vector<SReading>;

  ~CCI_FootBotProximitySensor() override = default;
  const TReadings& GetReadings() const { return readings_; }

 protected:
  TReadings readings_;
};

std::ostream& operator<<(std::ostream& os, const CCI_FootBotProximitySensor::SReading& reading);
std::ostream& operator<<(std::ostream& os, const CCI_FootBotProximitySensor::TReadings& readings);

}  // namespace argos
