// ARGoS compatibility layer (Colony): the base of an ARGoS robot controller.
// Subclass it as in ARGoS and register it with REGISTER_CONTROLLER(CLASS,
// "label"); Colony then runs it as a controller plugin of that label
// (build it with colony_add_plugin and link Colony::argos3).
//
// GetSensor<T>("footbot_proximity") and GetActuator<T>(...) find a device
// declared in the experiment file by its element name, by the Colony device
// it stands for ("proximity"), or, in a file written with Colony's names, by
// ARGoS's name of that device. Each step the sensors the controller asked for
// are read before ControlStep, in ARGoS's units (cm where ARGoS uses cm);
// actuator commands take effect at the next tick, as in ARGoS.
#pragma once

#include <memory>
#include <string>
#include <typeinfo>

#include "argos3/core/control_interface/ci_actuator.h"
#include "argos3/core/control_interface/ci_sensor.h"
#include "argos3/core/utility/configuration/argos_configuration.h"
#include "argos3/core/utility/configuration/argos_exception.h"
#include "argos3/core/utility/configuration/base_configurable_resource.h"
#include "argos3/core/utility/datatypes/datatypes.h"
#include "argos3/core/utility/logging/argos_log.h"

namespace argos {

namespace internal {
class ControllerHost;
}

class CCI_Controller : public CBaseConfigurableResource {
 public:
  ~CCI_Controller() override;
  void Init(TConfigurationNode& node) override {}
  virtual void ControlStep() {}
  void Reset() override {}
  void Destroy() override {}

  // The robot's id, as in the experiment file.
  const std::string& GetId() const;

  // The actuator declared as `label`; throws CARGoSException when there is
  // none or it is not an ACTUATOR_IMPL.
  template <typename ACTUATOR_IMPL>
  ACTUATOR_IMPL* GetActuator(const std::string& label) {
    if (auto* typed = dynamic_cast<ACTUATOR_IMPL*>(FindActuator(label))) return typed;
    THROW_ARGOSEXCEPTION("Actuator type " << label << " cannot be cast to type "
                                          << internal::TypeName(typeid(ACTUATOR_IMPL)));
  }
  // The sensor declared as `label`; throws CARGoSException when there is
  // none or it is not a SENSOR_IMPL.
  template <typename SENSOR_IMPL>
  SENSOR_IMPL* GetSensor(const std::string& label) {
    if (auto* typed = dynamic_cast<SENSOR_IMPL*>(FindSensor(label, typeid(SENSOR_IMPL))))
      return typed;
    THROW_ARGOSEXCEPTION("Sensor type " << label << " cannot be cast to type "
                                        << internal::TypeName(typeid(SENSOR_IMPL)));
  }
  bool HasActuator(const std::string& label) const;
  bool HasSensor(const std::string& label) const;

 private:
  friend class internal::ControllerHost;
  CCI_Sensor* FindSensor(const std::string& label, const std::type_info& wanted);
  CCI_Actuator* FindActuator(const std::string& label);

  internal::ControllerHost* host_ = nullptr;
};

}  // namespace argos

#include "argos3/colony/controller_host.h"

// REGISTER_CONTROLLER(CFootBotDiffusion, "footbot_diffusion_controller"):
// the controller element of that name in an experiment file runs CLASSNAME.
// As in ARGoS, no semicolon is needed after it.
#define REGISTER_CONTROLLER(CLASSNAME, LABEL)                      \
  COLONY_REGISTER_CONTROLLER(                                      \
      ::argos::internal::ControllerHostFor<CLASSNAME>, LABEL,      \
      "ARGoS controller " #CLASSNAME " (C++ compatibility layer)", \
      {{"*", "any name", "", "read by the controller's Init (TConfigurationNode)"}});
