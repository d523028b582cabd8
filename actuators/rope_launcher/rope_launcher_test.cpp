// The hand-bot's rope as a controller sees it (rope launcher actuator, rope
// traction sensor) in dynamics3d: a launch attaches to a ferromagnetic
// ceiling within reach and fails otherwise; climbing lifts the robot, the
// traction reads its weight while it hangs, going down returns it; the
// motor's speed and force limit what it does; bad setups are refused.
#include "actuators/rope_launcher/rope_launcher.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "actuators/rope_launcher/rope_state.h"
#include "core/registry.h"
#include "entities/handbot/handbot.h"
#include "sensors/rope_traction/rope_traction.h"
#include "tests/test_util.h"

namespace colony {
namespace {

using testing::LoadError;
using testing::LoadXml;
using testing::Mentions;

// Sends the commands in its public fields, copies what the sensor read.
class RopeProbe : public Controller {
 public:
  void Init(const Params&) override {
    rope_ = &GetActuator<RopeLauncherActuator>("rope_launcher");
    sensor = &GetSensor<RopeTractionSensor>("rope_traction");
  }
  void ControlStep() override {
    if (launch) rope_->Launch();
    if (retrieve) rope_->Retrieve();
    launch = retrieve = false;
    rope_->SetClimbSpeed(climb);
  }
  bool launch = false, retrieve = false;
  double climb = 0;
  const RopeTractionSensor* sensor = nullptr;

 private:
  RopeLauncherActuator* rope_ = nullptr;
};
COLONY_REGISTER_CONTROLLER(RopeProbe, "rope_probe", "test: scripted rope, records its sensor");

constexpr double kGravity = 9.81;

// A hand-bot at the origin of a 3 x 3 x 3 m arena.
std::string Scene(const std::string& ceiling, const std::string& handbot_attributes = "",
                  const std::string& more = "",
                  const std::string& engine = "<dynamics3d id=\"d3d\" stepper=\"worldstep\"/>") {
  return "<colony><framework><experiment length=\"100\" ticks_per_second=\"10\" "
         "random_seed=\"3\"/></framework>"
         "<controllers><rope_probe "
         "id=\"rp\"><actuators><rope_launcher/></actuators><sensors><rope_traction/>"
         "</sensors></rope_probe></controllers><arena size=\"3,3,3\" center=\"0,0,1.5\">" +
         ceiling + "<handbot id=\"h\" " + handbot_attributes +
         "><body position=\"0,0,0\"/><controller config=\"rp\"/></handbot>" + more +
         "</arena><physics_engines>" + engine + "</physics_engines></colony>";
}

RopeProbe& Probe(Simulation& sim) {
  return dynamic_cast<RopeProbe&>(*sim.ControllerOf(sim.space().Find("h")));
}
double Height(Simulation& sim) {
  return sim.space().pose(sim.space().Find("h").index).position.z();
}
using testing::RunFor;

TEST(RopeLauncher, ALaunchedRopeHoldsToACeiling2_5mUpAndTheTractionReadsTheWeightWhileItHangs) {
  auto sim = LoadXml(Scene("<ceiling height=\"2.5\"/>"));
  RopeProbe& p = Probe(*sim);
  RunFor(*sim, 0.5);
  EXPECT_EQ(p.sensor->status(), RopeTractionSensor::Status::kStowed);
  EXPECT_EQ(p.sensor->length(), 0.0);
  p.launch = true;
  RunFor(*sim, 0.5);
  ASSERT_TRUE(p.sensor->attached());
  // From the launcher's top (0.33 m) to the ceiling.
  EXPECT_NEAR(p.sensor->length(), 2.5 - handbot::kHeight, 0.005);
  EXPECT_LT(p.sensor->traction(), 1.0) << "standing on the floor, the rope is slack";
  p.climb = 0.1;
  RunFor(*sim, 3);
  EXPECT_NEAR(Height(*sim), 0.3, 0.02) << "3 s at 0.1 m/s";
  p.climb = 0;
  RunFor(*sim, 2);
  EXPECT_NEAR(Height(*sim), 0.3, 0.02) << "holding";
  EXPECT_NEAR(p.sensor->traction(), 2.0 * kGravity, 0.05 * 2.0 * kGravity) << "the hand-bot's 2 kg";
  EXPECT_NEAR(p.sensor->length(), 2.5 - handbot::kHeight - 0.3, 0.02);
  EXPECT_FALSE(p.sensor->stalled());
}

TEST(RopeLauncher, ALaunchFailsWithoutAFerromagneticCeilingWithinReach) {
  for (const std::string& ceiling :
       {std::string(""), std::string("<ceiling height=\"2.5\" ferromagnetic=\"false\"/>"),
        std::string("<ceiling height=\"3\"/>")}) {
    // The last: the ceiling 2.67 m above the launcher, a rope of 2.5 m.
    auto sim = LoadXml(
        Scene(ceiling, ceiling.find("\"3\"") != std::string::npos ? "rope_length=\"2.5\"" : ""));
    RopeProbe& p = Probe(*sim);
    p.launch = true;
    RunFor(*sim, 0.5);
    EXPECT_TRUE(p.sensor->launch_failed()) << ceiling;
    EXPECT_EQ(p.sensor->traction(), 0.0);
    p.climb = 0.1;
    RunFor(*sim, 1);
    EXPECT_NEAR(Height(*sim), 0.0, 1e-3) << "nothing to climb";
  }
  // A board over the robot stops the magnet before the ceiling.
  auto sim =
      LoadXml(Scene("<ceiling height=\"2.5\"/>", "",
                    "<box id=\"board\" size=\"0.5,0.5,0.02\"><body position=\"0,0,1.5\"/></box>"));
  RopeProbe& p = Probe(*sim);
  p.launch = true;
  RunFor(*sim, 0.5);
  EXPECT_TRUE(p.sensor->launch_failed());
  // The launch can be tried again.
  p.launch = true;
  RunFor(*sim, 0.5);
  EXPECT_TRUE(p.sensor->launch_failed());
}

// Fires the rope, climbs 0.2 m (2 s at 0.1 m/s) and hangs `hold` seconds.
void LaunchClimbAndHold(Simulation& sim, RopeProbe& p, double hold) {
  p.launch = true;
  RunFor(sim, 0.5);
  p.climb = 0.1;
  RunFor(sim, 2);
  p.climb = 0;
  RunFor(sim, hold);
}

TEST(RopeLauncher, ClimbingUpHalfAMetreAndBackDownReturnsToTheStartHeight) {
  auto sim = LoadXml(Scene("<ceiling height=\"2.5\"/>"));
  RopeProbe& p = Probe(*sim);
  LaunchClimbAndHold(*sim, p, 1);
  const double start = Height(*sim);
  EXPECT_NEAR(start, 0.2, 0.02);
  p.climb = 0.1;
  RunFor(*sim, 5);
  EXPECT_NEAR(Height(*sim) - start, 0.5, 0.02);
  p.climb = -0.1;
  RunFor(*sim, 5);
  p.climb = 0;
  RunFor(*sim, 1);
  EXPECT_NEAR(Height(*sim), start, 0.01);
  // Letting the rope out further lowers it to the floor, where the rope goes slack.
  p.climb = -0.1;
  RunFor(*sim, 4);
  EXPECT_NEAR(Height(*sim), 0.0, 2e-3);
  EXPECT_LT(p.sensor->traction(), 1.0);
}

TEST(RopeLauncher, ClimbingFasterThanTheMotorMovesAtItsFastest) {
  auto sim = LoadXml(Scene("<ceiling height=\"2.5\"/>", "climb_speed=\"0.05\""));
  RopeProbe& p = Probe(*sim);
  p.launch = true;
  RunFor(*sim, 0.5);
  ::testing::internal::CaptureStderr();
  p.climb = 0.5;
  RunFor(*sim, 4);
  const std::string log = ::testing::internal::GetCapturedStderr();
  EXPECT_NEAR(Height(*sim), 0.2, 0.02) << "4 s at 0.05 m/s";
  EXPECT_TRUE(Mentions(log, {"warning", "robot 'h'", "0.5 m/s", "0.05 m/s"}));
}

TEST(RopeLauncher, AMotorTooWeakForTheRobotStallsAndTheSensorSaysSo) {
  // 15 N cannot lift 2 kg (19.6 N).
  auto sim = LoadXml(Scene("<ceiling height=\"2.5\"/>", "rope_force=\"15\""));
  RopeProbe& p = Probe(*sim);
  p.launch = true;
  RunFor(*sim, 0.5);
  p.climb = 0.1;
  RunFor(*sim, 3);
  EXPECT_LT(Height(*sim), 0.01) << "still on the floor";
  EXPECT_TRUE(p.sensor->stalled());
  EXPECT_GT(p.sensor->traction(), 14.0);
  EXPECT_LT(p.sensor->traction(), 2.0 * kGravity);
}

TEST(RopeLauncher, RetrievingTheRopeDropsAHangingRobot) {
  auto sim = LoadXml(Scene("<ceiling height=\"2.5\"/>"));
  RopeProbe& p = Probe(*sim);
  p.launch = true;
  RunFor(*sim, 0.5);
  p.climb = 0.1;
  RunFor(*sim, 2);
  p.climb = 0;
  p.retrieve = true;
  RunFor(*sim, 2);
  EXPECT_EQ(p.sensor->status(), RopeTractionSensor::Status::kStowed);
  EXPECT_NEAR(Height(*sim), 0.0, 0.01) << "fell back to the floor";
  p.launch = true;  // and it can launch again
  RunFor(*sim, 0.5);
  EXPECT_TRUE(p.sensor->attached());
}

TEST(RopeLauncher, BadSetupsAreRefusedAtLoad) {
  // A hand-bot in a 2D engine.
  EXPECT_TRUE(Mentions(LoadError(Scene("", "", "", "<kinematics2d id=\"k2d\"/>")),
                       {"handbot", "kinematics2d"}));
  // The rope devices on a robot without a rope.
  const std::string marxbot =
      "<colony><framework><experiment length=\"10\" ticks_per_second=\"10\"/></framework>"
      "<controllers><rope_probe "
      "id=\"rp\"><actuators><rope_launcher/></actuators><sensors><rope_traction/>"
      "</sensors></rope_probe></controllers><arena size=\"3,3,3\" center=\"0,0,1.5\"><marxbot "
      "id=\"m\">"
      "<body position=\"0,0,0\"/><controller config=\"rp\"/></marxbot></arena><physics_engines>"
      "<dynamics3d id=\"d3d\"/></physics_engines></colony>";
  EXPECT_TRUE(Mentions(LoadError(marxbot), {"<rope_launcher>", "'m'", "rope"}));
  // A ceiling lower than the hand-bot (0.33 m tall).
  EXPECT_TRUE(Mentions(LoadError(Scene("<ceiling height=\"0.3\"/>")),
                       {"'h'", "reaches above the ceiling"}));
  // Bad attributes.
  EXPECT_TRUE(Mentions(LoadError(Scene("", "rope_length=\"-1\"")),
                       {"<handbot id=\"h\">", "rope_length", "'-1'"}));
  EXPECT_TRUE(Mentions(LoadError(Scene("", "climb_speed=\"fast\"")), {"climb_speed", "'fast'"}));
  EXPECT_TRUE(Mentions(LoadError(Scene("", "rope_stiffness=\"0\"")),
                       {"rope_stiffness", "'0'", "out of range"}));
}

TEST(RopeLauncher, TheRopeStretchesUnderTheRobotsWeight) {
  // Hanging still, a 2 kg robot stretches a 5000 N/m rope 3.9 mm, a 1000 N/m
  // one 19.6 mm: the launcher's top is that much farther from the magnet
  // than the rope let out.
  for (const double k : {5000.0, 1000.0}) {
    auto sim =
        LoadXml(Scene("<ceiling height=\"2.5\"/>", "rope_stiffness=\"" + std::to_string(k) + "\""));
    RopeProbe& p = Probe(*sim);
    LaunchClimbAndHold(*sim, p, 3);
    const RopeState& rope = *sim->space().Get<RopeState>(sim->space().Find("h").index);
    EXPECT_NEAR(rope.length - rope.paid_out, 2 * kGravity / k, 0.1 * 2 * kGravity / k) << k;
    EXPECT_NEAR(p.sensor->traction(), 2 * kGravity, 0.2) << k;
  }
}

TEST(RopeLauncher, SameResultsWhateverTheThreadCount) {
  uint64_t hashes[3];
  for (int threads = 0; threads <= 2; ++threads) {
    auto sim = LoadXml(Scene("<ceiling height=\"2.5\"/>"), {}, threads);
    RopeProbe& p = Probe(*sim);
    p.launch = true;
    RunFor(*sim, 0.5);
    p.climb = 0.1;
    RunFor(*sim, 3);
    hashes[threads] = sim->StateHash();
  }
  EXPECT_EQ(hashes[0], hashes[1]);
  EXPECT_EQ(hashes[1], hashes[2]);
}

}  // namespace
}  // namespace colony
