// The simulation a plugin object (sensor and actuator systems, engines,
// media, loop functions, renderers) belongs to: set once by the host with
// Bind, read by the plugin through sim().
#pragma once

#include <string>
#include <utility>

namespace colony {

class Simulation;

class SimulationBound {
 public:
  // For the host.
  void Bind(Simulation* sim) { sim_ = sim; }

 protected:
  Simulation& sim() const { return *sim_; }

 private:
  Simulation* sim_ = nullptr;
};

// A bound plugin object that the experiment file names: its id and label
// (engines, media).
class NamedSimulationBound : public SimulationBound {
 public:
  // For the host.
  void Bind(Simulation* sim, std::string id, std::string label) {
    SimulationBound::Bind(sim);
    id_ = std::move(id);
    label_ = std::move(label);
  }
  const std::string& id() const { return id_; }
  const std::string& label() const { return label_; }

 private:
  std::string id_, label_;
};

}  // namespace colony
