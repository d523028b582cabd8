// The eye-bot in pointmass3d (engines/pointmass3d): a point mass at its feet
// flown by its flight computer (flight.h), an upright cylinder of its
// geometry for collisions, level at all times; it holds to the ceiling when
// its attachment asks and its top touches. The pan-tilt unit is turned by
// its actuators; the model gives its frame (anchor "pan_tilt"), where the
// camera mounts.
#include <string_view>

#include "core/space.h"
#include "engines/pointmass3d/pointmass3d.h"
#include "entities/eyebot/eyebot.h"

namespace colony {
namespace {

class EyebotPointmass3dModel : public Pointmass3dFlyerModel {
 public:
  bool Anchor(const Space& space, uint32_t slot, std::string_view name, Pose& pose) const override {
    return PanTiltAnchor(space, slot, name, pose);
  }
};

COLONY_REGISTER_PHYSICS_MODEL(
    EyebotPointmass3dModel, "pointmass3d:eyebot",
    "point mass flown by its flight computer, level, upright cylinder for collisions; holds to "
    "the ceiling; anchor pan_tilt",
    (std::vector<std::string>{"quadrotor", "ceiling_attachment", "pan_tilt"}));

}  // namespace
}  // namespace colony
