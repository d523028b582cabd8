// Objects in kinematics2d: fixed obstacles, movable or not (robots stop at
// them and do not push them; engines/kinematics2d). Pockets too: they move
// only when a manipulator carries them.
#include "engines/kinematics2d/kinematics2d.h"

namespace colony {
namespace {

class ObjectKinematics2dModel : public Kinematics2dObstacleModel {};

COLONY_REGISTER_PHYSICS_MODEL(ObjectKinematics2dModel, "kinematics2d:box",
                              "fixed obstacle, movable or not (not pushed in this engine)", {});
COLONY_REGISTER_PHYSICS_MODEL(ObjectKinematics2dModel, "kinematics2d:cylinder",
                              "fixed obstacle, movable or not (not pushed in this engine)", {});
COLONY_REGISTER_PHYSICS_MODEL(ObjectKinematics2dModel, "kinematics2d:landmark",
                              "fixed obstacle: an upright cylinder", {});
COLONY_REGISTER_PHYSICS_MODEL(ObjectKinematics2dModel, "kinematics2d:pocket",
                              "obstacle robots stop at, never pushed; lies where it was put down",
                              {});

}  // namespace
}  // namespace colony
