// ARGoS compatibility layer (Colony): the controller of a robot, as loop
// functions see it.
#pragma once

#include <string>

#include "argos3/core/control_interface/ci_controller.h"

namespace argos {

namespace internal {
struct EntityLink;
}

class CControllableEntity {
 public:
  explicit CControllableEntity(const internal::EntityLink& link) : link_(link) {}
  CControllableEntity(const CControllableEntity&) = delete;
  CControllableEntity& operator=(const CControllableEntity&) = delete;

  // The robot's ARGoS controller (cast it to its class with dynamic_cast).
  // Throws CARGoSException when the robot runs a controller that is not an
  // ARGoS one (a Colony or Lua controller) or was removed.
  CCI_Controller& GetController();
  const std::string& GetId() const;

 private:
  const internal::EntityLink& link_;
};

}  // namespace argos
