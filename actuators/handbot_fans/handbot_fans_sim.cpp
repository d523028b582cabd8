// Simulated hand-bot fans actuator: writes the torque (at most the fans'
// most, with a warning once per robot) or the heading to hold into the
// robot's HandbotFansState; the physics model turns the hull (dynamics3d).
#include <algorithm>
#include <cmath>
#include <string>

#include "actuators/handbot_fans/handbot_fans.h"
#include "actuators/handbot_fans/handbot_fans_state.h"
#include "core/device.h"
#include "core/log.h"
#include "core/simulation.h"

namespace colony {
namespace {

struct FansInstance : HandbotFansActuator, InstanceBase {
  using Interface = HandbotFansActuator;
  void SetMax(double v) { max_torque_ = v; }
  bool warned = false;
};

class HandbotFansSystem : public ActuatorSystem {
 public:
  void Configure(const ConfigNode&) override {}
  std::vector<std::string> NeededComponents() const override {
    return {HandbotFansState::kComponentName};
  }
  Actuator* Attach(EntityHandle robot, const RandomStream& rng) override {
    FansInstance& a = instances_.Add(robot, rng);
    a.SetMax(sim().space().Get<HandbotFansState>(robot.index)->max_torque);
    return &a;
  }
  void Detach(Actuator* a) override { instances_.Remove(static_cast<HandbotFansActuator*>(a)); }
  size_t size() const override { return instances_.size(); }
  void Act(size_t begin, size_t end) override {
    Space& space = sim().space();
    for (size_t k = begin; k < end; ++k) {
      FansInstance& a = instances_[k];
      if (!a.alive) continue;
      HandbotFansState& fans = *space.Get<HandbotFansState>(a.robot.index);
      fans.hold = a.holding_heading() && std::isfinite(a.heading());
      fans.heading = fans.hold ? WrapAngle(a.heading()) : 0.0;
      double torque = std::isfinite(a.torque()) ? a.torque() : 0.0;
      if (std::abs(torque) > fans.max_torque) {
        if (!a.warned) {
          a.warned = true;
          LogWarning("robot '" + space.id(a.robot.index) + "': fan torque " + FormatNumber(torque) +
                     " N m is beyond the fans' most, " + FormatNumber(fans.max_torque) +
                     " N m; they give that (said once per robot)");
        }
        torque = std::clamp(torque, -fans.max_torque, fans.max_torque);
      }
      fans.torque = fans.hold ? 0.0 : torque;
    }
  }

 private:
  InstanceStore<FansInstance> instances_;
};

COLONY_REGISTER_ACTUATOR(
    HandbotFansSystem, "handbot_fans", "default",
    "the hand-bot's two fans: a yaw torque (N m) or a heading to hold while hanging",
    DeviceInterface{"actuators/handbot_fans/handbot_fans.h",
                    "colony::HandbotFansActuator",
                    {"SetTorque(torque): a yaw torque (N m)",
                     "HoldHeading(yaw): a heading to hold while hanging (rad)", "Stop()",
                     "torque(), holding_heading(), heading(), max_torque() (N m)"}},
    (std::vector<AttributeDoc>{}));

}  // namespace
}  // namespace colony
