// ARGoS compatibility layer (Colony): the body of an entity, as loop
// functions see it. Only the origin anchor is provided: the centre of the
// body's base, in metres, and its orientation, read from Colony's space when
// asked.
#pragma once

#include <string>

#include "argos3/core/utility/math/quaternion.h"
#include "argos3/core/utility/math/vector3.h"

namespace argos {

namespace internal {
struct EntityLink;
}

struct SAnchor {
  std::string Id;
  CVector3 Position;        // m
  CQuaternion Orientation;  // on the floor: the heading, about z
};

class CEmbodiedEntity {
 public:
  explicit CEmbodiedEntity(const internal::EntityLink& link) : link_(link) {}
  CEmbodiedEntity(const CEmbodiedEntity&) = delete;
  CEmbodiedEntity& operator=(const CEmbodiedEntity&) = delete;

  // The pose now. Throws CARGoSException when the entity was removed.
  const SAnchor& GetOriginAnchor() const;

 private:
  const internal::EntityLink& link_;
  mutable SAnchor origin_;
};

}  // namespace argos
