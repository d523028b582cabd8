// Adding a robot type touches no engine: this file alone defines a small
// tracked rover (its entity type and its dynamics3d model, composed of the
// engine's tread part), and the engine simulates it beside the marXbot.
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "core/entity_type.h"
#include "core/registry.h"
#include "engines/dynamics3d/dynamics3d.h"
#include "engines/dynamics3d/parts.h"
#include "tests/test_util.h"

namespace colony {
namespace {

// A cylinder 10 cm across and 8 cm tall, 1 kg, on two treads 10 cm apart.
constexpr double kRadius = 0.05, kHeight = 0.08, kTrack = 0.10, kWheel = 0.015;

class RoverType : public EntityType {
 public:
  void Build(const ConfigNode& node, EntityDesc& desc) const override {
    (void)node;
    auto& init = desc.init;
    init.geometry.shape = ShapeKind::kCylinder;
    init.geometry.radius = kRadius;
    init.geometry.size = Vec3(2 * kRadius, 2 * kRadius, kHeight);
    init.flags = kSolid | kMovable | kRobot;
    init.mass = 1.0;
    DriveState& drive = init.components.Add<DriveState>();
    drive.wheel_base = kTrack;
    drive.wheel_radius = kWheel;
    drive.max_speed = 0.5;
  }
  bool is_robot() const override { return true; }
};
COLONY_REGISTER_ENTITY(RoverType, "test_rover", "test: a small tracked rover", {}, {});

// Its dynamics3d model: one body, a cylinder hull above four tread wheels.
class RoverModel : public Dynamics3dModel {
 public:
  void Add(Engine& engine, uint32_t s) override {
    using namespace dynamics3d;
    dBodyID body = engine.MakeBody(s, 0.5 * kHeight);
    dMass m;
    dMassSetCylinderTotal(&m, 1.0, 3, kRadius, kHeight);
    dBodySetMass(body, &m);
    dSpaceID parts = engine.MakePartSpace(s);
    dGeomID hull = engine.AddGeom(s, dCreateCylinder(parts, kRadius, kHeight - 2 * kWheel), kBody);
    dGeomSetBody(hull, body);
    dGeomSetOffsetPosition(hull, 0, 0, kWheel);
    for (int k = 0; k < 4; ++k) {
      const uint8_t side = static_cast<uint8_t>(k / 2);  // 0 left, 1 right
      dGeomID w = engine.AddGeom(s, dCreateSphere(parts, kWheel), kTread, side);
      dGeomSetBody(w, body);
      dGeomSetOffsetPosition(w, k % 2 == 0 ? 0.03 : -0.03, side == 0 ? 0.5 * kTrack : -0.5 * kTrack,
                             kWheel - 0.5 * kHeight);
    }
    slots_.push_back(s);
  }
  void Remove(Engine&, uint32_t s) override { std::erase(slots_, s); }
  void AfterStep(Engine& engine, double dt) override {
    for (uint32_t s : slots_) {
      DriveState& d = *engine.entities().drive(s);
      d.travelled_left = d.left * dt;
      d.travelled_right = d.right * dt;
    }
  }
  void ModifyContacts(Engine& engine, dGeomID wheel, bool wheel_first, double mu,
                      dContact* contacts, int n) override {
    const DriveState& d = *engine.entities().drive(Engine::OwnerOf(wheel));
    const double speed = Engine::PartOf(wheel) == 0 ? d.left : d.right;
    dynamics3d::DriveTreadContacts(wheel, wheel_first, speed, mu, mu, 0.005, contacts, n);
  }

 private:
  std::vector<uint32_t> slots_;
};
COLONY_REGISTER_PHYSICS_MODEL(RoverModel, "dynamics3d:test_rover", "test: a tracked rover",
                              (std::vector<std::string>{"drive"}));

class Idle : public Controller {
 public:
  void Init(const Params&) override {}
  void ControlStep() override {}
};
COLONY_REGISTER_CONTROLLER(Idle, "rover_idle", "test: does nothing");

TEST(NewRobotType, ARoverDefinedOutsideTheEngineDrivesBesideAMarxbot) {
  auto sim = testing::LoadXml(testing::Experiment(
      "<test_rover id=\"rover\"><body position=\"-1,0.5,0\" orientation=\"0,0,0\"/>"
      "<controller config=\"idle\"/></test_rover>"
      "<marxbot id=\"mb\"><body position=\"-1,-0.5,0\" orientation=\"0,0,0\"/><controller "
      "config=\"idle\"/></marxbot>",
      "<rover_idle id=\"idle\"/>", "4,4,1", "", "<dynamics3d id=\"d3d\"/>"));
  Space& space = sim->space();
  const uint32_t rover = space.Find("rover").index, mb = space.Find("mb").index;
  for (uint32_t s : {rover, mb}) space.drive(s)->left = space.drive(s)->right = 0.1;
  for (int i = 0; i < 50; ++i) {
    for (uint32_t s : {rover, mb}) space.drive(s)->left = space.drive(s)->right = 0.1;
    sim->Step();
  }
  // 5 s at 0.1 m/s, straight along x, both upright.
  for (uint32_t s : {rover, mb}) {
    const Pose& p = space.pose(s);
    EXPECT_NEAR(p.position.x(), -0.5, 0.03) << space.id(s);
    EXPECT_NEAR(p.position.y(), s == rover ? 0.5 : -0.5, 0.02) << space.id(s);
    EXPECT_GT((p.orientation * Vec3::UnitZ()).z(), 0.999) << space.id(s);
  }
  EXPECT_NEAR(space.drive(rover)->travelled_left, 0.01, 1e-9) << "its model wrote the encoders";
}

}  // namespace
}  // namespace colony
