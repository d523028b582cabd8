// Boxes and cylinders in dynamics2d (engines/dynamics2d): pushed against
// floor friction if movable, static bodies otherwise.
#include <vector>

#include "engines/dynamics2d/dynamics2d.h"

namespace colony {
namespace {

class SlidingModel : public Dynamics2dModel {
 public:
  void Add(Engine& engine, uint32_t s) override { engine.AddFloorFriction(s); }
};

COLONY_REGISTER_PHYSICS_MODEL(SlidingModel, "dynamics2d:box",
                              "box: pushed against floor friction if movable, static otherwise",
                              (std::vector<std::string>{}));
COLONY_REGISTER_PHYSICS_MODEL(
    SlidingModel, "dynamics2d:cylinder",
    "cylinder: pushed against floor friction if movable, static otherwise",
    (std::vector<std::string>{}));

}  // namespace
}  // namespace colony
