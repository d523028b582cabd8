// Simulated gripper sensor: the turret angle and the holding state from the space.
#include "actuators/gripper/gripper_state.h"
#include "core/device.h"
#include "core/simulation.h"
#include "sensors/gripper/gripper.h"

namespace colony {
namespace {

struct GripperSensorInstance : GripperSensor, InstanceBase {
  using Interface = GripperSensor;
  void Set(double turret, bool holding) {
    turret_ = turret;
    holding_ = holding;
  }
};

class GripperSensorSystem : public SensorSystem {
 public:
  void Configure(const ConfigNode& node) override { (void)node; }
  std::vector<std::string> NeededComponents() const override {
    return {GripperState::kComponentName};
  }
  Sensor* Attach(EntityHandle robot, const RandomStream& rng) override {
    return &instances_.Add(robot, rng);
  }
  void Detach(Sensor* s) override { instances_.Remove(static_cast<GripperSensor*>(s)); }
  size_t size() const override { return instances_.size(); }
  void Update(size_t begin, size_t end) override {
    const Space& space = sim().space();
    for (size_t k = begin; k < end; ++k) {
      GripperSensorInstance& s = instances_[k];
      if (!s.alive) continue;
      const GripperState& g = *space.Get<GripperState>(s.robot.index);
      s.Set(g.turret, g.holding());
    }
  }

 private:
  InstanceStore<GripperSensorInstance> instances_;
};

COLONY_REGISTER_SENSOR(GripperSensorSystem, "gripper", "default",
                       "the turret angle (rad) and whether the gripper holds something",
                       DeviceInterface{
                           "sensors/gripper/gripper.h",
                           "colony::GripperSensor",
                           {"turret_angle(): the turret from the robot's front, ccw (rad)",
                            "holding(): the gripper holds something"}},
                       {}, {"footbot_turret_encoder"});

}  // namespace
}  // namespace colony
