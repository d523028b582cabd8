#include "entities/marxbot/marxbot.h"

#include "actuators/gripper/gripper_state.h"
#include "actuators/manipulator/manipulator_state.h"
#include "core/entity_type.h"

namespace colony {
namespace {

class MarxbotType : public EntityType {
 public:
  MarxbotType() {
    using namespace marxbot;
    mounts_.rings["proximity"] = {kProximityCount, kBodyRadius, kProximityElevation,
                                  M_PI / kProximityCount, kProximityRange};
    mounts_.rings["ground"] = {kGroundCount, kGroundRadius, 0.0, 0.0, 0.0};
    mounts_.rings["leds"] = {kRingLedCount, kLedRingRadius, kLedRingElevation, 0.0, 0.0};
    mounts_.rings["light"] = {kLightCount, kBodyRadius, kLightElevation, M_PI / kLightCount, 0.0};
    mounts_.rings["distance_scanner"] = {kScannerSensorCount, kScannerRadius, kScannerElevation,
                                         0.0, kScannerRange};
  }

  void Build(const ConfigNode& node, EntityDesc& desc) const override {
    using namespace marxbot;
    auto& init = desc.init;
    init.geometry.shape = ShapeKind::kCylinder;
    init.geometry.radius = kBodyRadius;
    init.geometry.size = Vec3(2 * kBodyRadius, 2 * kBodyRadius, kBodyHeight);
    init.flags = kSolid | kMovable | kRobot;
    init.color = node.GetColor("color", Color{60, 60, 60, 255});
    init.led_count = kLedCount;
    DriveState& drive = init.components.Add<DriveState>();
    drive.wheel_base = kWheelBase;
    drive.wheel_radius = kWheelRadius;
    drive.max_speed = kMaxSpeed;
    init.components.Add<GripperState>();
    desc.init.mass = kMass;
    // The construction manipulator (seed 000, 2.2.2; seed 004, 3.3).
    if (node.GetBool("manipulator", false)) {
      ManipulatorState& arm = init.components.Add<ManipulatorState>();
      arm.min_tilt = kMinTilt;
      arm.max_tilt = kMaxTilt;
      arm.tilt_speed = kTiltSpeed;
      init.geometry.size.z() = kHeightWithManipulator;
      init.mass = kMass + kManipulatorMass;
    }
  }
  bool is_robot() const override { return true; }
  std::string ComponentHint(std::string_view name) const override {
    return name == ManipulatorState::kComponentName
               ? "declare the marxbot with manipulator=\"true\""
               : "";
  }
  const DeviceMounts& mounts() const override { return mounts_; }

 private:
  DeviceMounts mounts_;
};

COLONY_REGISTER_ENTITY(
    MarxbotType, "marxbot",
    "the marXbot (foot-bot): 17 cm diameter, differential treels up to 0.3 m/s, 24 proximity "
    "sensors, 8 ground sensors, 12 RGB LEDs + beacon; takes <body> and <controller config>",
    (std::vector<AttributeDoc>{
        {"color", kColorAccepted, "60,60,60", "body colour"},
        {"manipulator", "true, false", "false",
         "carries the magnetic construction manipulator (29 cm tall); needs dynamics3d, "
         "kinematics2d or dynamics2d"}}),
    (std::vector<std::string>{"foot-bot"}));

}  // namespace
}  // namespace colony
