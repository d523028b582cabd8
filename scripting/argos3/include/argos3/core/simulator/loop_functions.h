// ARGoS compatibility layer (Colony): the base of ARGoS loop functions.
// Subclass it as in ARGoS and register it with REGISTER_LOOP_FUNCTIONS(CLASS,
// "label"); Colony runs it as loop functions of that label. Init gets the
// configuration tree of <loop_functions> (its <params> attributes, and
// dotted parameter names as child nodes); PreStep and PostStep run each tick
// around sense + control; IsExperimentFinished ends the run; PostExperiment
// and Destroy run when the run ends. Colony never resets a run, so Reset is
// not called. A class that overrides GetFloorColor colours the floor of an
// arena with <floor source="loop_functions" pixels_per_meter="...">: Colony
// samples it once, after Init, at the centre of every pixel (ARGoS's
// CFloorEntity::SetChanged, to repaint it while running, is not provided).
#pragma once

#include <memory>
#include <vector>

#include "argos3/core/simulator/space/space.h"
#include "argos3/core/utility/configuration/argos_configuration.h"
#include "argos3/core/utility/configuration/base_configurable_resource.h"
#include "argos3/core/utility/datatypes/color.h"
#include "argos3/core/utility/logging/argos_log.h"
#include "argos3/core/utility/math/rng.h"
#include "argos3/core/utility/math/vector2.h"
#include "argos3/core/utility/math/vector3.h"
#include "argos3/plugins/robots/foot-bot/simulator/footbot_entity.h"

namespace argos {

namespace internal {
class LoopFunctionsHost;
}

class CLoopFunctions : public CBaseConfigurableResource {
 public:
  ~CLoopFunctions() override;
  void Init(TConfigurationNode& node) override {}
  void Reset() override {}
  void Destroy() override {}
  virtual void PreStep() {}
  virtual void PostStep() {}
  virtual bool IsExperimentFinished() { return false; }
  virtual void PostExperiment() {}
  // The floor's colour at a point (m); see above.
  virtual CColor GetFloorColor(const CVector2& position) { return CColor::BLACK; }

  CSpace& GetSpace() { return *space_; }
  const CSpace& GetSpace() const { return *space_; }

 private:
  friend class internal::LoopFunctionsHost;
  CSpace* space_ = nullptr;
};

}  // namespace argos

#include "argos3/colony/loop_functions_host.h"

// REGISTER_LOOP_FUNCTIONS(CForagingLoopFunctions, "foraging_loop_functions"):
// <loop_functions label="..."> runs CLASSNAME. As in ARGoS, no semicolon is
// needed after it.
#define REGISTER_LOOP_FUNCTIONS(CLASSNAME, LABEL)                      \
  COLONY_REGISTER_LOOP_FUNCTIONS(                                      \
      ::argos::internal::LoopFunctionsHostFor<CLASSNAME>, LABEL,       \
      "ARGoS loop functions " #CLASSNAME " (C++ compatibility layer)", \
      {{"*", "any parameter", "", "ARGoS loop functions read their own parameters"}});
