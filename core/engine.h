// Physics engines (plugin kind "engine"). An engine steps the poses of the
// entities it owns. Each entity type it can simulate has a registered model
// for the (engine, entity type) pair (plugin kind "physics_model", label
// "engine:entity"); a missing pair is a load-time error naming both.
#pragma once

#include <string>

#include "core/config.h"
#include "core/registry.h"
#include "core/space.h"

namespace colony {

class Simulation;

// Engine-specific description of how an entity type is simulated.
class PhysicsModel {
 public:
  virtual ~PhysicsModel() = default;
};

class PhysicsEngine {
 public:
  virtual ~PhysicsEngine() = default;

  // Reads the engine's element in <physics_engines> (attributes already
  // checked against the registered list).
  virtual void Configure(const ConfigNode& node) { (void)node; }
  // Takes the entity in slot `entity` under this engine, simulated by `model`
  // (the model registered for this engine and the entity's type).
  virtual void AddEntity(EntityHandle entity, const PhysicsModel& model) = 0;
  virtual void RemoveEntity(EntityHandle entity) = 0;
  // Advances the owned entities by dt seconds.
  virtual void Step(double dt) = 0;

  // For the host.
  void Bind(Simulation* sim, std::string id, std::string label) {
    sim_ = sim;
    id_ = std::move(id);
    label_ = std::move(label);
  }
  const std::string& id() const { return id_; }
  const std::string& label() const { return label_; }

 protected:
  Simulation& sim() const { return *sim_; }

 private:
  Simulation* sim_ = nullptr;
  std::string id_, label_;
};

}  // namespace colony
