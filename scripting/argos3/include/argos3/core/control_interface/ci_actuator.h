// ARGoS compatibility layer (Colony): the base of the actuators' control
// interfaces.
#pragma once

#include <map>
#include <string>

#include "argos3/core/utility/configuration/base_configurable_resource.h"
#include "argos3/core/utility/datatypes/datatypes.h"

namespace argos {

class CCI_Actuator : public CBaseConfigurableResource {
 public:
  using TMap = std::map<std::string, CCI_Actuator*>;

  ~CCI_Actuator() override = default;
};

}  // namespace argos
