// ARGoS compatibility layer (Colony): the wheels. Speeds in cm/s, as in
// ARGoS; Colony's differential_steering actuator receives them in m/s. A
// speed beyond what the robot can do is the actuator's business (see its
// README): this layer converts, it never clamps.
#pragma once

#include "argos3/core/control_interface/ci_actuator.h"

namespace argos {

class CCI_DifferentialSteeringActuator : public CCI_Actuator {
 public:
  ~CCI_DifferentialSteeringActuator() override = default;
  // Left and right wheel speeds (cm/s), positive forwards.
  virtual void SetLinearVelocity(Real left, Real right) = 0;
};

}  // namespace argos
