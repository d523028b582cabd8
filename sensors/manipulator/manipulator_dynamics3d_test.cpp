// The manipulator actuator and sensor on the dynamics3d engine: the head
// follows its commands at its speeds, the engaged magnet holds a cube in
// front of it (lifted with the head, dropped when disengaged), and the IR
// sensors of the IR side see a cube in front of it.
#include <cmath>
#include <string>
#include <vector>

#include "actuators/manipulator/manipulator.h"
#include "sensors/manipulator/manipulator.h"
#include "tests/test_util.h"

namespace colony {
namespace {

// Sends the commands in its public fields every control step.
class ManipulatorUser : public Controller {
 public:
  void Init(const Params&) override {
    arm_ = &GetActuator<ManipulatorActuator>("manipulator");
    sensor = &GetSensor<ManipulatorSensor>("manipulator");
  }
  void ControlStep() override {
    arm_->SetElevation(elevation);
    arm_->SetRotation(rotation);
    if (magnet) {
      arm_->EngageMagnet();
    } else {
      arm_->DisengageMagnet();
    }
  }
  double elevation = 0.03, rotation = ManipulatorActuator::kMagnetSide;
  bool magnet = false;
  const ManipulatorSensor* sensor = nullptr;

 private:
  ManipulatorActuator* arm_ = nullptr;
};
COLONY_REGISTER_CONTROLLER(ManipulatorUser, "manipulator_user",
                           "test: scripted manipulator on dynamics3d");

std::unique_ptr<Simulation> Load(const std::string& arena) {
  return testing::LoadXml(testing::Experiment(
      "<marxbot id=\"r\" manipulator=\"true\"><body position=\"0,0,0\"/><controller "
      "config=\"mu\"/></marxbot>" +
          arena,
      "<manipulator_user "
      "id=\"mu\"><actuators><manipulator/></actuators><sensors><manipulator/></sensors>"
      "</manipulator_user>",
      "3,3,1", "", "<dynamics3d id=\"d3d\"/>"));
}

ManipulatorUser& User(Simulation& sim) {
  return dynamic_cast<ManipulatorUser&>(*sim.ControllerOf(sim.space().Find("r")));
}
using testing::PositionOf;

using testing::RunFor;

TEST(ManipulatorOnDynamics3d, ElevationFollowsTheCommandAtItsSpeed) {
  auto sim = Load("");
  ManipulatorUser& u = User(*sim);
  RunFor(*sim, 0.5);
  EXPECT_NEAR(u.sensor->elevation(), 0.03, 0.003) << "the head starts at its lowest";
  u.elevation = 0.15;
  // 0.12 m at 0.05 m/s: 2.4 s. Halfway through it is about halfway up.
  RunFor(*sim, 1.2);
  EXPECT_GT(u.sensor->elevation(), 0.06);
  EXPECT_LT(u.sensor->elevation(), 0.12);
  RunFor(*sim, 2.0);
  EXPECT_NEAR(u.sensor->elevation(), 0.15, 0.005);
  u.elevation = 0.05;
  RunFor(*sim, 3.0);
  EXPECT_NEAR(u.sensor->elevation(), 0.05, 0.005);
  u.rotation = 1.0;
  RunFor(*sim, 2.0);
  EXPECT_NEAR(u.sensor->rotation(), 1.0, 0.05);
}

TEST(ManipulatorOnDynamics3d, EngagedMagnetHoldsTheCubeInFrontLiftsItAndDropsIt) {
  // The magnet face is 0.115 m ahead of the robot's axis at rotation 0; the
  // cube's near side 2 mm beyond it.
  auto sim = Load("<cube id=\"c\"><body position=\"0.147,0,0\"/></cube>");
  ManipulatorUser& u = User(*sim);
  RunFor(*sim, 0.5);
  EXPECT_FALSE(u.sensor->holding());
  u.magnet = true;
  RunFor(*sim, 0.5);
  EXPECT_FALSE(u.sensor->magnet_engaged()) << "switching takes about 1 s";
  EXPECT_FALSE(u.sensor->holding());
  RunFor(*sim, 1.0);
  EXPECT_TRUE(u.sensor->magnet_engaged());
  EXPECT_TRUE(u.sensor->holding());
  u.elevation = 0.10;
  RunFor(*sim, 2.5);
  EXPECT_TRUE(u.sensor->holding());
  EXPECT_GT(PositionOf(*sim, "c").z(), 0.05) << "the cube went up with the head";
  u.magnet = false;
  RunFor(*sim, 2.0);
  EXPECT_FALSE(u.sensor->holding());
  EXPECT_LT(PositionOf(*sim, "c").z(), 0.005) << "dropped, it is back on the floor";
}

TEST(ManipulatorOnDynamics3d, IrSensorsSeeACubeInFrontOfTheIrSide) {
  // A cube 3 cm in front of where the IR face will be once the head has
  // turned it forwards (0.115 m ahead of the axis).
  auto sim = Load("<cube id=\"c\"><body position=\"0.175,0,0\"/></cube>");
  ManipulatorUser& u = User(*sim);
  RunFor(*sim, 0.5);
  for (const auto& r : u.sensor->readings())
    EXPECT_EQ(r.value, 0.0f) << "the IR side faces the body";
  u.rotation = ManipulatorActuator::kIrSide;
  RunFor(*sim, 4.0);
  EXPECT_GT(std::abs(u.sensor->rotation()), 3.1);
  const auto& r = u.sensor->readings();
  ASSERT_EQ(r.size(), 6u);
  EXPECT_GT(r[2].value, 0.25f);
  EXPECT_GT(r[3].value, 0.25f);
  EXPECT_EQ(r[0].value, 0.0f);
  EXPECT_EQ(r[5].value, 0.0f);
  // Raised above the cube, the rays pass over it.
  u.elevation = 0.1;
  RunFor(*sim, 2.0);
  for (const auto& x : u.sensor->readings()) EXPECT_EQ(x.value, 0.0f);
}

}  // namespace
}  // namespace colony
