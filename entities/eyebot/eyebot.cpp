#include "entities/eyebot/eyebot.h"

#include <cmath>

#include "core/entity_type.h"
#include "core/log.h"
#include "core/text.h"

namespace colony {
namespace {

class EyebotType : public EntityType {
 public:
  EyebotType() {
    using namespace eyebot;
    mounts_.rings["proximity"] = {kProximityCount, kRadius, kProximityElevation,
                                  M_PI / kProximityCount, kProximityRange};
    mounts_.rings["leds"] = {1, 0.0, kLedElevation, 0.0, 0.0};
    mounts_.rings["distance_scanner"] = {kScannerSensorCount, kScannerRadius, kScannerElevation,
                                         0.0, 0.0};
  }

  void Build(const ConfigNode& node, EntityDesc& desc) const override {
    using namespace eyebot;
    auto& init = desc.init;
    init.geometry.shape = ShapeKind::kCylinder;
    init.geometry.radius = kRadius;
    init.geometry.size = Vec3(2 * kRadius, 2 * kRadius, kHeight);
    init.flags = kSolid | kMovable | kRobot;
    init.color = node.GetColor("color", Color{60, 60, 60, 255});
    init.led_count = 1;
    init.mass = node.GetDouble("mass", kMass, Range::Positive());
    QuadrotorState& rotors = init.components.Add<QuadrotorState>();
    rotors.max_thrust = node.GetDouble("max_thrust", kMaxThrust, Range::Positive());
    rotors.max_speed = node.GetDouble("max_speed", kMaxSpeed, Range::Positive());
    rotors.max_vertical_speed =
        node.GetDouble("max_vertical_speed", kMaxVerticalSpeed, Range::Positive());
    rotors.max_acceleration =
        node.GetDouble("max_acceleration", kMaxAcceleration, Range::Positive());
    rotors.max_yaw_rate =
        DegToRad(node.GetDouble("max_yaw_rate", RadToDeg(kMaxYawRate), Range::Positive()));
    // Weight the rotors cannot lift: the robot can be declared (a payload
    // study), but it will not take off, and the user is told so.
    const double weight = init.mass * 9.81;
    if (weight >= rotors.max_thrust) {
      LogWarning(node.file() + ":" + std::to_string(node.line()) + ": <" + node.name() +
                 ">: an eye-bot of " + FormatNumber(init.mass) + " kg, whose rotors lift at most " +
                 FormatNumber(rotors.max_thrust / 9.81) + " kg (max_thrust " +
                 FormatNumber(rotors.max_thrust) + " N): it cannot take off");
    }
    init.components.Add<CeilingAttachmentState>().attach = node.GetBool("attached", false);
    PanTiltState& head = init.components.Add<PanTiltState>();
    head.pan_speed = DegToRad(node.GetDouble("pan_speed", RadToDeg(kPanSpeed), Range::Positive()));
    head.tilt_speed =
        DegToRad(node.GetDouble("tilt_speed", RadToDeg(kTiltSpeed), Range::Positive()));
    head.laser_range = node.GetDouble("laser_range", kLaserRange, Range::Positive());
  }
  bool is_robot() const override { return true; }
  const DeviceMounts& mounts() const override { return mounts_; }

 private:
  DeviceMounts mounts_;
};

COLONY_REGISTER_ENTITY(
    EyebotType, "eyebot",
    "the eye-bot: a quadrotor that flies (position or speed control) or hangs from a ceiling; a "
    "pan-tilt head with a colour camera and a red laser pointer, an RGB LED underneath, "
    "proximity ring, distance scanner, range-and-bearing (needs pointmass3d or dynamics3d); "
    "takes <body> and <controller config>",
    (std::vector<AttributeDoc>{
        {"color", kColorAccepted, "60,60,60", "body colour"},
        {"mass", "a number > 0 (kg)", "1",
         "the whole robot's mass; at or above max_thrust/g it "
         "cannot take off (a warning at load)"},
        {"max_thrust", "a number > 0 (N)", "13.73",
         "the four rotors' most thrust together (seed 003: 4 x 350 g)"},
        {"max_speed", "a number > 0 (m/s)", "2",
         "fastest horizontal speed the flight computer "
         "commands"},
        {"max_vertical_speed", "a number > 0 (m/s)", "1", "fastest climb or descent"},
        {"max_acceleration", "a number > 0 (m/s^2)", "3",
         "largest acceleration commanded (the thrust may allow less)"},
        {"max_yaw_rate", "a number > 0 (degrees/s)", "90", "fastest turn about the vertical"},
        {"attached", "true, false", "false",
         "starts holding to the ceiling (place it with its top at the ceiling's height)"},
        {"pan_speed", "a number > 0 (degrees/s)", "180", "the pan-tilt unit's pan speed"},
        {"tilt_speed", "a number > 0 (degrees/s)", "90", "the pan-tilt unit's tilt speed"},
        {"laser_range", "a number > 0 (m)", "10", "farthest the laser's spot is seen"},
    }),
    (std::vector<std::string>{"eye-bot"}));

}  // namespace

bool PanTiltAnchor(const Space& space, uint32_t slot, std::string_view name, Pose& pose) {
  const PanTiltState* head = space.Get<PanTiltState>(slot);
  if (name != PanTiltState::kComponentName || !head) return false;
  pose = PanTiltFrame(space.pose(slot), *head);
  return true;
}

void WarnIfHeldAwayFromCeiling(const Space& space, uint32_t slot) {
  const auto* hold = space.Get<CeilingAttachmentState>(slot);
  if (!hold || !hold->attach) return;
  const double top = space.pose(slot).position.z() + space.geometry(slot).height();
  const auto& ceiling = space.ceiling();
  if (ceiling && std::abs(ceiling->z - top) <= eyebot::kAttachDistance) return;
  LogWarning("eye-bot '" + space.id(slot) + "' is declared attached=\"true\", but its top is at " +
             FormatNumber(top) + " m and " +
             (ceiling ? "the ceiling at " + FormatNumber(ceiling->z) + " m"
                      : std::string("the arena has no <ceiling>")) +
             ": it does not hold at the start, and will once its top touches a ceiling");
}

}  // namespace colony
