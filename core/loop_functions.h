// Loop functions (plugin kind "loop_functions"): experiment hooks run every
// tick before and after sense + control, with access to the whole
// simulation: metrics, spawning and removing entities, stop conditions.
#pragma once

#include "core/color.h"
#include "core/control_interface.h"
#include "core/drawing.h"
#include "core/registry.h"
#include "core/simulation_bound.h"
#include "core/space.h"

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
  // Called by Simulation::Reset on the new loop functions it built and
  // Init'ed, after every controller's Reset (as ARGoS calls it on reset).
  // Reset rebuilds the loop functions, so nothing is kept from before it;
  // Reset() must leave them as Init did, or the run differs from a fresh
  // load's (docs/embedding.md).
  virtual void Reset() {}
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
  // Shapes drawn in the world for whoever watches (as ARGoS's DrawInWorld):
  // points, lines, circles and text at world coordinates (core/drawing.h),
  // shown by the live viewer and in rendered frames. Called between ticks,
  // on the thread that steps, only when something shows them: once per
  // frame a viewer sends or a renderer draws, never in a run nobody
  // watches. `list` is empty on entry; what is added replaces the last
  // call's. It must not change the simulation (draw no random numbers,
  // move nothing): a drawn run's results are the undrawn run's.
  virtual void Draw(DrawList& list) const { (void)list; }
  // Per-robot columns of the per-robot table (<output trajectories_every>;
  // see RobotValues in core/control_interface.h): called for every robot
  // on the ticks the table records, after its controller's RecordValues.
  // It must not change the simulation. Loop functions write tables of their
  // own into the run folder with core/table_writer.h.
  virtual void RecordRobotValues(EntityHandle robot, RobotValues& values) {
    (void)robot;
    (void)values;
  }
};

}  // namespace colony
