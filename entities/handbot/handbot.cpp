#include "entities/handbot/handbot.h"

#include "actuators/handbot_arms/handbot_arms_state.h"
#include "actuators/handbot_fans/handbot_fans_state.h"
#include "actuators/rope_launcher/rope_state.h"
#include "core/entity_type.h"
#include "core/text.h"

namespace colony {
namespace {

class HandbotType : public EntityType {
 public:
  HandbotType() {
    using namespace handbot;
    mounts_.rings["proximity"] = {kProximityCount, kHullRadius, kProximityElevation,
                                  M_PI / kProximityCount, kProximityRange};
    mounts_.rings["leds"] = {kRingLedCount, kLedRingRadius, kLedRingElevation, 0.0, 0.0};
  }

  void Build(const ConfigNode& node, EntityDesc& desc) const override {
    using namespace handbot;
    auto& init = desc.init;
    init.geometry.shape = ShapeKind::kCylinder;
    init.geometry.radius = kHullRadius;
    init.geometry.size = Vec3(2 * kHullRadius, 2 * kHullRadius, kHeight);
    init.flags = kSolid | kMovable | kRobot;
    init.color = node.GetColor("color", Color{200, 200, 200, 255});
    init.led_count = kRingLedCount;
    init.mass = node.GetDouble("mass", kMass, Range::Positive());
    if (init.mass <= kPartsMass) {
      node.Error("mass", node.GetString("mass", ""),
                 "a hand-bot of " + FormatNumber(init.mass) +
                     " kg is no heavier than its head, arms and grippers (" +
                     FormatNumber(kPartsMass) + " kg); accepted: a number > " +
                     FormatNumber(kPartsMass) + " (kg)");
    }
    RopeState& rope = init.components.Add<RopeState>();
    rope.max_length = node.GetDouble("rope_length", kRopeMaxLength, Range::Positive());
    rope.max_climb_speed = node.GetDouble("climb_speed", kRopeMaxClimbSpeed, Range::Positive());
    rope.motor_force = node.GetDouble("rope_force", kRopeMotorForce, Range::Positive());
    rope.stiffness = node.GetDouble("rope_stiffness", kRopeStiffness, Range::Positive());
    if (node.Has("rope_anchor")) {
      const auto xy = node.GetPair("rope_anchor", {0, 0});
      rope.start_attached = true;
      rope.start_anchor_x = xy[0];
      rope.start_anchor_y = xy[1];
    }
    HandbotArmsState& arms = init.components.Add<HandbotArmsState>();
    arms.head.motor = {kHeadStallTorque, kHeadNoLoadSpeed};
    arms.head.speed = kHeadNominalSpeed;
    for (int k = 0; k < 2; ++k) {
      arms.arm[k].motor = {kArmStallTorque, kArmNoLoadSpeed};
      arms.arm[k].speed = kArmNominalSpeed;
      arms.arm[k].min = 0;
      arms.arm[k].max = M_PI / 2;
      arms.wrist[k].motor = {kWristStallTorque, kWristNoLoadSpeed};
      arms.wrist[k].speed = kWristNominalSpeed;
      arms.claws[k].speed = kClawSpeed;
    }
    arms.grasp_force = kGraspForce;
    arms.holding_limit = node.GetDouble("holding_limit", kHoldingLimit, Range::Positive());
    init.components.Add<HandbotFansState>().max_torque =
        node.GetDouble("fan_torque", kFanTorque, Range::Positive());
  }
  bool is_robot() const override { return true; }
  const DeviceMounts& mounts() const override { return mounts_; }

 private:
  DeviceMounts mounts_;
};

COLONY_REGISTER_ENTITY(
    HandbotType, "handbot",
    "the hand-bot: a climbing robot that cannot drive; hull with proximity ring and 12 RGB LEDs on "
    "its "
    "docking ring, a rope launcher that fires a magnet up to a ferromagnetic ceiling and climbs "
    "the rope, a "
    "head turning two arms with a gripper each (needs dynamics3d); takes <body> and <controller "
    "config>",
    (std::vector<AttributeDoc>{
        {"color", kColorAccepted, "200,200,200", "hull colour"},
        {"mass", "a number > 0.8 (kg)", "2", "the whole robot's mass"},
        {"rope_length", "a number > 0 (m)", "2.7", "how far above the launcher the magnet reaches"},
        {"climb_speed", "a number > 0 (m/s)", "0.1",
         "fastest the rope motor coils the rope in or lets it out"},
        {"rope_force", "a number > 0 (N)", "50",
         "most the rope motor pulls (climbing stalls beyond it)"},
        {"rope_stiffness", "a number > 0 (N/m)", "5000",
         "the rope's pull per metre it is stretched (a 2 kg robot stretches it 4 mm)"},
        {"rope_anchor", "\"x,y\" (m)", "none: the rope starts in its tube",
         "the magnet already holds to the ceiling above (x, y) when the run starts, the rope taut"},
        {"holding_limit", "a number > 0 (N)", "39.24",
         "pull beyond which a grasped thing slips out of a gripper"},
        {"fan_torque", "a number > 0 (N m)", "0.05", "most yaw torque the two fans give together"},
    }),
    (std::vector<std::string>{"hand-bot"}));

}  // namespace
}  // namespace colony
