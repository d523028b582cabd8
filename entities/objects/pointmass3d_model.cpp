// Objects in pointmass3d: fixed obstacles, movable or not (flyers land on
// them and stop at them; nothing pushes them; engines/pointmass3d).
#include "engines/pointmass3d/pointmass3d.h"

namespace colony {
namespace {

class ObjectPointmass3dModel : public Pointmass3dObstacleModel {};

COLONY_REGISTER_PHYSICS_MODEL(ObjectPointmass3dModel, "pointmass3d:box",
                              "fixed obstacle, movable or not (not pushed in this engine)", {});
COLONY_REGISTER_PHYSICS_MODEL(ObjectPointmass3dModel, "pointmass3d:cylinder",
                              "fixed obstacle, movable or not (not pushed in this engine)", {});
COLONY_REGISTER_PHYSICS_MODEL(ObjectPointmass3dModel, "pointmass3d:landmark",
                              "fixed obstacle: an upright cylinder", {});
COLONY_REGISTER_PHYSICS_MODEL(ObjectPointmass3dModel, "pointmass3d:pocket",
                              "obstacle, never pushed; lies where it was put down", {});

}  // namespace
}  // namespace colony
