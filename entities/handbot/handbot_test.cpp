// The hand-bot's head, arms and grippers as a controller sees them, in
// dynamics3d: the head turns at its speed; an arm pushing a board it cannot
// move stalls and reads about its stall torque; a gripper closing on a book
// holds it as the robot climbs, and a 6 kg weight slips out of it.
#include "entities/handbot/handbot.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "actuators/handbot_arms/handbot_arms.h"
#include "actuators/handbot_fans/handbot_fans.h"
#include "actuators/handbot_grippers/handbot_grippers.h"
#include "actuators/handbot_head/handbot_head.h"
#include "actuators/rope_launcher/rope_launcher.h"
#include "core/registry.h"
#include "sensors/handbot_arms/handbot_arms.h"
#include "sensors/handbot_grippers/handbot_grippers.h"
#include "sensors/handbot_head/handbot_head.h"
#include "tests/test_util.h"

namespace colony {
namespace {

using testing::LoadError;
using testing::LoadXml;
using testing::Mentions;

// Gives the devices to the test, which commands them between steps.
class HandbotProbe : public Controller {
 public:
  void Init(const Params&) override {
    head = &GetActuator<HandbotHeadActuator>("handbot_head");
    arms = &GetActuator<HandbotArmsActuator>("handbot_arms");
    grippers = &GetActuator<HandbotGrippersActuator>("handbot_grippers");
    rope = &GetActuator<RopeLauncherActuator>("rope_launcher");
    fans = &GetActuator<HandbotFansActuator>("handbot_fans");
    head_sensor = &GetSensor<HandbotHeadSensor>("handbot_head");
    arms_sensor = &GetSensor<HandbotArmsSensor>("handbot_arms");
    grippers_sensor = &GetSensor<HandbotGrippersSensor>("handbot_grippers");
  }
  void ControlStep() override {}
  HandbotHeadActuator* head = nullptr;
  HandbotArmsActuator* arms = nullptr;
  HandbotGrippersActuator* grippers = nullptr;
  RopeLauncherActuator* rope = nullptr;
  HandbotFansActuator* fans = nullptr;
  const HandbotHeadSensor* head_sensor = nullptr;
  const HandbotArmsSensor* arms_sensor = nullptr;
  const HandbotGrippersSensor* grippers_sensor = nullptr;
};
COLONY_REGISTER_CONTROLLER(HandbotProbe, "handbot_probe",
                           "test: the hand-bot's devices, commanded by the test");

constexpr int kLeft = HandbotArmsActuator::kLeft;

std::string Scene(const std::string& arena, const std::string& handbot_attributes = "") {
  return "<colony><framework><experiment length=\"100\" ticks_per_second=\"10\" "
         "random_seed=\"3\"/></framework>"
         "<controllers><handbot_probe "
         "id=\"hp\"><actuators><handbot_head/><handbot_arms/><handbot_grippers/>"
         "<rope_launcher/><handbot_fans/></actuators><sensors><handbot_head/><handbot_arms/"
         "><handbot_grippers/>"
         "</sensors></handbot_probe></controllers><arena size=\"3,3,3\" "
         "center=\"0,0,1.5\"><ceiling height=\"2.5\"/>"
         "<handbot id=\"h\" " +
         handbot_attributes + "><body position=\"0,0,0\"/><controller config=\"hp\"/></handbot>" +
         arena +
         "</arena><physics_engines><dynamics3d id=\"d3d\" "
         "stepper=\"worldstep\"/></physics_engines></colony>";
}

HandbotProbe& Probe(Simulation& sim) {
  return dynamic_cast<HandbotProbe&>(*sim.ControllerOf(sim.space().Find("h")));
}
using testing::PositionOf;
using testing::RunFor;

TEST(Handbot, TheHeadTurnsAtItsCommandedSpeed) {
  auto sim = LoadXml(Scene(""));
  HandbotProbe& p = Probe(*sim);
  // Hanging 0.2 m up, so the arms swing clear of the floor.
  p.rope->Launch();
  RunFor(*sim, 0.5);
  p.rope->SetClimbSpeed(0.1);
  RunFor(*sim, 2);
  p.rope->SetClimbSpeed(0);
  RunFor(*sim, 0.5);
  p.head->SetSpeed(1.0);
  p.head->SetRotation(1.2);
  RunFor(*sim, 0.6);
  EXPECT_NEAR(p.head_sensor->rotation(), 0.6, 0.05) << "0.6 s at 1 rad/s";
  EXPECT_NEAR(p.head_sensor->velocity(), 1.0, 0.05);
  RunFor(*sim, 1.4);
  EXPECT_NEAR(p.head_sensor->rotation(), 1.2, 0.01);
  EXPECT_FALSE(p.head_sensor->stalled());
  EXPECT_LT(std::abs(p.head_sensor->torque()), 0.5 * handbot::kHeadStallTorque)
      << "turning the balanced arms is easy";
}

TEST(Handbot, AnArmPushingABoardItCannotMoveStallsAtItsStallTorque) {
  // A fixed board 0.2 m ahead of the head: the left gripper meets it on the
  // way out; the robot is heavy enough not to slide back (25 kg).
  auto sim = LoadXml(Scene("<box id=\"board\" size=\"0.02,1,1\"><body position=\"0.3,0,0\"/></box>",
                           "mass=\"25\""));
  HandbotProbe& p = Probe(*sim);
  p.arms->SetExtension(kLeft, M_PI / 2);
  RunFor(*sim, 2);
  const double extension = p.arms_sensor->extension(kLeft);
  EXPECT_GT(extension, 0.2);
  EXPECT_LT(extension, M_PI / 2 - 0.2) << "stopped by the board";
  EXPECT_TRUE(p.arms_sensor->stalled(kLeft));
  EXPECT_NEAR(p.arms_sensor->torque(kLeft), handbot::kArmStallTorque,
              0.1 * handbot::kArmStallTorque);
  EXPECT_FALSE(p.arms_sensor->stalled(HandbotArmsActuator::kRight));
  // Folded back, it is free again.
  p.arms->SetExtension(kLeft, 0);
  RunFor(*sim, 2);
  EXPECT_NEAR(p.arms_sensor->extension(kLeft), 0.0, 0.02);
  EXPECT_FALSE(p.arms_sensor->stalled(kLeft));
}

// A book of `mass` standing on a shelf in front of the left gripper (the
// arm straight ahead puts the gripper's tip 0.335 m ahead, 0.06 m left,
// 0.18 m up).
std::string Shelf(double mass) {
  return "<box id=\"shelf\" size=\"0.3,0.4,0.05\"><body position=\"0.45,0.06,0.03\"/></box>"
         "<box id=\"book\" size=\"0.05,0.15,0.2\" movable=\"true\" mass=\"" +
         std::to_string(mass) + "\"><body position=\"0.365,0.06,0.0801\"/></box>";
}

TEST(Handbot, AGripperHoldsABookAsTheRobotClimbsAndASixKiloWeightSlipsOut) {
  for (const double mass : {0.3, 6.0}) {
    auto sim = LoadXml(Scene(Shelf(mass), "rope_force=\"200\""));
    HandbotProbe& p = Probe(*sim);
    p.arms->SetExtension(kLeft, M_PI / 2);
    RunFor(*sim, 1.5);
    p.grippers->Close(kLeft);
    RunFor(*sim, 2);
    ASSERT_TRUE(p.grippers_sensor->holding(kLeft)) << mass << " kg";
    EXPECT_NEAR(p.grippers_sensor->aperture(kLeft), 0.35, 0.01) << "the claws stop on the book";
    const double start = PositionOf(*sim, "book").z();
    p.rope->Launch();
    RunFor(*sim, 0.5);
    p.rope->SetClimbSpeed(0.1);
    RunFor(*sim, 3);
    p.rope->SetClimbSpeed(0);
    RunFor(*sim, 1);
    if (mass < 1) {
      // The robot rose 0.3 m; holding the book in front, it swings back
      // under the rope and drags the book off the shelf. (Holding 6 kg, it
      // tips forward about its grip as the rope pulls, until the weight
      // hangs from the claws and slips out, after about 2 s; the stretched
      // rope then throws it up: its height says nothing about the claws.)
      EXPECT_NEAR(PositionOf(*sim, "h").z(), 0.3, 0.03);
      EXPECT_TRUE(p.grippers_sensor->holding(kLeft));
      EXPECT_GT(PositionOf(*sim, "book").z() - start, 0.05) << "lifted off the shelf";
    } else {
      EXPECT_FALSE(p.grippers_sensor->holding(kLeft)) << "over the claws' 4 kg";
      EXPECT_NEAR(PositionOf(*sim, "book").z(), start, 0.03) << "left on the shelf";
    }
  }
}

TEST(Handbot, BothGrippersHoldOneBoard) {
  // The board's face 0.325 m ahead: the grippers' tips reach 0.335 m.
  auto sim = LoadXml(
      Scene("<box id=\"board\" size=\"0.04,0.6,0.9\"><body position=\"0.345,0,0\"/></box>"));
  HandbotProbe& p = Probe(*sim);
  for (int k = 0; k < 2; ++k) p.arms->SetExtension(k, M_PI / 2);
  RunFor(*sim, 1.5);
  for (int k = 0; k < 2; ++k) p.grippers->Close(k);
  RunFor(*sim, 2);
  EXPECT_TRUE(p.grippers_sensor->holding(0));
  EXPECT_TRUE(p.grippers_sensor->holding(1));
}

TEST(Handbot, OpeningTheClawsLetsGo) {
  auto sim = LoadXml(Scene(Shelf(0.3)));
  HandbotProbe& p = Probe(*sim);
  p.arms->SetExtension(kLeft, M_PI / 2);
  RunFor(*sim, 1.5);
  p.grippers->Close(kLeft);
  RunFor(*sim, 2);
  ASSERT_TRUE(p.grippers_sensor->holding(kLeft));
  p.grippers->Open(kLeft);
  RunFor(*sim, 2);
  EXPECT_FALSE(p.grippers_sensor->holding(kLeft));
  EXPECT_NEAR(p.grippers_sensor->aperture(kLeft), M_PI / 2, 1e-9);
  // Closing on nothing closes them completely.
  p.grippers->Close(HandbotGrippersActuator::kRight);
  RunFor(*sim, 2);
  EXPECT_FALSE(p.grippers_sensor->holding(HandbotGrippersActuator::kRight));
  EXPECT_NEAR(p.grippers_sensor->aperture(HandbotGrippersActuator::kRight), 0.0, 1e-9);
}

double YawOfRobot(Simulation& sim) {
  return YawOf(sim.space().pose(sim.space().Find("h").index).orientation);
}

TEST(Handbot, TheFansTurnTheHangingRobotAndHoldAHeading) {
  auto sim = LoadXml(Scene(""));
  HandbotProbe& p = Probe(*sim);
  p.rope->Launch();
  RunFor(*sim, 0.5);
  p.rope->SetClimbSpeed(0.1);
  RunFor(*sim, 2);
  p.rope->SetClimbSpeed(0);
  EXPECT_NEAR(YawOfRobot(*sim), 0.0, 1e-3);
  p.fans->SetTorque(0.05);
  RunFor(*sim, 2);
  const double turned = YawOfRobot(*sim);
  EXPECT_GT(turned, 0.2) << "a steady torque spins it up";
  p.fans->HoldHeading(-0.5);
  RunFor(*sim, 20);
  EXPECT_NEAR(YawOfRobot(*sim), -0.5, 0.05);
  EXPECT_LT(std::abs(sim->space().twist(sim->space().Find("h").index).angular.z()), 0.02);
}

TEST(Handbot, CommandsBeyondWhatTheMotorsCanDoAreCappedWithAWarning) {
  auto sim = LoadXml(Scene(""));
  HandbotProbe& p = Probe(*sim);
  ::testing::internal::CaptureStderr();
  p.head->SetSpeed(10);
  p.head->SetRotation(3);
  p.arms->SetExtension(kLeft, 3);
  p.fans->SetTorque(1);
  RunFor(*sim, 0.5);
  const std::string log = ::testing::internal::GetCapturedStderr();
  EXPECT_TRUE(Mentions(log, {"robot 'h'", "head speed 10 rad/s", "2.85"}));
  EXPECT_TRUE(Mentions(log, {"robot 'h'", "left arm 3 rad is outside [0, 1.5708]"}));
  EXPECT_TRUE(Mentions(log, {"robot 'h'", "fan torque 1 N m", "0.05 N m"}));
  EXPECT_LT(p.head_sensor->velocity(), handbot::kHeadNoLoadSpeed + 1e-6);
}

TEST(Handbot, BadSetupsAreRefusedAtLoad) {
  EXPECT_TRUE(Mentions(LoadError(Scene("", "mass=\"0.5\"")),
                       {"<handbot id=\"h\">", "mass", "no heavier than"}));
  // The hand-bot's devices on a marXbot.
  const std::string marxbot =
      "<colony><framework><experiment length=\"10\" ticks_per_second=\"10\"/></framework>"
      "<controllers><handbot_probe "
      "id=\"hp\"><actuators><handbot_head/><handbot_arms/><handbot_grippers/>"
      "<rope_launcher/></actuators><sensors><handbot_head/><handbot_arms/><handbot_grippers/></"
      "sensors>"
      "</handbot_probe></controllers><arena size=\"3,3,3\" center=\"0,0,1.5\"><marxbot id=\"m\">"
      "<body position=\"0,0,0\"/><controller config=\"hp\"/></marxbot></arena><physics_engines>"
      "<dynamics3d id=\"d3d\"/></physics_engines></colony>";
  EXPECT_TRUE(Mentions(LoadError(marxbot), {"<handbot_head>", "'m'", "handbot_arms"}));
}

}  // namespace
}  // namespace colony
