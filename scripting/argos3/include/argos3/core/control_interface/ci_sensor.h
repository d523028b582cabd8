// ARGoS compatibility layer (Colony): the base of the sensors' control
// interfaces. Sensors are enabled from the start, except the coloured-blob
// camera, which (as in ARGoS) sees nothing until Enable() is called.
#pragma once

#include <map>
#include <string>

#include "argos3/core/utility/configuration/base_configurable_resource.h"
#include "argos3/core/utility/datatypes/datatypes.h"

namespace argos {

class CCI_Sensor : public CBaseConfigurableResource {
 public:
  using TMap = std::map<std::string, CCI_Sensor*>;

  ~CCI_Sensor() override = default;
  virtual void Enable() { enabled_ = true; }
  virtual void Disable() { enabled_ = false; }
  bool IsEnabled() const { return enabled_; }
  bool IsDisabled() const { return !enabled_; }

 private:
  bool enabled_ = true;
};

}  // namespace argos
