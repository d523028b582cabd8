// The eye-bot's flight as a controller sees it, in pointmass3d: it flies to
// a commanded point and heading and holds them, never faster than its
// limits; it cannot climb when heavier than its thrust; it holds to the
// ceiling only once touching it, rotors off, and flies or falls when it lets
// go; its altimeter reads the height above the floor or what is below.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <tuple>
#include <utility>

#include "actuators/eyebot_ceiling/eyebot_ceiling.h"
#include "actuators/eyebot_propulsion/eyebot_propulsion.h"
#include "core/registry.h"
#include "entities/eyebot/eyebot.h"
#include "sensors/eyebot_altitude/eyebot_altitude.h"
#include "sensors/eyebot_ceiling/eyebot_ceiling.h"
#include "tests/test_util.h"

namespace colony {
namespace {

using testing::LoadError;
using testing::LoadXml;
using testing::Mentions;
using testing::PositionOf;
using testing::RunFor;

// Gives the devices to the test, which commands them between steps.
class EyebotProbe : public Controller {
 public:
  void Init(const Params&) override {
    rotors = &GetActuator<EyebotPropulsionActuator>("eyebot_propulsion");
    hook = &GetActuator<EyebotCeilingActuator>("eyebot_ceiling");
    ceiling = &GetSensor<EyebotCeilingSensor>("eyebot_ceiling");
    altimeter = &GetSensor<EyebotAltitudeSensor>("eyebot_altitude");
  }
  void ControlStep() override {}
  EyebotPropulsionActuator* rotors = nullptr;
  EyebotCeilingActuator* hook = nullptr;
  const EyebotCeilingSensor* ceiling = nullptr;
  const EyebotAltitudeSensor* altimeter = nullptr;
};
COLONY_REGISTER_CONTROLLER(EyebotProbe, "eyebot_probe",
                           "test: the eye-bot's flight devices, commanded by the test");

// An arena 6 x 6 x 3 m with eye-bot "e" at `position`, flown by pointmass3d.
std::string Scene(const std::string& position, const std::string& eyebot_attributes = "",
                  const std::string& arena = "", const std::string& altimeter = "") {
  return "<colony><framework><experiment length=\"1000\" ticks_per_second=\"10\" "
         "random_seed=\"3\"/></framework><controllers><eyebot_probe id=\"ep\"><actuators>"
         "<eyebot_propulsion/><eyebot_ceiling/></actuators><sensors><eyebot_ceiling/>"
         "<eyebot_altitude " +
         altimeter +
         "/></sensors></eyebot_probe></controllers>"
         "<arena size=\"6,6,3\" center=\"0,0,1.5\">" +
         arena + "<eyebot id=\"e\" " + eyebot_attributes + "><body position=\"" + position +
         "\"/><controller config=\"ep\"/></eyebot></arena>"
         "<physics_engines><pointmass3d id=\"pm3d\"/></physics_engines></colony>";
}

EyebotProbe& Probe(Simulation& sim) {
  return dynamic_cast<EyebotProbe&>(*sim.ControllerOf(sim.space().Find("e")));
}
const Twist& TwistOf(const Simulation& sim) {
  return sim.space().twist(sim.space().Find("e").index);
}
const QuadrotorState& Rotors(const Simulation& sim) {
  return *sim.space().Get<QuadrotorState>(sim.space().Find("e").index);
}
double Yaw(const Simulation& sim) {
  return YawOf(sim.space().pose(sim.space().Find("e").index).orientation);
}

TEST(EyebotFlight, FliesToACommandedPointAndHoldsItAndItsHeading) {
  auto sim = LoadXml(Scene("0,0,0"));
  EyebotProbe& p = Probe(*sim);
  const Vec3 target(1, -0.5, 1.5);
  p.rotors->SetTargetPosition(target.x(), target.y(), target.z());
  p.rotors->SetTargetYaw(1.0);
  // About 1.6 s to climb 1.5 m at 1 m/s, braking included.
  double reached = -1;
  for (int t = 0; t < 100 && reached < 0; ++t) {
    sim->Step();
    if ((PositionOf(*sim, "e") - target).norm() < 0.02) reached = sim->time();
  }
  ASSERT_GT(reached, 0) << "still at " << PositionOf(*sim, "e").transpose();
  EXPECT_LT(reached, 4.0);
  double worst = 0;
  for (int t = 0; t < 50; ++t) {
    sim->Step();
    worst = std::max(worst, (PositionOf(*sim, "e") - target).norm());
  }
  EXPECT_LT(worst, 0.02) << "holds the point for 5 s";
  EXPECT_NEAR(Yaw(*sim), 1.0, 0.01);
  EXPECT_NEAR(Rotors(*sim).thrust, 9.81, 0.01) << "hovering, the rotors carry its 1 kg";
  EXPECT_NEAR(p.altimeter->altitude(), 1.5, 0.02);
}

TEST(EyebotFlight, AtTwoTicksPerSecondItStillReachesAndHoldsThePoint) {
  std::string xml = Scene("0,0,0");
  xml.replace(xml.find("ticks_per_second=\"10\""), 22, "ticks_per_second=\"2\"");
  auto sim = LoadXml(xml);
  Probe(*sim).rotors->SetTargetPosition(1, -0.5, 1.5);
  RunFor(*sim, 6);
  double worst = 0;
  for (int t = 0; t < 10; ++t) {
    sim->Step();
    worst = std::max(worst, (PositionOf(*sim, "e") - Vec3(1, -0.5, 1.5)).norm());
  }
  EXPECT_LT(worst, 0.02);
}

TEST(EyebotFlight, ARelativeTargetIsTakenInTheRobotsHeadingFrame) {
  // Facing +y: one metre forward is +y, half a metre left is -x.
  auto sim = LoadXml(Scene("0,0,0\" orientation=\"90,0,0"));
  EyebotProbe& p = Probe(*sim);
  p.rotors->SetRelativePosition(1, 0.5, 1);
  RunFor(*sim, 6);
  EXPECT_LT((PositionOf(*sim, "e") - Vec3(-0.5, 1, 1)).norm(), 0.02)
      << PositionOf(*sim, "e").transpose();
  EXPECT_NEAR(p.rotors->target_position()[1], 1.0, 1e-9) << "the world point, once applied";
  EXPECT_NEAR(Yaw(*sim), M_PI / 2, 0.01) << "it keeps the heading it had";
}

// Steps `ticks` times; the fastest horizontal and vertical speeds (m/s) of
// eye-bot "e" meanwhile.
std::pair<double, double> FastestOver(Simulation& sim, int ticks) {
  double fastest = 0, fastest_up = 0;
  for (int t = 0; t < ticks; ++t) {
    sim.Step();
    const Vec3& v = TwistOf(sim).linear;
    fastest = std::max(fastest, v.head<2>().norm());
    fastest_up = std::max(fastest_up, std::abs(v.z()));
  }
  return {fastest, fastest_up};
}

TEST(EyebotFlight, NeverFlyFasterThanItsLimitsInPositionMode) {
  auto sim = LoadXml(Scene("-2.5,-2.5,0", "max_speed=\"1.5\" max_vertical_speed=\"0.8\""));
  EyebotProbe& p = Probe(*sim);
  p.rotors->SetTargetPosition(2.5, 2.5, 2.5);
  auto [fastest, fastest_up] = FastestOver(*sim, 80);
  EXPECT_LE(fastest, 1.5 + 1e-9);
  EXPECT_GT(fastest, 1.4) << "and it does fly about that fast";
  EXPECT_LE(fastest_up, 0.8 + 1e-9);
  EXPECT_GT(fastest_up, 0.75);
  // On the way down too.
  p.rotors->SetTargetPosition(-2.5, -2.5, 0);
  std::tie(fastest, fastest_up) = FastestOver(*sim, 80);
  EXPECT_LE(fastest, 1.5 + 1e-9);
  EXPECT_LE(fastest_up, 0.8 + 1e-9);
  EXPECT_LT((PositionOf(*sim, "e") - Vec3(-2.5, -2.5, 0)).norm(), 0.02);
}

TEST(EyebotFlight, SpeedCommandsBeyondTheLimitsAreFlownAtTheLimitWithOneWarning) {
  auto sim = LoadXml(Scene("-2,0,0"));
  EyebotProbe& p = Probe(*sim);
  ::testing::internal::CaptureStderr();
  double fastest = 0, fastest_up = 0, fastest_turn = 0;
  for (int t = 0; t < 20; ++t) {
    p.rotors->SetVelocity(3, 0, 2);  // every tick: still one warning of each
    p.rotors->SetYawRate(4);
    sim->Step();
    const Twist& v = TwistOf(*sim);
    fastest = std::max(fastest, v.linear.head<2>().norm());
    fastest_up = std::max(fastest_up, std::abs(v.linear.z()));
    fastest_turn = std::max(fastest_turn, std::abs(v.angular.z()));
  }
  const std::string log = ::testing::internal::GetCapturedStderr();
  EXPECT_TRUE(
      Mentions(log, {"warning", "robot 'e'", "horizontal speed 3 m/s", "max_speed, 2 m/s"}));
  EXPECT_TRUE(Mentions(log, {"robot 'e'", "vertical speed 2 m/s", "max_vertical_speed, 1 m/s"}));
  EXPECT_TRUE(Mentions(log, {"robot 'e'", "yaw rate 4 rad/s", "1.5708 rad/s (90 degrees/s)"}));
  size_t count = 0;
  for (size_t at = log.find("horizontal speed"); at != std::string::npos;
       at = log.find("horizontal speed", at + 1)) {
    ++count;
  }
  EXPECT_EQ(count, 1u) << log;
  EXPECT_LE(fastest, 2.0 + 1e-9);
  EXPECT_GT(fastest, 1.9);
  EXPECT_LE(fastest_up, 1.0 + 1e-9);
  EXPECT_LE(fastest_turn, M_PI / 2 + 1e-9);
  EXPECT_GT(fastest_turn, M_PI / 2 - 1e-6);
}

TEST(EyebotFlight, ACommandThatIsNotANumberIsIgnoredWithAWarning) {
  auto sim = LoadXml(Scene("0,0,0"));
  EyebotProbe& p = Probe(*sim);
  p.rotors->SetTargetPosition(0, 0, 1);
  RunFor(*sim, 4);
  ::testing::internal::CaptureStderr();
  p.rotors->SetTargetPosition(std::nan(""), 0, 2);
  RunFor(*sim, 2);
  const std::string log = ::testing::internal::GetCapturedStderr();
  EXPECT_TRUE(Mentions(log, {"robot 'e'", "not a finite number", "previous"}));
  EXPECT_NEAR(PositionOf(*sim, "e").z(), 1.0, 0.02) << "still holding the last good target";
}

TEST(EyebotFlight, AnEyebotHeavierThanItsThrustStaysOnTheFloor) {
  ::testing::internal::CaptureStderr();
  auto sim = LoadXml(Scene("0,0,0", "mass=\"1.5\""));
  const std::string log = ::testing::internal::GetCapturedStderr();
  EXPECT_TRUE(Mentions(log, {"warning", "<eyebot", "1.5 kg", "cannot take off"})) << log;
  EyebotProbe& p = Probe(*sim);
  p.rotors->SetTargetPosition(0, 0, 1.5);
  double highest = 0;
  for (int t = 0; t < 30; ++t) {
    sim->Step();
    highest = std::max(highest, PositionOf(*sim, "e").z());
  }
  EXPECT_EQ(highest, 0.0);
  EXPECT_DOUBLE_EQ(Rotors(*sim).thrust, eyebot::kMaxThrust) << "rotors flat out";
  EXPECT_EQ(TwistOf(*sim).linear.norm(), 0.0);
}

TEST(EyebotFlight, ItHoldsToTheCeilingOnlyOnceTouchingItRotorsOff) {
  auto sim = LoadXml(Scene("0,0,0", "", "<ceiling height=\"2.5\"/>"));
  EyebotProbe& p = Probe(*sim);
  p.hook->Attach();
  p.rotors->SetTargetPosition(0, 0, 1.0);
  RunFor(*sim, 4);
  EXPECT_FALSE(p.ceiling->attached()) << "not touching: asking does nothing";
  EXPECT_NEAR(p.ceiling->ceiling_distance(), 2.5 - 1.0 - eyebot::kHeight, 0.02);
  // Up against the ceiling (the target is beyond it).
  p.rotors->SetTargetPosition(0, 0, 2.4);
  RunFor(*sim, 3);
  ASSERT_TRUE(p.ceiling->attached());
  EXPECT_NEAR(p.ceiling->ceiling_distance(), 0.0, 1e-9);
  const Vec3 held = PositionOf(*sim, "e");
  EXPECT_NEAR(held.z() + eyebot::kHeight, 2.5, 1e-9);
  // Rotors off or commanded elsewhere: it hangs still, rotors stopped.
  p.rotors->SetTargetPosition(1, 1, 1);
  for (int t = 0; t < 30; ++t) {
    sim->Step();
    EXPECT_EQ(PositionOf(*sim, "e"), held);
    EXPECT_EQ(Rotors(*sim).thrust, 0.0);
    EXPECT_EQ(TwistOf(*sim).linear.norm(), 0.0);
  }
  p.rotors->Off();
  RunFor(*sim, 2);
  EXPECT_EQ(PositionOf(*sim, "e"), held);
  // Let go with the rotors off: it falls to the floor.
  p.hook->Detach();
  RunFor(*sim, 0.5);
  EXPECT_FALSE(p.ceiling->attached());
  EXPECT_LT(PositionOf(*sim, "e").z(), held.z() - 0.5);
  RunFor(*sim, 1.5);
  EXPECT_EQ(PositionOf(*sim, "e").z(), 0.0);
  EXPECT_EQ(TwistOf(*sim).linear.z(), 0.0) << "landed";
}

TEST(EyebotFlight, LettingGoOfTheCeilingInPositionModeFliesToTheTarget) {
  // Starts attached, its top at the ceiling.
  auto sim = LoadXml(Scene("0,0,2.2", "attached=\"true\"", "<ceiling height=\"2.5\"/>"));
  EyebotProbe& p = Probe(*sim);
  RunFor(*sim, 1);
  EXPECT_TRUE(p.ceiling->attached());
  EXPECT_TRUE(p.hook->attach_requested());
  EXPECT_EQ(PositionOf(*sim, "e").z(), 2.2);
  p.rotors->SetTargetPosition(1, 0, 1);
  RunFor(*sim, 1);
  EXPECT_EQ(PositionOf(*sim, "e").z(), 2.2) << "still holding";
  p.hook->Detach();
  RunFor(*sim, 5);
  EXPECT_FALSE(p.ceiling->attached());
  EXPECT_LT((PositionOf(*sim, "e") - Vec3(1, 0, 1)).norm(), 0.02);
}

TEST(EyebotFlight, DeclaredAttachedAwayFromTheCeilingItWarnsAndHoldsOnceThere) {
  ::testing::internal::CaptureStderr();
  auto sim = LoadXml(Scene("0,0,1", "attached=\"true\"", "<ceiling height=\"2.5\"/>"));
  const std::string log = ::testing::internal::GetCapturedStderr();
  EXPECT_TRUE(Mentions(log, {"warning", "eye-bot 'e'", "attached=\"true\"", "top is at 1.3 m",
                             "the ceiling at 2.5 m"}))
      << log;
  EyebotProbe& p = Probe(*sim);
  p.rotors->SetVelocity(0, 0, 0.5);
  RunFor(*sim, 0.5);
  EXPECT_FALSE(p.ceiling->attached());
  RunFor(*sim, 4);
  EXPECT_TRUE(p.ceiling->attached());
  EXPECT_NEAR(PositionOf(*sim, "e").z(), 2.2, 0.011);
  // Declared at the ceiling: no warning.
  ::testing::internal::CaptureStderr();
  LoadXml(Scene("0,0,2.2", "attached=\"true\"", "<ceiling height=\"2.5\"/>"));
  EXPECT_EQ(::testing::internal::GetCapturedStderr().find("attached"), std::string::npos);
}

TEST(EyebotFlight, TheAltimeterReadsTheHeightAboveTheFloorOrWhatIsBelow) {
  auto sim = LoadXml(Scene("0,0,0", "",
                           "<box id=\"table\" size=\"0.8,0.8,0.5\"><body position=\"1.5,0,0\"/>"
                           "</box>"));
  EyebotProbe& p = Probe(*sim);
  RunFor(*sim, 0.1);
  EXPECT_EQ(p.altimeter->altitude(), 0.0) << "standing on the floor";
  p.rotors->SetTargetPosition(0, 0, 1.2);
  RunFor(*sim, 4);
  EXPECT_NEAR(p.altimeter->altitude(), 1.2, 0.01);
  p.rotors->SetTargetPosition(1.5, 0, 1.2);
  RunFor(*sim, 4);
  EXPECT_NEAR(p.altimeter->altitude(), 0.7, 0.01) << "above the 0.5 m table";
  // Landed on the table.
  p.rotors->Off();
  RunFor(*sim, 2);
  EXPECT_NEAR(PositionOf(*sim, "e").z(), 0.5, 1e-9);
  EXPECT_EQ(p.altimeter->altitude(), 0.0);
}

TEST(EyebotFlight, BeyondItsRangeTheAltimeterReadsInfinityAndItsNoiseIsItsOwn) {
  auto sim = LoadXml(Scene("0,0,0", "", "", "range=\"1\""));
  EyebotProbe& p = Probe(*sim);
  p.rotors->SetTargetPosition(0, 0, 1.5);
  RunFor(*sim, 4);
  EXPECT_EQ(p.altimeter->altitude(), std::numeric_limits<double>::infinity());
  EXPECT_EQ(p.altimeter->range(), 1.0);
  auto noisy = LoadXml(Scene("0,0,1", "", "", "noise=\"gaussian\" noise_std_dev=\"0.01\""));
  EyebotProbe& q = Probe(*noisy);
  q.rotors->SetTargetPosition(0, 0, 1);
  double sum = 0, sum2 = 0;
  const int n = 200;
  for (int t = 0; t < n; ++t) {
    noisy->Step();
    sum += q.altimeter->altitude();
    sum2 += q.altimeter->altitude() * q.altimeter->altitude();
  }
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 1.0, 0.005);
  EXPECT_NEAR(sd, 0.01, 0.003);
}

TEST(EyebotFlight, BadSetupsAreRefusedAtLoad) {
  // No engine of the experiment flies eye-bots.
  std::string k2d = Scene("0,0,0");
  k2d.replace(k2d.find("<pointmass3d id=\"pm3d\"/>"), 24, "<kinematics2d id=\"k2d\"/>");
  EXPECT_TRUE(Mentions(LoadError(k2d), {"kinematics2d", "eyebot", "pointmass3d"}));
  EXPECT_TRUE(Mentions(LoadError(Scene("0,0,0", "max_speed=\"0\"")),
                       {"<eyebot id=\"e\">", "max_speed", "'0'", "> 0"}));
  EXPECT_TRUE(Mentions(LoadError(Scene("0,0,0", "mass=\"heavy\"")), {"mass", "'heavy'"}));
  EXPECT_TRUE(Mentions(LoadError(Scene("0,0,0", "", "", "range=\"-1\"")),
                       {"<eyebot_altitude>", "range", "'-1'"}));
  EXPECT_TRUE(Mentions(LoadError(Scene("0,0,0", "", "", "noise=\"loud\"")),
                       {"<eyebot_altitude>", "noise", "'loud'"}));
  // Flight devices on a robot without rotors.
  const std::string marxbot =
      "<colony><framework><experiment length=\"10\" ticks_per_second=\"10\"/></framework>"
      "<controllers><eyebot_probe id=\"ep\"><actuators><eyebot_propulsion/><eyebot_ceiling/>"
      "</actuators><sensors><eyebot_ceiling/><eyebot_altitude/></sensors></eyebot_probe>"
      "</controllers><arena size=\"3,3,1\" center=\"0,0,0.5\"><marxbot id=\"m\"><body "
      "position=\"0,0,0\"/><controller config=\"ep\"/></marxbot></arena><physics_engines>"
      "<kinematics2d id=\"k2d\"/></physics_engines></colony>";
  EXPECT_TRUE(Mentions(LoadError(marxbot), {"<eyebot_propulsion>", "'m'", "quadrotor"}));
}

TEST(EyebotFlight, RegisteredAttributesMatchTheReadmes) {
  auto with_implementation = [](std::vector<std::string> names) {
    names.push_back("implementation");
    return names;
  };
  EXPECT_EQ(testing::ReadmeAttributes("sensors/eyebot_altitude"),
            with_implementation(
                Registry<SensorSystem>::Get().Find("eyebot_altitude")->info.AttributeNames()));
  EXPECT_EQ(testing::ReadmeAttributes("sensors/eyebot_ceiling"),
            with_implementation(
                Registry<SensorSystem>::Get().Find("eyebot_ceiling")->info.AttributeNames()));
  EXPECT_EQ(testing::ReadmeAttributes("actuators/eyebot_propulsion"),
            with_implementation(
                Registry<ActuatorSystem>::Get().Find("eyebot_propulsion")->info.AttributeNames()));
  EXPECT_EQ(testing::ReadmeAttributes("actuators/eyebot_ceiling"),
            with_implementation(
                Registry<ActuatorSystem>::Get().Find("eyebot_ceiling")->info.AttributeNames()));
  std::vector<std::string> entity = {"id"};
  for (const auto& a : Registry<EntityType>::Get().Find("eyebot")->info.AttributeNames())
    entity.push_back(a);
  EXPECT_EQ(testing::ReadmeAttributes("entities/eyebot"), entity);
}

}  // namespace
}  // namespace colony
