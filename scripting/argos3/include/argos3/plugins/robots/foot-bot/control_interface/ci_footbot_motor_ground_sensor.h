// ARGoS compatibility layer (Colony): the foot-bot's 4 ground sensors under
// its motors, in ARGoS's order and offsets (cm, robot frame): 0 front-left
// (6.3, 1.16), 1 back-left (-6.3, 1.16), 2 back-right (-6.3, -1.16), 3
// front-right (6.3, -1.16). Value: the floor's grey level, 0 black .. 1
// white. Colony's ground sensor supplies them: when its sensors are not at
// these points (the marXbot's are 8, on a 6.5 cm circle), each reading is
// that of Colony's sensor nearest in direction (front or back for all four).
#pragma once

#include <iostream>
#include <vector>

#include "argos3/core/control_interface/ci_sensor.h"
#include "argos3/core/utility/math/range.h"
#include "argos3/core/utility/math/vector2.h"

namespace argos {

class CCI_FootBotMotorGroundSensor : public CCI_Sensor {
 public:
  struct SReading {
    Real Value = 0;
    CVector2 Offset;  // cm
    SReading() = default;
    SReading(Real value, const CVector2& offset) : Value(value), Offset(offset) {}
  };
  using TReadings = std::vector<SReading>;

  CCI_FootBotMotorGroundSensor()
      : readings_{SReading(0, CVector2(6.3, 1.16)), SReading(0, CVector2(-6.3, 1.16)),
                  SReading(0, CVector2(-6.3, -1.16)), SReading(0, CVector2(6.3, -1.16))} {}
  ~CCI_FootBotMotorGroundSensor() override = default;
  const TReadings& GetReadings() const { return readings_; }

 protected:
  TReadings readings_;
};

std::ostream& operator<<(std::ostream& os, const CCI_FootBotMotorGroundSensor::SReading& reading);
std::ostream& operator<<(std::ostream& os, const CCI_FootBotMotorGroundSensor::TReadings& readings);

}  // namespace argos
