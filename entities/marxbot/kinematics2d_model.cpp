// The marXbot in kinematics2d: a disc of its body's radius driven by its
// treels as a differential drive (engines/kinematics2d).
#include "engines/kinematics2d/kinematics2d.h"

namespace colony {
namespace {

class MarxbotKinematics2dModel : public Kinematics2dDrivenDiscModel {};

COLONY_REGISTER_PHYSICS_MODEL(
    MarxbotKinematics2dModel, "kinematics2d:marxbot",
    "circular footprint moved by its differential drive; stops at obstacles",
    (std::vector<std::string>{"drive"}));

}  // namespace
}  // namespace colony
