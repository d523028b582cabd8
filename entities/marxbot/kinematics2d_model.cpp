// The marXbot in kinematics2d: a disc of its body's radius driven by its
// treels as a differential drive (engines/kinematics2d). With
// manipulator="true" it also simulates the construction manipulator,
// kinematically, after the discs moved (manipulator2d.h); a pocket it
// carries is marked carried, so it blocks no robot.
#include <string_view>
#include <vector>

#include "engines/kinematics2d/kinematics2d.h"
#include "entities/marxbot/manipulator2d.h"

namespace colony {
namespace {

class MarxbotKinematics2dModel : public Kinematics2dDrivenDiscModel {
 public:
  void Add(kinematics2d::Engine& engine, uint32_t s) override {
    manipulator_.Add(engine.entities(), s);
  }
  void EntityLeaving(kinematics2d::Engine& engine, uint32_t s) override {
    manipulator_.Leaving(engine.entities(), s, Carried(engine));
  }
  void AfterStep(kinematics2d::Engine& engine, double dt) override {
    manipulator_.Step(engine.entities(), dt, Carried(engine));
  }
  bool Anchor(const Space& space, uint32_t s, std::string_view name, Pose& pose) const override {
    return Manipulator2d::Anchor(space, s, name, pose);
  }

 private:
  static Manipulator2d::CarriedHook Carried(kinematics2d::Engine& engine) {
    return [&engine](uint32_t s, bool carried) { engine.SetCarried(s, carried); };
  }

  Manipulator2d manipulator_;
};

COLONY_REGISTER_PHYSICS_MODEL(
    MarxbotKinematics2dModel, "kinematics2d:marxbot",
    "circular footprint moved by its differential drive; stops at obstacles; with "
    "manipulator=\"true\" a kinematic head (elevation, rotation, tilt) whose magnet carries "
    "pockets",
    (std::vector<std::string>{"drive", "manipulator"}));

}  // namespace
}  // namespace colony
