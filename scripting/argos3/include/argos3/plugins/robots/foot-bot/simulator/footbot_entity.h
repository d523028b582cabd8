// ARGoS compatibility layer (Colony): a foot-bot (Colony's marxbot) as loop
// functions see it through CSpace::GetEntitiesByType("foot-bot"): its id, its
// body's pose, its controller and its LEDs.
#pragma once

#include <string>

#include "argos3/core/simulator/entity/controllable_entity.h"
#include "argos3/core/simulator/entity/embodied_entity.h"
#include "argos3/plugins/simulator/entities/led_equipped_entity.h"

namespace colony {
class Simulation;
}

namespace argos {

namespace internal {
// Which robot of which simulation an entity view stands for.
struct EntityLink {
  colony::Simulation* simulation = nullptr;
  UInt32 index = 0;
  UInt32 generation = 0;
  std::string id;
};
}  // namespace internal

class CFootBotEntity {
 public:
  explicit CFootBotEntity(internal::EntityLink link)
      : link_(std::move(link)), body_(link_), controllable_(link_), leds_(link_) {}
  CFootBotEntity(const CFootBotEntity&) = delete;
  CFootBotEntity& operator=(const CFootBotEntity&) = delete;

  const std::string& GetId() const { return link_.id; }
  CEmbodiedEntity& GetEmbodiedEntity() { return body_; }
  CControllableEntity& GetControllableEntity() { return controllable_; }
  CLEDEquippedEntity& GetLEDEquippedEntity() { return leds_; }

 private:
  internal::EntityLink link_;
  CEmbodiedEntity body_;
  CControllableEntity controllable_;
  CLEDEquippedEntity leds_;
};

}  // namespace argos
