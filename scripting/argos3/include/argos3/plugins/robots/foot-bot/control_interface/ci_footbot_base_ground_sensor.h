// ARGoS compatibility layer (Colony): the foot-bot's 8 black-and-white
// ground sensors around its base, in ARGoS's order and offsets (cm, robot
// frame, counter-clockwise from the front on an 8 cm circle). Value 0 on a
// dark floor (grey level below 0.5), 1 on a light one. Colony's ground
// sensor supplies them: each reading is that of Colony's sensor nearest in
// direction (the marXbot has 8, 45 degrees apart on a 6.5 cm circle).
#pragma once

#include <iostream>
#include <vector>

#include "argos3/core/control_interface/ci_sensor.h"
#include "argos3/core/utility/math/vector2.h"

namespace argos {

class CCI_FootBotBaseGroundSensor : public CCI_Sensor {
 public:
  struct SReading {
    Real Value = 0;
    CVector2 Offset;  // cm
    SReading() = default;
    SReading(Real value, const CVector2& offset) : Value(value), Offset(offset) {}
  };
  using TReadings = std::vector<SReading>;

  CCI_FootBotBaseGroundSensor()
      : readings_{SReading(0, CVector2(8.0, 0.0)),  SReading(0, CVector2(4.2, 6.5)),
                  SReading(0, CVector2(0.0, 8.0)),  SReading(0, CVector2(-4.2, 6.5)),
                  SReading(0, CVector2(-8.0, 0.0)), SReading(0, CVector2(-4.2, -6.5)),
                  SReading(0, CVector2(0.0, -8.0)), SReading(0, CVector2(4.2, -6.5))} {}
  ~CCI_FootBotBaseGroundSensor() override = default;
  const TReadings& GetReadings() const { return readings_; }

 protected:
  TReadings readings_;
};

std::ostream& operator<<(std::ostream& os, const CCI_FootBotBaseGroundSensor::SReading& reading);
std::ostream& operator<<(std::ostream& os, const CCI_FootBotBaseGroundSensor::TReadings& readings);

}  // namespace argos
