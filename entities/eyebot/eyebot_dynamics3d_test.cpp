// The eye-bot in dynamics3d (entities/eyebot/dynamics3d_model.cpp), as a
// user would see it: it flies to a point and hovers there level; too heavy
// for its rotors it stays on the floor; it hangs from the ceiling with its
// rotors off and flies again when it lets go; it flies over a foot-bot and
// lands on it. The test commands the robot's components directly between
// ticks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/registry.h"
#include "entities/eyebot/eyebot.h"
#include "entities/marxbot/marxbot.h"
#include "tests/test_util.h"

namespace colony {
namespace {

using testing::LoadXml;
using testing::PositionOf;
using testing::RunFor;

// A controller that does nothing: the test drives the components.
class EyebotIdle : public Controller {
 public:
  void ControlStep() override {}
};
COLONY_REGISTER_CONTROLLER(EyebotIdle, "eyebot_d3d_idle", "test: does nothing");

constexpr double kDegree = M_PI / 180;

std::string Eyebot(const std::string& id, const std::string& position,
                   const std::string& attributes = "") {
  return "<eyebot id=\"" + id + "\" " + attributes + "><body position=\"" + position +
         "\"/><controller config=\"idle\"/></eyebot>";
}

// A 4 m x 4 m arena, 3 m high, around `body`.
std::string Scene(const std::string& body, const std::string& engine = "") {
  return "<colony><framework><experiment length=\"100\" ticks_per_second=\"10\" "
         "random_seed=\"3\"/></framework>"
         "<controllers><eyebot_d3d_idle id=\"idle\"/></controllers>"
         "<arena size=\"4,4,3\" center=\"0,0,1.5\">" +
         body + "</arena><physics_engines><dynamics3d id=\"d3d\" " + engine +
         "/></physics_engines></colony>";
}

uint32_t Slot(const Simulation& sim, const std::string& id) { return sim.space().Find(id).index; }
QuadrotorState& Rotors(Simulation& sim, const std::string& id) {
  return *sim.space().Get<QuadrotorState>(Slot(sim, id));
}
CeilingAttachmentState& Attachment(Simulation& sim, const std::string& id) {
  return *sim.space().Get<CeilingAttachmentState>(Slot(sim, id));
}
void FlyTo(Simulation& sim, const std::string& id, const Vec3& target, double yaw = 0) {
  QuadrotorState& q = Rotors(sim, id);
  q.mode = QuadrotorState::Mode::kPosition;
  q.target_position = target;
  q.target_yaw = yaw;
}
// Angle between the body's axis and the vertical (rad).
double Tilt(const Simulation& sim, const std::string& id) {
  const Vec3 up = sim.space().pose(Slot(sim, id)).orientation * Vec3::UnitZ();
  return std::acos(std::clamp(up.z(), -1.0, 1.0));
}

TEST(EyebotDynamics3d, TheFlightComputerCompensatesTheEnginesGravity) {
  // On Mars: the rotors carry 1 kg x 3.71 m/s^2, not 9.81.
  auto sim = LoadXml(Scene(Eyebot("e", "0,0,0"), "gravity=\"0,0,-3.71\""));
  const Vec3 target(0, 0, 1);
  FlyTo(*sim, "e", target);
  RunFor(*sim, 8);
  EXPECT_LT((PositionOf(*sim, "e") - target).norm(), 0.02) << PositionOf(*sim, "e").transpose();
  EXPECT_NEAR(Rotors(*sim, "e").thrust, eyebot::kMass * 3.71, 0.05);
}

TEST(EyebotDynamics3d, FliesToAPointAndHoversThereLevel) {
  auto sim = LoadXml(Scene(Eyebot("e", "0,0,0")));
  const Vec3 target(0.5, -0.5, 1.2);
  FlyTo(*sim, "e", target, 1.0);
  double worst_tilt = 0;
  for (int t = 0; t < 60; ++t) {
    sim->Step();
    worst_tilt = std::max(worst_tilt, Tilt(*sim, "e"));
  }
  EXPECT_LT(worst_tilt, 3 * kDegree) << "the attitude loop keeps it level while it flies";
  EXPECT_LT((PositionOf(*sim, "e") - target).norm(), 0.02) << PositionOf(*sim, "e").transpose();
  // It holds the point, level, its rotors carrying its weight.
  for (int t = 0; t < 30; ++t) {
    sim->Step();
    ASSERT_LT((PositionOf(*sim, "e") - target).norm(), 0.02) << "tick " << t;
    ASSERT_LT(Tilt(*sim, "e"), 0.5 * kDegree) << "tick " << t;
  }
  EXPECT_NEAR(YawOf(sim->space().pose(Slot(*sim, "e")).orientation), 1.0, 0.02);
  EXPECT_NEAR(Rotors(*sim, "e").thrust, eyebot::kMass * 9.81, 0.1);
  EXPECT_LT(sim->space().twist(Slot(*sim, "e")).linear.norm(), 0.01);
}

TEST(EyebotDynamics3d, TheAttitudeLoopLevelsATiltedBody) {
  for (const std::string engine : {"", "substeps=\"1\"", "stepper=\"worldstep\""}) {
    SCOPED_TRACE(engine);
    auto sim =
        LoadXml(Scene("<eyebot id=\"e\"><body position=\"0,0,1\" orientation=\"0,10,25\"/>"
                      "<controller config=\"idle\"/></eyebot>",
                      engine));
    FlyTo(*sim, "e", Vec3(0, 0, 1));
    EXPECT_NEAR(Tilt(*sim, "e"), 27 * kDegree, 1 * kDegree);
    // Back to level in a second, without swinging through.
    double tilt = Tilt(*sim, "e");
    for (int t = 0; t < 10; ++t) {
      sim->Step();
      ASSERT_LE(Tilt(*sim, "e"), tilt) << "tick " << t;
      tilt = Tilt(*sim, "e");
    }
    EXPECT_LT(tilt, 0.1 * kDegree);
    EXPECT_LT((PositionOf(*sim, "e") - Vec3(0, 0, 1)).norm(), 0.02);
  }
}

TEST(EyebotDynamics3d, FliesAtACommandedVelocityAndStopsWhenTheRotorsStop) {
  auto sim = LoadXml(Scene(Eyebot("e", "0,0,0")));
  QuadrotorState& q = Rotors(*sim, "e");
  q.mode = QuadrotorState::Mode::kSpeed;
  q.target_velocity = Vec3(0, 0, 0.5);
  RunFor(*sim, 2);
  q.target_velocity = Vec3(0.4, 0.3, 0);
  q.target_yaw_rate = 0.5;
  RunFor(*sim, 2);
  const Twist& twist = sim->space().twist(Slot(*sim, "e"));
  EXPECT_NEAR(twist.linear.x(), 0.4, 0.02);
  EXPECT_NEAR(twist.linear.y(), 0.3, 0.02);
  EXPECT_NEAR(twist.linear.z(), 0.0, 0.02);
  EXPECT_NEAR(twist.angular.z(), 0.5, 0.02);
  EXPECT_GT(PositionOf(*sim, "e").z(), 0.8);
  // Rotors off: it falls to the floor and lies there, thrust 0.
  q.mode = QuadrotorState::Mode::kOff;
  RunFor(*sim, 2);
  EXPECT_NEAR(PositionOf(*sim, "e").z(), 0.0, 0.005);
  EXPECT_EQ(q.thrust, 0.0);
}

TEST(EyebotDynamics3d, TooHeavyForItsRotorsItCannotClimb) {
  auto sim = LoadXml(Scene(Eyebot("e", "0,0,0", "mass=\"1.5\"")));
  FlyTo(*sim, "e", Vec3(0, 0, 1.2));
  for (int t = 0; t < 30; ++t) {
    sim->Step();
    ASSERT_LT(PositionOf(*sim, "e").z(), 0.002) << "tick " << t;
  }
  EXPECT_NEAR(Rotors(*sim, "e").thrust, eyebot::kMaxThrust, 1e-9) << "full thrust, in vain";
}

// Both ODE steppers.
const std::string kSteppers[] = {"stepper=\"quickstep\"", "stepper=\"worldstep\""};

TEST(EyebotDynamics3d, HangsFromTheCeilingWithItsRotorsOffAndFliesWhenItLetsGo) {
  for (const std::string& stepper : kSteppers) {
    SCOPED_TRACE(stepper);
    auto sim = LoadXml(Scene("<ceiling height=\"2.5\"/>" + Eyebot("e", "0,0,0"), stepper));
    const double feet = 2.5 - eyebot::kHeight;  // with its top against the ceiling
    CeilingAttachmentState& c = Attachment(*sim, "e");
    // Asked to attach far from the ceiling: nothing to hold to.
    c.attach = true;
    FlyTo(*sim, "e", Vec3(0.2, 0.1, 1.0));
    RunFor(*sim, 3);
    EXPECT_FALSE(c.attached);
    // Climbing beyond the ceiling: it stops against it, and holds.
    c.attach = false;
    FlyTo(*sim, "e", Vec3(0.2, 0.1, 3.0));
    RunFor(*sim, 3);
    EXPECT_NEAR(PositionOf(*sim, "e").z(), feet, 0.005) << "the ceiling stops it";
    EXPECT_FALSE(c.attached);
    EXPECT_GT(Rotors(*sim, "e").thrust, 0.0);
    c.attach = true;
    sim->Step();
    EXPECT_TRUE(c.attached);
    // Hanging, rotors off: it stays where it is.
    Rotors(*sim, "e").mode = QuadrotorState::Mode::kOff;
    const Vec3 hang = PositionOf(*sim, "e");
    for (int t = 0; t < 30; ++t) {
      sim->Step();
      ASSERT_LT((PositionOf(*sim, "e") - hang).norm(), 0.001) << "tick " << t;
      ASSERT_EQ(Rotors(*sim, "e").thrust, 0.0);
    }
    // Still attached with a position command: rotors off all the same.
    FlyTo(*sim, "e", Vec3(0.2, 0.1, 1.0));
    RunFor(*sim, 1);
    EXPECT_EQ(Rotors(*sim, "e").thrust, 0.0);
    EXPECT_LT((PositionOf(*sim, "e") - hang).norm(), 0.001);
    // Let go: it flies down to the point.
    c.attach = false;
    sim->Step();
    EXPECT_FALSE(c.attached);
    RunFor(*sim, 4);
    EXPECT_LT((PositionOf(*sim, "e") - Vec3(0.2, 0.1, 1.0)).norm(), 0.02);
  }
}

TEST(EyebotDynamics3d, StartsHangingFromTheCeilingWhenPlacedThere) {
  auto sim =
      LoadXml(Scene("<ceiling height=\"2.5\"/>" + Eyebot("e", "1,1,2.2", "attached=\"true\"")));
  RunFor(*sim, 2);
  EXPECT_TRUE(Attachment(*sim, "e").attached);
  EXPECT_LT((PositionOf(*sim, "e") - Vec3(1, 1, 2.2)).norm(), 0.001);
}

TEST(EyebotDynamics3d, FliesOverAFootbotAndLandsOnIt) {
  for (const std::string& stepper : kSteppers) {
    SCOPED_TRACE(stepper);
    auto sim = LoadXml(Scene(
        Eyebot("e", "-1,0,0") +
            "<marxbot id=\"f\"><body position=\"0,0,0\"/><controller config=\"idle\"/></marxbot>",
        stepper));
    const uint32_t e = Slot(*sim, "e");
    FlyTo(*sim, "e", Vec3(-1, 0, 0.6));
    RunFor(*sim, 3);
    FlyTo(*sim, "e", Vec3(1, 0, 0.6));
    double crossing = 0;  // its feet's height as it crossed over the foot-bot's axis
    for (int t = 0; t < 40; ++t) {
      const Vec3 before = PositionOf(*sim, "e");
      sim->Step();
      const Vec3 after = PositionOf(*sim, "e");
      if (before.x() < 0 && after.x() >= 0) crossing = after.z();
      ASSERT_FALSE(sim->space().in_contact(e)) << "tick " << t;
    }
    EXPECT_NEAR(crossing, 0.6, 0.01) << "over the foot-bot's top, at 0.147 m";
    EXPECT_LT((PositionOf(*sim, "e") - Vec3(1, 0, 0.6)).norm(), 0.02);
    // Down onto the foot-bot: it lands on its top and stops there.
    FlyTo(*sim, "e", Vec3(0, 0, 0.6));
    RunFor(*sim, 3);
    FlyTo(*sim, "e", Vec3(0, 0, 0));
    RunFor(*sim, 4);
    Rotors(*sim, "e").mode = QuadrotorState::Mode::kOff;
    RunFor(*sim, 2);
    EXPECT_NEAR(PositionOf(*sim, "e").z(), marxbot::kBodyHeight, 0.005);
    EXPECT_LT(Tilt(*sim, "e"), 1 * kDegree);
    EXPECT_LT(PositionOf(*sim, "f").norm(), 0.01) << "the foot-bot carries it where it stood";
  }
}

TEST(EyebotDynamics3d, TwoEyebotsMeetingInTheAirCollideAndFlyOnLevel) {
  auto sim = LoadXml(Scene(Eyebot("a", "-1,0,0") + Eyebot("b", "1,0.1,0")));
  FlyTo(*sim, "a", Vec3(-1, 0, 0.5));
  FlyTo(*sim, "b", Vec3(1, 0.1, 0.5));
  RunFor(*sim, 3);
  FlyTo(*sim, "a", Vec3(1, 0, 0.5));
  FlyTo(*sim, "b", Vec3(-1, 0.1, 0.5));
  bool touched = false;
  double worst_tilt = 0;
  for (int t = 0; t < 60; ++t) {
    sim->Step();
    const Vec3 d = PositionOf(*sim, "b") - PositionOf(*sim, "a");
    ASSERT_GT(d.head<2>().norm(), 2 * eyebot::kRadius - 0.01) << "tick " << t;
    touched = touched || sim->space().in_contact(Slot(*sim, "a"));
    worst_tilt = std::max(worst_tilt, Tilt(*sim, "a"));
  }
  EXPECT_TRUE(touched);
  EXPECT_GT(worst_tilt, 1 * kDegree) << "knocked askew";
  // They slid past each other and reached their points, level again.
  EXPECT_LT((PositionOf(*sim, "a") - Vec3(1, 0, 0.5)).norm(), 0.02);
  EXPECT_LT((PositionOf(*sim, "b") - Vec3(-1, 0.1, 0.5)).norm(), 0.02);
  EXPECT_LT(Tilt(*sim, "a"), 0.5 * kDegree);
  EXPECT_LT(Tilt(*sim, "b"), 0.5 * kDegree);
}

TEST(EyebotDynamics3d, ThePanTiltAnchorIsTheHeadOnTheBody) {
  auto sim = LoadXml(Scene(Eyebot("e", "0,0,0")));
  FlyTo(*sim, "e", Vec3(0.3, 0.2, 1.0), 0.7);
  PanTiltState& head = *sim->space().Get<PanTiltState>(Slot(*sim, "e"));
  head.pan = 0.4;
  head.tilt = 0.3;
  RunFor(*sim, 2);
  Pose anchor;
  ASSERT_TRUE(sim->Anchor(sim->space().Find("e"), "pan_tilt", anchor));
  const Pose expected = PanTiltFrame(sim->space().pose(Slot(*sim, "e")), head);
  EXPECT_LT((anchor.position - expected.position).norm(), 1e-12);
  EXPECT_LT(anchor.orientation.angularDistance(expected.orientation), 1e-12);
  EXPECT_FALSE(sim->Anchor(sim->space().Find("e"), "manipulator_head", anchor));
}

TEST(EyebotDynamics3d, StateHashIsTheSameWith0_1And2Threads) {
  const std::string xml =
      Scene("<ceiling height=\"2\"/>" + Eyebot("a", "-1,0,0") + Eyebot("b", "1,0.1,0") +
            Eyebot("c", "0.5,-1,1.7", "attached=\"true\"") +
            "<marxbot id=\"f\"><body position=\"0,0,0\"/><controller config=\"idle\"/></marxbot>");
  uint64_t reference = 0;
  for (int threads : {0, 1, 2}) {
    auto sim = LoadXml(xml, {}, threads);
    FlyTo(*sim, "a", Vec3(1, 0, 0.5), 1);
    FlyTo(*sim, "b", Vec3(-1, 0, 0.5), -1);
    for (int t = 0; t < 60; ++t) {
      if (t == 30) Attachment(*sim, "c").attach = false;
      sim->Step();
    }
    const uint64_t hash = sim->StateHash();
    if (threads == 0) reference = hash;
    EXPECT_EQ(hash, reference) << threads << " threads";
  }
}

}  // namespace
}  // namespace colony
