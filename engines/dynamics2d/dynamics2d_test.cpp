// dynamics2d: robots push movable objects, cannot move fixed ones, and slip
// when they push too hard.
#include <box2d/box2d.h>

#include "actuators/differential_steering/differential_steering.h"
#include "actuators/gripper/gripper_state.h"
#include "sensors/wheel_encoders/wheel_encoders.h"
#include "tests/test_util.h"

namespace colony {
namespace {

// Drives straight at `speed` m/s.
class Pusher : public Controller {
 public:
  void Init(const Params& params) override {
    speed_ = params.GetDouble("speed", 0.2);
    wheels_ = &GetActuator<DifferentialSteering>("differential_steering");
  }
  void ControlStep() override { wheels_->SetLinearVelocity(speed_, speed_); }

 private:
  double speed_ = 0;
  DifferentialSteering* wheels_ = nullptr;
};
COLONY_REGISTER_CONTROLLER(Pusher, "dyn2d_pusher", "test: drives straight");

const char* kPusher =
    "<dyn2d_pusher id=\"p\"><actuators><differential_steering/></actuators><params "
    "speed=\"0.2\"/></dyn2d_pusher>";
const char* kEngine = "<dynamics2d id=\"d2d\"/>";

std::string Scene(const std::string& object) {
  return testing::Experiment(
      "<marxbot id=\"r\"><body position=\"-0.5,0,0\"/><controller config=\"p\"/></marxbot>" +
          object,
      kPusher, "4,4,1", "", kEngine);
}

Vec3 PositionOf(Simulation& sim, const std::string& id) {
  return sim.space().pose(sim.space().Find(id).index).position;
}

TEST(Dynamics2d, RobotPushesAMovableBox) {
  auto sim =
      testing::LoadXml(Scene("<box id=\"b\" size=\"0.2,0.2,0.2\" movable=\"true\" "
                             "mass=\"0.3\"><body position=\"0,0,0\"/></box>"));
  for (int t = 0; t < 50; ++t) sim->Step();
  const Vec3 box = PositionOf(*sim, "b");
  const Vec3 robot = PositionOf(*sim, "r");
  EXPECT_GT(box.x(), 0.3) << "the box should have been pushed along +x";
  EXPECT_LT(std::abs(box.y()), 0.1);
  EXPECT_LT(robot.x(), box.x()) << "the robot stays behind the box it pushes";
}

TEST(Dynamics2d, RobotCannotMoveAFixedWall) {
  auto sim =
      testing::LoadXml(Scene("<box id=\"w\" size=\"0.1,1,0.3\"><body position=\"0,0,0\"/></box>"));
  for (int t = 0; t < 80; ++t) sim->Step();
  EXPECT_EQ(PositionOf(*sim, "w"), Vec3(0, 0, 0));
  // The robot's front stops at the wall's face (x = -0.05), give or take Box2D's skin.
  EXPECT_LT(PositionOf(*sim, "r").x() + 0.085, -0.05 + 0.02);
  EXPECT_GT(PositionOf(*sim, "r").x(), -0.5 + 0.2) << "it did drive up to the wall";
  EXPECT_TRUE(sim->space().in_contact(sim->space().Find("r").index));
}

TEST(Dynamics2d, TreelsSlipAgainstAnObjectTooHeavyToPush) {
  // Floor friction on 50 kg (about 245 N) is far beyond the treels' 15 N.
  auto sim =
      testing::LoadXml(Scene("<box id=\"b\" size=\"0.2,0.2,0.2\" movable=\"true\" "
                             "mass=\"50\"><body position=\"0,0,0\"/></box>"));
  for (int t = 0; t < 60; ++t) sim->Step();
  EXPECT_NEAR(PositionOf(*sim, "b").x(), 0.0, 0.002);
  const uint32_t r = sim->space().Find("r").index;
  EXPECT_LT(sim->space().twist(r).linear.norm(), 0.02) << "commanded 0.2 m/s, it is stuck";
  EXPECT_DOUBLE_EQ(sim->space().drive(r)->target_left, 0.2);
}

TEST(Dynamics2d, RobotDrivesAtItsCommandedSpeedOnAFreeFloor) {
  auto sim = testing::LoadXml(Scene(""));
  for (int t = 0; t < 20; ++t) sim->Step();
  const uint32_t r = sim->space().Find("r").index;
  EXPECT_NEAR(sim->space().twist(r).linear.x(), 0.2, 1e-3);
  EXPECT_NEAR(sim->space().twist(r).linear.y(), 0.0, 1e-3);
}

TEST(Dynamics2d, BadParametersAreRejectedWithElementAndLine) {
  for (const char* bad_text :
       {"substeps=\"0\"", "friction=\"-1\"", "robot_max_force=\"nan\"", "iterations=\"x\""}) {
    const std::string bad = bad_text;
    const std::string message = testing::LoadError(testing::Experiment(
        "", "", "4,4,1", "", std::string("<dynamics2d id=\"d2d\" ") + bad + "/>"));
    const std::string attribute = bad.substr(0, bad.find('='));
    EXPECT_NE(message.find("<string>:1: <dynamics2d id=\"d2d\"> attribute '" + attribute + "'"),
              std::string::npos)
        << bad << ": " << message;
  }
}

// Box2D's own profiling timer reads the clock six times per island per step;
// Colony replaces it with one that reads nothing (box2d_timer.cpp). If a
// change of linking lost that, every dynamics2d run would be a quarter slower.
TEST(Dynamics2d, Box2DsProfilingTimerReadsNoClock) {
  b2World world(b2Vec2(0, 0));
  b2CircleShape disc;
  disc.m_radius = 0.085f;
  for (int i = 0; i < 500; ++i) {
    b2BodyDef def;
    def.type = b2_dynamicBody;
    def.position.Set(0.2f * static_cast<float>(i % 25), 0.2f * static_cast<float>(i / 25));
    def.linearVelocity.Set(0.1f, 0.05f);
    world.CreateBody(&def)->CreateFixture(&disc, 1.0f);
  }
  for (int t = 0; t < 20; ++t) world.Step(0.05f, 8, 3);
  const b2Profile& profile = world.GetProfile();
  EXPECT_EQ(profile.step, 0.0f);
  EXPECT_EQ(profile.solve, 0.0f);
  EXPECT_EQ(profile.solveVelocity, 0.0f);
}

}  // namespace
}  // namespace colony

namespace colony {
namespace {

TEST(Dynamics2dExamples, GrippingExperimentDragsTheCylinderIntoTheCorner) {
  ExperimentOptions options;
  options.file = COLONY_SOURCE_DIR "/experiments/gripping.xml";
  auto sim = Simulation::Load(options);
  const uint32_t cylinder = sim->space().Find("cylinder").index;
  const Vec3 start = sim->space().pose(cylinder).position;
  while (!sim->Done()) sim->Step();
  const Vec3 end = sim->space().pose(cylinder).position;
  EXPECT_GT((end - start).norm(), 1.5) << "the cylinder was dragged across the arena";
  EXPECT_LT(std::hypot(end.x() - 1.3, end.y() - 1.3), 0.1) << "it ends at the corner";
  EXPECT_FALSE(sim->space().Get<GripperState>(sim->space().Find("mb").index)->holding())
      << "and was let go";
}

}  // namespace
}  // namespace colony
