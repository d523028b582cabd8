// The external controller: robots driven from outside the simulation, e.g.
// from Python between ticks (sim.actuators["differential_steering"].set,
// docs/python.md). It declares sensors and actuators like any controller and
// its step does nothing: the commands its actuators hold when a tick's act
// phase runs are the last ones the program set, and its sensors are read
// every tick for the program to look at.
#include "core/control_interface.h"
#include "core/registry.h"

namespace {

class ExternalController : public colony::Controller {
 public:
  void ControlStep() override {}
};

COLONY_REGISTER_CONTROLLER(
    ExternalController, "external_controller",
    "does nothing itself: the program that steps the simulation (Python: sim.actuators) sets "
    "the robots' actuators between ticks and reads their sensors",
    {});

}  // namespace
