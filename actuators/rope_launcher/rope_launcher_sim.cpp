// Simulated rope launcher: writes the controller's requests into the
// robot's RopeState (a launch or a retrieval once per call; the climb speed
// each tick, at most the motor's fastest, with a warning the first time a
// robot asks for more). The physics model of the robot's engine launches,
// attaches, climbs and retrieves (dynamics3d); only engines that simulate
// the rope accept the actuator.
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "actuators/rope_launcher/rope_launcher.h"
#include "actuators/rope_launcher/rope_state.h"
#include "core/device.h"
#include "core/log.h"
#include "core/simulation.h"

namespace colony {
namespace {

struct RopeLauncherInstance : RopeLauncherActuator, InstanceBase {
  using Interface = RopeLauncherActuator;
  bool TakeLaunch() { return std::exchange(launch_, false); }
  bool TakeRetrieve() { return std::exchange(retrieve_, false); }
  void SetMaxClimbSpeed(double v) { max_climb_speed_ = v; }
  bool warned = false;
};

class RopeLauncherSystem : public ActuatorSystem {
 public:
  void Configure(const ConfigNode&) override {}
  std::vector<std::string> NeededComponents() const override { return {RopeState::kComponentName}; }

  Actuator* Attach(EntityHandle robot, const RandomStream& rng) override {
    const RopeState* rope = sim().space().Get<RopeState>(robot.index);  // checked by the host
    RopeLauncherInstance& a = instances_.Add(robot, rng);
    a.SetMaxClimbSpeed(rope->max_climb_speed);
    return &a;
  }
  void Detach(Actuator* a) override { instances_.Remove(static_cast<RopeLauncherActuator*>(a)); }
  size_t size() const override { return instances_.size(); }

  void Act(size_t begin, size_t end) override {
    Space& space = sim().space();
    for (size_t k = begin; k < end; ++k) {
      RopeLauncherInstance& a = instances_[k];
      if (!a.alive) continue;
      RopeState& rope = *space.Get<RopeState>(a.robot.index);
      if (a.TakeLaunch()) rope.want_launch = true;
      if (a.TakeRetrieve()) rope.want_retrieve = true;
      double speed = std::isfinite(a.climb_speed()) ? a.climb_speed() : 0.0;
      if (std::abs(speed) > rope.max_climb_speed) {
        if (!a.warned) {
          // Chunks run in parallel: the log is thread-safe, the flag is the instance's own.
          a.warned = true;
          LogWarning("robot '" + space.id(a.robot.index) + "': rope climb speed " +
                     FormatNumber(speed) + " m/s is beyond its motor's fastest, " +
                     FormatNumber(rope.max_climb_speed) +
                     " m/s; it moves at that speed (said once per robot)");
        }
        speed = std::clamp(speed, -rope.max_climb_speed, rope.max_climb_speed);
      }
      rope.climb_speed = speed;
    }
  }

 private:
  InstanceStore<RopeLauncherInstance> instances_;
};

COLONY_REGISTER_ACTUATOR(
    RopeLauncherSystem, "rope_launcher", "default",
    "the hand-bot's rope launcher: fire the magnet to the ceiling, climb up or down the rope "
    "(m/s, force-limited motor), retrieve (needs an engine that simulates it: dynamics3d)",
    DeviceInterface{
        "actuators/rope_launcher/rope_launcher.h",
        "colony::RopeLauncherActuator",
        {"Launch(): fire the magnet to the ceiling", "SetClimbSpeed(speed): > 0 up (m/s)",
         "Retrieve()", "climb_speed(), max_climb_speed() (m/s)"}},
    (std::vector<AttributeDoc>{}));

}  // namespace
}  // namespace colony
