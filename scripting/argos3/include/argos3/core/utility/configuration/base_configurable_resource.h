// ARGoS compatibility layer (Colony): the base of everything configured from
// the experiment file (controllers, loop functions, sensors, actuators).
#pragma once

#include "argos3/core/utility/configuration/argos_configuration.h"

namespace argos {

class CBaseConfigurableResource {
 public:
  virtual ~CBaseConfigurableResource() = default;
  virtual void Init(TConfigurationNode& node) {}
  virtual void Reset() {}
  virtual void Destroy() {}
};

}  // namespace argos
