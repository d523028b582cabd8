// ARGoS compatibility layer (Colony): one LED of a robot, as loop functions
// see it.
#pragma once

#include "argos3/core/utility/datatypes/color.h"

namespace argos {

class CLEDEntity {
 public:
  // The colour the LED shows now.
  const CColor& GetColor() const { return color_; }

 private:
  friend class CLEDEquippedEntity;
  CColor color_;
};

}  // namespace argos
