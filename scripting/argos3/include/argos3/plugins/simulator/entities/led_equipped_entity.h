// ARGoS compatibility layer (Colony): a robot's LEDs, as loop functions see
// them (read-only: controllers set them).
#pragma once

#include "argos3/core/utility/datatypes/datatypes.h"
#include "argos3/plugins/simulator/entities/led_entity.h"

namespace argos {

namespace internal {
struct EntityLink;
}

class CLEDEquippedEntity {
 public:
  explicit CLEDEquippedEntity(const internal::EntityLink& link) : link_(link) {}
  CLEDEquippedEntity(const CLEDEquippedEntity&) = delete;
  CLEDEquippedEntity& operator=(const CLEDEquippedEntity&) = delete;

  // LED `index` (foot-bot: 0..11 the ring, 12 the beacon), its colour read
  // now; throws CARGoSException beyond the last.
  CLEDEntity& GetLED(UInt32 index);

 private:
  const internal::EntityLink& link_;
  CLEDEntity led_;
};

}  // namespace argos
