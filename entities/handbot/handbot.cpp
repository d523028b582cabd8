#include "entities/handbot/handbot.h"

#include "actuators/rope_launcher/rope_state.h"
#include "core/entity_type.h"

namespace colony {
namespace {

class HandbotType : public EntityType {
 public:
  HandbotType() {
    using namespace handbot;
    mounts_.rings["proximity"] = {kProximityCount, kHullRadius, kProximityElevation, M_PI / kProximityCount,
                                  kProximityRange};
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
    RopeState& rope = init.components.Add<RopeState>();
    rope.max_length = node.GetDouble("rope_length", kRopeMaxLength, Range::Positive());
    rope.max_climb_speed = node.GetDouble("climb_speed", kRopeMaxClimbSpeed, Range::Positive());
    rope.motor_force = node.GetDouble("rope_force", kRopeMotorForce, Range::Positive());
  }
  bool is_robot() const override { return true; }
  const DeviceMounts& mounts() const override { return mounts_; }

 private:
  DeviceMounts mounts_;
};

COLONY_REGISTER_ENTITY(
    HandbotType, "handbot",
    "the hand-bot: a climbing robot that cannot drive; hull with proximity ring and 12 RGB LEDs on its "
    "docking ring, a rope launcher that fires a magnet up to a ferromagnetic ceiling and climbs the rope "
    "(needs dynamics3d); takes <body> and <controller config>",
    (std::vector<AttributeDoc>{
        {"color", kColorAccepted, "200,200,200", "hull colour"},
        {"mass", "a number > 0 (kg)", "2", "the whole robot's mass"},
        {"rope_length", "a number > 0 (m)", "2.7", "how far above the launcher the magnet reaches"},
        {"climb_speed", "a number > 0 (m/s)", "0.1", "fastest the rope motor coils the rope in or lets it out"},
        {"rope_force", "a number > 0 (N)", "50", "most the rope motor pulls (climbing stalls beyond it)"},
    }),
    (std::vector<std::string>{"hand-bot"}));

}  // namespace
}  // namespace colony
