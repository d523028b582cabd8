// ARGoS compatibility layer (Colony): CAny, the value type of CSpace's entity
// maps, read with any_cast<CFootBotEntity*>(...). It is std::any.
#pragma once

#include <any>

namespace argos {

using CAny = std::any;
using std::any_cast;

}  // namespace argos
