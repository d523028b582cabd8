// Simulated eye-bot ceiling attachment actuator: writes the request into the
// robot's CeilingAttachmentState; the physics model takes hold when the top
// of the body touches the ceiling, and lets go when asked (pointmass3d,
// dynamics3d).
#include <string>
#include <vector>

#include "actuators/eyebot_ceiling/eyebot_ceiling.h"
#include "core/device.h"
#include "core/simulation.h"
#include "entities/eyebot/eyebot.h"

namespace colony {
namespace {

struct CeilingInstance : EyebotCeilingActuator, InstanceBase {
  using Interface = EyebotCeilingActuator;
};

class EyebotCeilingSystem : public ActuatorSystem {
 public:
  void Configure(const ConfigNode&) override {}
  std::vector<std::string> NeededComponents() const override {
    return {CeilingAttachmentState::kComponentName};
  }
  Actuator* Attach(EntityHandle robot, const RandomStream& rng) override {
    CeilingInstance& a = instances_.Add(robot, rng);
    // A robot that starts attached (attached="true") keeps holding until
    // told to let go.
    if (sim().space().Get<CeilingAttachmentState>(robot.index)->attach) a.Attach();
    return &a;
  }
  void Detach(Actuator* a) override { instances_.Remove(static_cast<EyebotCeilingActuator*>(a)); }
  size_t size() const override { return instances_.size(); }
  void Act(size_t begin, size_t end) override {
    Space& space = sim().space();
    for (size_t k = begin; k < end; ++k) {
      CeilingInstance& a = instances_[k];
      if (!a.alive) continue;
      space.Get<CeilingAttachmentState>(a.robot.index)->attach = a.attach_requested();
    }
  }

 private:
  InstanceStore<CeilingInstance> instances_;
};

COLONY_REGISTER_ACTUATOR(
    EyebotCeilingSystem, "eyebot_ceiling", "default",
    "the eye-bot's ceiling attachment: hold on to the ceiling once the top "
    "of the body touches it (rotors off), or let go",
    DeviceInterface{"actuators/eyebot_ceiling/eyebot_ceiling.h",
                    "colony::EyebotCeilingActuator",
                    {"Attach(): hold on once the top of the body touches the ceiling (rotors off)",
                     "Detach(): let go", "attach_requested(): whether Attach is in force"}},
    (std::vector<AttributeDoc>{}));

}  // namespace
}  // namespace colony
