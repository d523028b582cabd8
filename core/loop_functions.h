// Loop functions (plugin kind "loop_functions"): experiment hooks run every
// tick before and after sense + control, with access to the whole
// simulation: metrics, spawning and removing entities, stop conditions.
#pragma once

#include "core/color.h"
#include "core/control_interface.h"
#include "core/registry.h"
#include "core/simulation_bound.h"

namespace colony {

class Simulation;

class LoopFunctions : public SimulationBound {
 public:
  virtual ~LoopFunctions() = default;
  // Called once after the arena is built, with the <loop_functions> params.
  virtual void Init(const Params& params) { (void)params; }
  virtual void PreStep() {}
  virtual void PostStep() {}
  // Ends the run early when true.
  virtual bool IsExperimentFinished() { return false; }
  // Loop functions that colour the floor (<floor source="loop_functions"
  // pixels_per_meter=...>, as ARGoS's GetFloorColor) return true from
  // DrawsFloor; FloorColor is then sampled once after Init, at the centre of
  // every pixel, and ground sensors and renderers see that image.
  virtual bool DrawsFloor() const { return false; }
  virtual Color FloorColor(double x, double y) {
    (void)x;
    (void)y;
    return Color::White();
  }
  virtual void Destroy() {}
};

}  // namespace colony
