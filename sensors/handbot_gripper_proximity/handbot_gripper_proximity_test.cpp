// The hand-bot's gripper IR sensors as a controller sees them, in
// dynamics3d: a board ahead of an extended gripper is seen, nearer as the
// arm reaches towards it; nothing in free air, nor the robot itself; 3, 12
// or 24 sensors per gripper by implementation; a bad implementation is
// refused; results do not depend on the thread count.
#include "sensors/handbot_gripper_proximity/handbot_gripper_proximity.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "actuators/handbot_arms/handbot_arms.h"
#include "core/registry.h"
#include "tests/test_util.h"

namespace colony {
namespace {

using testing::LoadError;
using testing::LoadXml;
using testing::Mentions;

class GripperIrProbe : public Controller {
 public:
  void Init(const Params&) override {
    arms = &GetActuator<HandbotArmsActuator>("handbot_arms");
    ir = &GetSensor<HandbotGripperProximitySensor>("handbot_gripper_proximity");
  }
  void ControlStep() override {}
  HandbotArmsActuator* arms = nullptr;
  const HandbotGripperProximitySensor* ir = nullptr;
};
COLONY_REGISTER_CONTROLLER(GripperIrProbe, "gripper_ir_probe",
                           "test: the hand-bot's gripper IR sensors");

std::string Scene(const std::string& arena, const std::string& sensor_attributes = "") {
  return "<colony><framework><experiment length=\"100\" ticks_per_second=\"10\" "
         "random_seed=\"3\"/></framework>"
         "<controllers><gripper_ir_probe id=\"p\"><actuators><handbot_arms/></actuators><sensors>"
         "<handbot_gripper_proximity " +
         sensor_attributes +
         "/></sensors></gripper_ir_probe></controllers><arena size=\"3,3,3\" center=\"0,0,1.5\">"
         "<handbot id=\"h\"><body position=\"0,0,0\"/><controller config=\"p\"/></handbot>" +
         arena +
         "</arena><physics_engines><dynamics3d id=\"d3d\" "
         "stepper=\"worldstep\"/></physics_engines></colony>";
}

// A board whose face is 0.36 m ahead of the robot's axis: the grippers'
// tips reach 0.335 m with the arms straight ahead.
const std::string kBoard =
    "<box id=\"board\" size=\"0.04,1,1\"><body position=\"0.38,0,0\"/></box>";

GripperIrProbe& Probe(Simulation& sim) {
  return dynamic_cast<GripperIrProbe&>(*sim.ControllerOf(sim.space().Find("h")));
}
using testing::RunFor;
float Max(const std::vector<HandbotGripperProximitySensor::Reading>& readings) {
  float m = 0;
  for (const auto& r : readings) m = std::max(m, r.value);
  return m;
}

TEST(HandbotGripperProximity, ABoardAheadIsSeenNearerAsTheArmReachesForIt) {
  auto sim = LoadXml(Scene(kBoard));
  GripperIrProbe& p = Probe(*sim);
  RunFor(*sim, 0.5);
  EXPECT_EQ(Max(p.ir->readings(0)), 0.0f) << "folded, the gripper points sideways: nothing";
  p.arms->SetSpeed(0, 0.5);
  p.arms->SetExtension(0, M_PI / 2);
  float last = 0;
  int rises = 0;
  for (int t = 0; t < 40; ++t) {
    sim->Step();
    const float m = Max(p.ir->readings(0));
    if (m > last + 1e-4f) ++rises;
    last = std::max(last, m);
  }
  EXPECT_GT(rises, 2) << "the readings rise as the gripper nears the board";
  // Straight ahead, 2.5 cm from the board: the sensors 30 degrees off the
  // axis see it at 2.5 / cos 30 cm: 0.35.
  EXPECT_NEAR(Max(p.ir->readings(0)), 0.01 / (0.025 / std::cos(M_PI / 6)), 0.03);
  EXPECT_EQ(Max(p.ir->readings(1)), 0.0f) << "the right arm is still folded";
}

TEST(HandbotGripperProximity, NothingIsSeenInFreeAirNorTheRobotItself) {
  auto sim = LoadXml(Scene(""));
  GripperIrProbe& p = Probe(*sim);
  p.arms->SetExtension(0, M_PI / 2);
  p.arms->SetExtension(1, M_PI / 4);
  RunFor(*sim, 2);
  EXPECT_EQ(Max(p.ir->readings(0)), 0.0f);
  EXPECT_EQ(Max(p.ir->readings(1)), 0.0f);
}

TEST(HandbotGripperProximity, ThreeTwelveOrTwentyFourSensorsPerGripper) {
  for (const auto& [implementation, count] : {std::pair<std::string, size_t>{"", 12},
                                              {"implementation=\"simple\"", 3},
                                              {"implementation=\"full\"", 24}}) {
    auto sim = LoadXml(Scene(kBoard, implementation));
    GripperIrProbe& p = Probe(*sim);
    EXPECT_EQ(p.ir->readings(0).size(), count) << implementation;
    EXPECT_EQ(p.ir->readings(1).size(), count) << implementation;
    p.arms->SetExtension(0, M_PI / 2);
    RunFor(*sim, 2);
    EXPECT_GT(Max(p.ir->readings(0)), 0.2f) << implementation << ": the board is seen";
  }
  EXPECT_TRUE(Mentions(LoadError(Scene("", "implementation=\"six\"")),
                       {"<handbot_gripper_proximity>", "implementation", "six"}));
  EXPECT_TRUE(Mentions(LoadError(Scene("", "range=\"-1\"")), {"range", "'-1'"}));
}

TEST(HandbotGripperProximity, SameResultsWhateverTheThreadCount) {
  uint64_t hashes[3];
  for (int threads = 0; threads <= 2; ++threads) {
    auto sim = LoadXml(Scene(kBoard, "noise=\"gaussian\" noise_std_dev=\"0.02\""), {}, threads);
    Probe(*sim).arms->SetExtension(0, M_PI / 2);
    RunFor(*sim, 2);
    hashes[threads] = sim->StateHash();
  }
  EXPECT_EQ(hashes[0], hashes[1]);
  EXPECT_EQ(hashes[1], hashes[2]);
}

}  // namespace
}  // namespace colony
