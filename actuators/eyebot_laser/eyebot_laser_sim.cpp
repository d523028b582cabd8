// Simulated eye-bot laser actuator: switches the laser pointer of the
// robot's PanTiltState; the LED medium and the renderers find its spot
// (CastLaser, entities/eyebot/laser.cpp).
#include <string>

#include "actuators/eyebot_laser/eyebot_laser.h"
#include "core/device.h"
#include "core/simulation.h"
#include "entities/eyebot/eyebot.h"

namespace colony {
namespace {

struct LaserInstance : EyebotLaserActuator, InstanceBase {
  using Interface = EyebotLaserActuator;
};

class LaserSystem : public ActuatorSystem {
 public:
  void Configure(const ConfigNode&) override {}
  std::vector<std::string> NeededComponents() const override {
    return {PanTiltState::kComponentName};
  }
  Actuator* Attach(EntityHandle robot, const RandomStream& rng) override {
    LaserInstance& a = instances_.Add(robot, rng);
    a.Set(sim().space().Get<PanTiltState>(robot.index)->laser_on);
    return &a;
  }
  void Detach(Actuator* a) override { instances_.Remove(static_cast<EyebotLaserActuator*>(a)); }
  size_t size() const override { return instances_.size(); }
  void Act(size_t begin, size_t end) override {
    Space& space = sim().space();
    for (size_t k = begin; k < end; ++k) {
      const LaserInstance& a = instances_[k];
      if (a.alive) space.Get<PanTiltState>(a.robot.index)->laser_on = a.is_on();
    }
  }

 private:
  InstanceStore<LaserInstance> instances_;
};

COLONY_REGISTER_ACTUATOR(LaserSystem, "eyebot_laser", "default",
                         "the eye-bot's red laser pointer, along the pan-tilt head's axis: on or "
                         "off; its spot is a red point in the LED medium",
                         DeviceInterface{
                             "actuators/eyebot_laser/eyebot_laser.h",
                             "colony::EyebotLaserActuator",
                             {"On(), Off(), Set(on): the laser along the head's axis", "is_on()"}},
                         (std::vector<AttributeDoc>{}));

}  // namespace
}  // namespace colony
