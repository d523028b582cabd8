// ARGoS compatibility layer (Colony): the space as ARGoS loop functions see
// it: the robots by type, the clock and the arena. GetEntitiesByType serves
// "foot-bot" (Colony's marxbot; "marxbot" is accepted too); other entity
// types (boxes, lights, cylinders, other robots) are not provided and throw
// CARGoSException naming the type.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "argos3/core/utility/datatypes/any.h"
#include "argos3/core/utility/datatypes/datatypes.h"
#include "argos3/core/utility/math/range.h"
#include "argos3/core/utility/math/vector3.h"
#include "argos3/plugins/robots/foot-bot/simulator/footbot_entity.h"

namespace argos {

class CSpace {
 public:
  using TMapPerType = std::map<std::string, CAny>;

  // For the loop functions' host.
  explicit CSpace(colony::Simulation& simulation);
  ~CSpace();
  CSpace(const CSpace&) = delete;
  CSpace& operator=(const CSpace&) = delete;

  // Entity id -> CFootBotEntity* (read with any_cast<CFootBotEntity*>), for
  // the robots alive now, by id. The pointers stay valid as long as the
  // robot lives.
  TMapPerType& GetEntitiesByType(const std::string& type);
  const TMapPerType& GetEntitiesByType(const std::string& type) const;

  // Ticks since the start.
  UInt32 GetSimulationClock() const;
  const CVector3& GetArenaSize() const { return arena_size_; }      // m
  const CVector3& GetArenaCenter() const { return arena_center_; }  // m
  const CRange<CVector3>& GetArenaLimits() const { return arena_limits_; }

 private:
  void Refresh() const;

  colony::Simulation& simulation_;
  CVector3 arena_size_, arena_center_;
  CRange<CVector3> arena_limits_;
  mutable std::vector<std::unique_ptr<CFootBotEntity>> footbots_;  // by slot
  mutable std::vector<UInt32> generations_;                        // of each view, by slot
  mutable TMapPerType footbot_map_;
  mutable std::vector<UInt32> listed_;  // slots in footbot_map_
};

}  // namespace argos
