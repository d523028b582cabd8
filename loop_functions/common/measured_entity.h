// The entity a loop function measures (construction_metrics' robot,
// handbot_shelf's hand-bot): the one its parameter `key` names, or, without
// that parameter, the only entity of the arena that `wanted` accepts.
// Problems are ParamErrors naming the parameter.
#pragma once

#include <string>

#include "core/control_interface.h"
#include "core/space.h"

namespace colony {

// `what` names the kind in messages ("robot", "hand-bot").
template <class Wanted>
EntityHandle FindMeasured(const Space& space, const Params& params, const std::string& key,
                          const std::string& what, Wanted wanted) {
  const std::string prefix = "parameter '" + key + "': ";
  if (params.Has(key)) {
    const std::string id = params.GetString(key);
    const EntityHandle h = space.Find(id);
    if (!h.valid()) throw ParamError(key, id, prefix + "no entity '" + id + "' in the arena");
    return h;
  }
  EntityHandle found;
  for (uint32_t s = 0; s < space.slots(); ++s) {
    if (!space.alive(s) || !wanted(s)) continue;
    if (found.valid()) {
      throw ParamError(key, "",
                       prefix + "the arena has several " + what + "s; say which one is measured");
    }
    found = space.HandleOf(s);
  }
  if (!found.valid()) throw ParamError(key, "", prefix + "the arena has no " + what);
  return found;
}

}  // namespace colony
