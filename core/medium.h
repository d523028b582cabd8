// Media (plugin kind "medium"): the elements of <media>. A medium carries what
// robots show or say to each other (LEDs for cameras, range-and-bearing
// messages) and keeps its own index of it, rebuilt once per tick after
// physics and the space's index (tick step 3), so that a query costs what is
// near, not what exists. Sensors and actuators find their medium through
// Simulation::MediumFor (attribute medium="id" on the device element).
#pragma once

#include <string>

#include "core/config.h"
#include "core/registry.h"
#include "core/simulation_bound.h"

namespace colony {

class Simulation;

class Medium : public NamedSimulationBound {
 public:
  virtual ~Medium() = default;
  // Reads the medium's element (attributes already checked against the
  // registered list). Called before the controllers and the arena are built.
  virtual void Configure(const ConfigNode& node) { (void)node; }
  // Rebuilds the medium's index from the space and what actuators wrote
  // during this tick's act step. Called once per tick, from the main thread,
  // after physics and the space's index; it may use sim().pool().
  virtual void Update() = 0;
};

// COLONY_REGISTER_MEDIUM(MyMedium, "label", "summary", {{"attribute", "accepted", "default",
// "doc"}});
#define COLONY_REGISTER_MEDIUM(CLASS, LABEL, SUMMARY, ...)                               \
  COLONY_REGISTER_PLUGIN_(::colony::Medium, ::colony::PluginKind::kMedium, CLASS, LABEL, \
                          "default", SUMMARY, __VA_ARGS__)

}  // namespace colony
