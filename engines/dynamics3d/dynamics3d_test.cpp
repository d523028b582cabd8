// dynamics3d: the marXbot on its treels (straight, turning, encoders,
// slipping), into a ditch and over a bridge of two cubes; the manipulator's
// magnet; cubes that stack and self-align; boxes and cylinders; the state
// hash whatever the thread count; several engines; bad parameters.
#include <algorithm>
#include <cmath>
#include <regex>
#include <string>
#include <vector>

#include "actuators/gripper/gripper_state.h"
#include "actuators/manipulator/manipulator_state.h"
#include "core/registry.h"
#include "tests/test_util.h"

namespace colony {
namespace {

// A robot that does nothing by itself: the tests write its DriveState and
// ManipulatorState between steps, as the steering and manipulator actuators
// would.
class Idle : public Controller {
 public:
  void Init(const Params&) override {}
  void ControlStep() override {}
};
COLONY_REGISTER_CONTROLLER(Idle, "dyn3d_idle", "test: does nothing");

const char* kIdle = "<dyn3d_idle id=\"idle\"/>";

std::string Engine(const std::string& attributes = "") {
  return "<dynamics3d id=\"d3d\" " + attributes + "/>";
}

std::string Num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string Robot(const std::string& id, double x, double y, double yaw = 0,
                  bool manipulator = false) {
  return "<marxbot id=\"" + id + "\"" + (manipulator ? " manipulator=\"true\"" : "") +
         "><body position=\"" + Num(x) + "," + Num(y) + ",0\" orientation=\"" + Num(yaw) +
         ",0,0\"/><controller config=\"idle\"/></marxbot>";
}

std::string Cube(const std::string& id, double x, double y, double z = 0, double yaw = 0) {
  return "<cube id=\"" + id + "\"><body position=\"" + Num(x) + "," + Num(y) + "," + Num(z) +
         "\" orientation=\"" + Num(yaw) + ",0,0\"/></cube>";
}

std::string Scene(const std::string& body, const std::string& engine = Engine(),
                  const std::string& size = "3,2,1") {
  return testing::Experiment(body, kIdle, size, "", engine);
}

uint32_t SlotOf(Simulation& sim, const std::string& id) { return sim.space().Find(id).index; }
const Pose& PoseOf(Simulation& sim, const std::string& id) {
  return sim.space().pose(SlotOf(sim, id));
}
Vec3 PositionOf(Simulation& sim, const std::string& id) { return PoseOf(sim, id).position; }
// Angle between the body's up axis and the vertical (rad).
double TiltOf(Simulation& sim, const std::string& id) {
  return std::acos(std::clamp((PoseOf(sim, id).orientation * Vec3::UnitZ()).z(), -1.0, 1.0));
}

void SetWheels(Simulation& sim, const std::string& id, double left, double right) {
  DriveState& d = *sim.space().drive(SlotOf(sim, id));
  d.target_left = d.left = left;
  d.target_right = d.right = right;
}

ManipulatorState& Manipulator(Simulation& sim, const std::string& id) {
  return *sim.space().Get<ManipulatorState>(SlotOf(sim, id));
}

using testing::RunFor;

// ---------------------------------------------------------------------------
// Driving.

TEST(Dynamics3d, RobotRestsOnItsTreelsAndItsEncodersReadZero) {
  auto sim = testing::LoadXml(Scene(Robot("r", 0, 0)));
  RunFor(*sim, 2);
  const uint32_t r = SlotOf(*sim, "r");
  EXPECT_NEAR(PositionOf(*sim, "r").z(), 0.0, 0.001) << "the base stands on the floor";
  EXPECT_NEAR(PositionOf(*sim, "r").x(), 0.0, 0.001);
  EXPECT_NEAR(PositionOf(*sim, "r").y(), 0.0, 0.001);
  EXPECT_LT(TiltOf(*sim, "r"), 0.005);
  EXPECT_LT(sim->space().twist(r).linear.norm(), 1e-3);
  EXPECT_EQ(sim->space().drive(r)->travelled_left, 0.0);
  EXPECT_EQ(sim->space().drive(r)->travelled_right, 0.0);
  EXPECT_FALSE(sim->space().in_contact(r)) << "standing on the floor is not a contact";
}

TEST(Dynamics3d, RobotDrivesStraightAtItsCommandedSpeedAndItsEncodersMeasureIt) {
  auto sim = testing::LoadXml(Scene(Robot("r", -1, 0)));
  RunFor(*sim, 0.5);
  SetWheels(*sim, "r", 0.2, 0.2);
  RunFor(*sim, 1);  // up to speed
  const uint32_t r = SlotOf(*sim, "r");
  const Vec3 start = PositionOf(*sim, "r");
  double left = 0, right = 0;
  for (int t = 0; t < 50; ++t) {
    sim->Step();
    left += sim->space().drive(r)->travelled_left;
    right += sim->space().drive(r)->travelled_right;
  }
  const Vec3 moved = PositionOf(*sim, "r") - start;
  EXPECT_NEAR(moved.x(), 1.0, 0.01) << "5 s at 0.2 m/s";
  EXPECT_NEAR(moved.y(), 0.0, 0.005);
  EXPECT_NEAR(sim->space().twist(r).linear.x(), 0.2, 0.002);
  EXPECT_NEAR(left, 1.0, 1e-9);
  EXPECT_NEAR(right, 1.0, 1e-9);
  EXPECT_LT(TiltOf(*sim, "r"), 0.01);
}

TEST(Dynamics3d, RobotTurnsOnTheSpotAtItsCommandedRate) {
  auto sim = testing::LoadXml(Scene(Robot("r", 0, 0)));
  RunFor(*sim, 0.5);
  SetWheels(*sim, "r", -0.07, 0.07);  // (right - left) / 0.14 m = 1 rad/s
  RunFor(*sim, 1);
  const uint32_t r = SlotOf(*sim, "r");
  EXPECT_NEAR(sim->space().twist(r).angular.z(), 1.0, 0.02);
  double yaw = 0, previous = YawOf(PoseOf(*sim, "r").orientation);
  for (int t = 0; t < 20; ++t) {
    sim->Step();
    const double now = YawOf(PoseOf(*sim, "r").orientation);
    yaw += WrapAngle(now - previous);
    previous = now;
  }
  EXPECT_NEAR(yaw, 2.0, 0.04) << "2 s at 1 rad/s";
  EXPECT_LT(PositionOf(*sim, "r").head<2>().norm(), 0.02) << "on the spot";
}

TEST(Dynamics3d, RobotDrivesACircleOfTheCommandedRadius) {
  auto sim = testing::LoadXml(Scene(Robot("r", 0, 0), Engine(), "4,4,1"));
  // v = 0.1 m/s, w = 0.05 / 0.14 rad/s: radius 0.28 m, centre (0, 0.28).
  SetWheels(*sim, "r", 0.075, 0.125);
  for (int t = 0; t < 100; ++t) {
    sim->Step();
    const Vec3 p = PositionOf(*sim, "r");
    ASSERT_NEAR(std::hypot(p.x(), p.y() - 0.28), 0.28, 0.003) << "tick " << t + 1;
  }
  const Twist& twist = sim->space().twist(SlotOf(*sim, "r"));
  EXPECT_NEAR(twist.linear.norm(), 0.1, 1e-3);
  EXPECT_NEAR(twist.angular.z(), 0.05 / 0.14, 1e-3);
}

TEST(Dynamics3d, TreelsSlipAgainstAWallAndAHeavyBoxButPushALightOne) {
  auto sim = testing::LoadXml(
      Scene(Robot("walled", -1, 0.6) +
            "<box id=\"wall\" size=\"0.1,0.4,0.3\"><body position=\"-0.8,0.6,0\"/></box>" +
            Robot("heavy", -1, 0) +
            "<box id=\"lead\" size=\"0.2,0.2,0.2\" movable=\"true\" mass=\"50\">"
            "<body position=\"-0.78,0,0\"/></box>" +
            Robot("light", -1, -0.6) +
            "<box id=\"foam\" size=\"0.2,0.2,0.2\" movable=\"true\" mass=\"0.3\">"
            "<body position=\"-0.78,-0.6,0\"/></box>"));
  for (const char* r : {"walled", "heavy", "light"}) SetWheels(*sim, r, 0.2, 0.2);
  RunFor(*sim, 3);
  EXPECT_LT(PositionOf(*sim, "walled").x(), -0.8 - 0.05 - 0.08) << "stopped by the wall";
  EXPECT_EQ(PositionOf(*sim, "wall"), Vec3(-0.8, 0.6, 0)) << "fixed";
  EXPECT_NEAR(PositionOf(*sim, "lead").x(), -0.78, 0.005) << "50 kg is beyond the treels' pull";
  EXPECT_GT(PositionOf(*sim, "foam").x(), -0.78 + 0.4) << "0.3 kg is pushed along";
  for (const char* r : {"walled", "heavy"}) {
    const uint32_t s = SlotOf(*sim, r);
    EXPECT_LT(sim->space().twist(s).linear.norm(), 0.01) << r;
    EXPECT_TRUE(sim->space().in_contact(s)) << r;
    // The treads still turn: the encoders count what the wheels do.
    EXPECT_NEAR(sim->space().drive(s)->travelled_left, 0.02, 1e-9) << r;
  }
}

// ---------------------------------------------------------------------------
// A ditch one cube wide (6.5 cm) and one cube deep, across the arena at
// x = 0.3; the robot drives at it from x = 0 at 0.1 m/s.

std::string DitchScene(const std::string& extra, bool manipulator = false, double width = 0.065) {
  return Scene("<floor><ditch center=\"0.3,0\" size=\"" + Num(width) +
               ",1.6\" depth=\"0.06\"/></floor>" + Robot("r", 0, 0, 0, manipulator) + extra);
}

// Drives the robot at the ditch for 10 s, then checks for 3 s more that it
// does not move although its treads turn; returns its pose.
Pose DriveIntoTheDitch(Simulation& sim) {
  SetWheels(sim, "r", 0.1, 0.1);
  RunFor(sim, 10);
  const Pose before = PoseOf(sim, "r");
  RunFor(sim, 3);
  const Pose after = PoseOf(sim, "r");
  EXPECT_LT((after.position - before.position).norm(), 0.002) << "stuck";
  EXPECT_GT(sim.space().drive(SlotOf(sim, "r"))->travelled_left, 0.0) << "though its treads turn";
  EXPECT_GT(TiltOf(sim, "r"), 0.25);
  return after;
}

TEST(Dynamics3d, RobotDrivingAtADitchWithoutABridgeFallsInNoseFirstAndIsStuck) {
  // The plain marXbot, and one whose manipulator's head is raised (as when
  // carrying a cube).
  for (const double width : {0.062, 0.065, 0.075}) {
    for (const bool manipulator : {false, true}) {
      SCOPED_TRACE("ditch " + Num(width) + " m wide, manipulator " + (manipulator ? "yes" : "no"));
      auto sim = testing::LoadXml(DitchScene("", manipulator, width));
      if (manipulator) Manipulator(*sim, "r").target_elevation = 0.1;
      const Pose p = DriveIntoTheDitch(*sim);
      // The front of the body is below the floor, the robot's middle short
      // of the far edge.
      const Vec3 front = p.position + p.orientation * Vec3(0.085, 0, 0);
      EXPECT_LT(front.z(), -0.02);
      EXPECT_LT(p.position.x(), 0.3 + 0.5 * width);
    }
  }
}

TEST(Dynamics3d, WithItsHeadLoweredTheRobotSkidsOnItButItsRearFallsIn) {
  // The head at its lowest sticks out in front of the body 1.5 cm above the
  // floor: it lands on the far side and carries the front across; the rear
  // treels then drop into the ditch and the robot is stuck nose up.
  for (const double width : {0.062, 0.065, 0.075}) {
    SCOPED_TRACE("ditch " + Num(width) + " m wide");
    auto sim = testing::LoadXml(DitchScene("", true, width));
    const Pose p = DriveIntoTheDitch(*sim);
    const Vec3 rear = p.position + p.orientation * Vec3(-0.085, 0, 0);
    EXPECT_LT(rear.z(), -0.03);
    EXPECT_LT(rear.x(), 0.3 + 0.5 * width) << "its rear is over the ditch";
  }
}

TEST(Dynamics3d, RobotCrossesTheDitchWhenTwoCubesSideBySideFillIt) {
  // The cubes start level with the floor over the ditch and drop into it.
  for (const double offset : {0.0, 0.02}) {
    for (const bool manipulator : {false, true}) {
      SCOPED_TRACE("robot " + Num(offset) + " m off the bridge's middle, manipulator " +
                   (manipulator ? "yes" : "no"));
      auto sim = testing::LoadXml(Scene(
          "<floor><ditch center=\"0.3,0\" size=\"0.065,1.6\" depth=\"0.06\"/></floor>" +
          Robot("r", 0, offset, 0, manipulator) + Cube("c1", 0.3, 0.03) + Cube("c2", 0.3, -0.03)));
      RunFor(*sim, 1);
      for (const char* c : {"c1", "c2"})
        EXPECT_NEAR(PositionOf(*sim, c).z(), -0.06, 0.002) << c << " in the ditch";
      SetWheels(*sim, "r", 0.1, 0.1);
      RunFor(*sim, 8);
      const Vec3 p = PositionOf(*sim, "r");
      EXPECT_GT(p.x(), 0.7) << "well beyond the ditch (far edge at 0.3325)";
      EXPECT_NEAR(p.z(), 0.0, 0.002);
      EXPECT_LT(TiltOf(*sim, "r"), 0.01) << "upright";
      for (const char* c : {"c1", "c2"})
        EXPECT_NEAR(PositionOf(*sim, c).z(), -0.06, 0.002) << c << " still in the ditch";
    }
  }
}

TEST(Dynamics3d, ACubeFallsIntoADitchAndFillsItFlushWithTheFloor) {
  auto sim = testing::LoadXml(
      Scene("<floor><ditch center=\"0.3,0\" size=\"0.065,1.6\" depth=\"0.06\"/></floor>" +
            Cube("c", 0.3, 0.5, 0.1)));
  RunFor(*sim, 1.5);
  const Vec3 p = PositionOf(*sim, "c");
  EXPECT_NEAR(p.z() + 0.06, 0.0, 0.002) << "its top is level with the floor";
  EXPECT_NEAR(p.x(), 0.3, 0.003);
  EXPECT_LT(TiltOf(*sim, "c"), 0.01);
}

// ---------------------------------------------------------------------------
// The manipulator and its magnet. The head's magnet face is 0.115 m in front
// of the robot's axis; a cube 3 mm beyond it is within reach.

constexpr double kFace = 0.115;

TEST(Dynamics3d, HeadFollowsItsTargetsAtItsSpeeds) {
  auto sim = testing::LoadXml(Scene(Robot("r", 0, 0, 0, true)));
  ManipulatorState& m = Manipulator(*sim, "r");
  RunFor(*sim, 0.5);
  EXPECT_NEAR(m.elevation, 0.03, 1e-3);
  m.target_elevation = 0.13;
  m.target_rotation = 1.0;
  RunFor(*sim, 1);
  EXPECT_NEAR(m.elevation, 0.03 + 0.05, 2e-3) << "0.05 m/s";
  EXPECT_NEAR(m.rotation, 1.0, 0.02) << "1 rad/s";
  RunFor(*sim, 2);
  EXPECT_NEAR(m.elevation, 0.13, 1e-3);
  EXPECT_NEAR(m.rotation, 1.0, 0.01);
  m.target_elevation = 0.5;  // beyond max_elevation: stops there
  m.target_rotation = -2.5;  // the short way round, through pi
  RunFor(*sim, 3);
  EXPECT_NEAR(m.elevation, 0.20, 1e-3);
  EXPECT_NEAR(m.rotation, -2.5, 0.01);
  EXPECT_LT(TiltOf(*sim, "r"), 0.01);
  EXPECT_LT(PositionOf(*sim, "r").head<2>().norm(), 0.003)
      << "the head's motion barely moves the robot";
}

// The manipulator sensor reads the head where the model put it (its anchor),
// not where the commands say it should be.
TEST(Dynamics3d, HeadAnchorIsWhereTheHeadIs) {
  auto sim = testing::LoadXml(Scene(Robot("r", 0.2, -0.1, 30, true) + Robot("plain", -0.5, 0)));
  ManipulatorState& m = Manipulator(*sim, "r");
  m.target_elevation = 0.12;
  m.target_rotation = 0.8;
  RunFor(*sim, 3);
  const EntityHandle r = sim->space().Find("r");
  Pose head;
  ASSERT_TRUE(sim->Anchor(r, ManipulatorState::kHeadAnchor, head));
  const Pose& robot = PoseOf(*sim, "r");
  // Pivot 0.085 + 0.015 m ahead of the robot's axis, at the base + elevation.
  const Vec3 expected = robot.position + robot.orientation * Vec3(0.1, 0, m.elevation);
  EXPECT_LT((head.position - expected).norm(), 2e-3);
  const Vec3 magnet = head.orientation * Vec3::UnitX();
  EXPECT_NEAR(WrapAngle(std::atan2(magnet.y(), magnet.x()) - (30 * M_PI / 180 + 0.8)), 0.0, 0.02);
  EXPECT_NEAR(head.position.z(), 0.12, 2e-3);
  EXPECT_FALSE(sim->Anchor(r, "no_such_anchor", head));
  EXPECT_FALSE(sim->Anchor(sim->space().Find("plain"), ManipulatorState::kHeadAnchor, head))
      << "a marXbot without the manipulator has no head";
}

TEST(Dynamics3d, MagnetHoldsACubeWhileTheHeadLiftsItAndDropsItWhenDisengaged) {
  auto sim = testing::LoadXml(Scene(Robot("r", 0, 0, 0, true) + Cube("c", kFace + 0.033, 0)));
  ManipulatorState& m = Manipulator(*sim, "r");
  const uint32_t cube = SlotOf(*sim, "c");
  m.want_magnet = true;
  RunFor(*sim, 1.2);
  EXPECT_EQ(m.magnet, 1.0);
  ASSERT_EQ(m.held, cube) << "engaged and touching";
  m.target_elevation = 0.13;
  RunFor(*sim, 2.5);
  EXPECT_NEAR(m.elevation, 0.13, 2e-3);
  EXPECT_NEAR(PositionOf(*sim, "c").z(), 0.10, 0.005) << "the cube rose with the head";
  EXPECT_EQ(m.held, cube);
  // Carried while the robot drives.
  SetWheels(*sim, "r", 0.1, 0.1);
  RunFor(*sim, 2);
  SetWheels(*sim, "r", 0, 0);
  RunFor(*sim, 0.5);
  EXPECT_EQ(m.held, cube);
  EXPECT_NEAR(PositionOf(*sim, "c").x() - PositionOf(*sim, "r").x(), kFace + 0.03, 0.01);
  EXPECT_NEAR(PositionOf(*sim, "c").z(), 0.10, 0.005);
  m.want_magnet = false;
  sim->Step();
  EXPECT_LT(m.magnet, 1.0);
  EXPECT_FALSE(m.holding()) << "it holds only while fully engaged";
  RunFor(*sim, 1);
  EXPECT_NEAR(PositionOf(*sim, "c").z(), 0.0, 0.002) << "the cube dropped back to the floor";
  EXPECT_EQ(m.magnet, 0.0);
}

TEST(Dynamics3d, MagnetDoesNotHoldBeforeItsSwitchTimeHasPassed) {
  auto sim = testing::LoadXml(Scene(Robot("r", 0, 0, 0, true) + Cube("c", kFace + 0.033, 0)));
  ManipulatorState& m = Manipulator(*sim, "r");
  m.switch_time = 2.0;
  m.want_magnet = true;
  RunFor(*sim, 1);
  EXPECT_NEAR(m.magnet, 0.5, 1e-9);
  EXPECT_FALSE(m.holding());
  m.target_elevation = 0.1;  // lifting now leaves the cube behind
  RunFor(*sim, 0.9);
  EXPECT_FALSE(m.holding());
  EXPECT_NEAR(PositionOf(*sim, "c").z(), 0.0, 0.002);
  m.target_elevation = 0.03;
  RunFor(*sim, 1.5);
  EXPECT_EQ(m.magnet, 1.0);
  EXPECT_EQ(m.held, SlotOf(*sim, "c")) << "engaged at last";
}

TEST(Dynamics3d, MagnetHoldsOnlyACubeSideItFacesWithinReach) {
  // A cube 2 cm beyond reach, one turned 45 degrees (the magnet meets its
  // corner), a box (not ferromagnetic): none is held.
  for (const std::string& thing : {Cube("c", kFace + 0.05, 0), Cube("c", kFace + 0.045, 0, 0, 45),
                                   std::string("<box id=\"c\" size=\"0.06,0.06,0.06\" "
                                               "movable=\"true\" mass=\"0.04\"><body position=\"") +
                                       Num(kFace + 0.033) + ",0,0\"/></box>"}) {
    auto sim = testing::LoadXml(Scene(Robot("r", 0, 0, 0, true) + thing));
    ManipulatorState& m = Manipulator(*sim, "r");
    m.want_magnet = true;
    RunFor(*sim, 2);
    EXPECT_EQ(m.magnet, 1.0);
    EXPECT_FALSE(m.holding()) << thing;
  }
}

TEST(Dynamics3d, MagnetLetsGoWhenOverloaded) {
  // Lifting a cube pressed down by a fixed plate above it pulls the magnet
  // far beyond its 2 N.
  // The plate covers the cube's far half only, clear of the head.
  auto sim = testing::LoadXml(Scene(Robot("r", 0, 0, 0, true) + Cube("c", kFace + 0.033, 0) +
                                    "<box id=\"plate\" size=\"0.04,0.1,0.01\"><body position=\"" +
                                    Num(kFace + 0.033 + 0.02) + ",0,0.0605\"/></box>"));
  ManipulatorState& m = Manipulator(*sim, "r");
  m.want_magnet = true;
  RunFor(*sim, 1.2);
  ASSERT_TRUE(m.holding());
  m.target_elevation = 0.1;
  RunFor(*sim, 1);
  EXPECT_FALSE(m.holding());
  EXPECT_NEAR(PositionOf(*sim, "c").z(), 0.0, 0.002) << "the cube stayed under the plate";
}

// ---------------------------------------------------------------------------
// Cubes stacking: A on the floor, B dropped onto it from 1.5 cm above.

struct Stack {
  std::unique_ptr<Simulation> sim;
  // B relative to A, in A's frame.
  Vec3 Offset() {
    const Pose& a = PoseOf(*sim, "a");
    return a.orientation.conjugate() * (PositionOf(*sim, "b") - a.position);
  }
  // B's turn relative to A about A's vertical, folded to (-45, 45] degrees.
  double Turn() {
    const Quat rel = PoseOf(*sim, "a").orientation.conjugate() * PoseOf(*sim, "b").orientation;
    const Vec3 x = rel * Vec3::UnitX();
    return std::remainder(std::atan2(x.y(), x.x()), M_PI / 2);
  }
};

// The robot holds A by the magnet and, in LiftAndShake, lifts it 3 cm and
// shakes it sideways: it turns on the spot one way then the other (wheels at
// +-0.14 m/s, reversing every 0.2 s, 3 m/s^2 as the steering actuator's
// default), for 1 s. A, 0.145 m from the robot's axis, swings back and forth
// by about 1.5 cm with accelerations up to about 6 m/s^2, beyond what the
// friction between two cubes (0.5 g) holds.
Stack HeldStack(double dx, double dy, double yaw_degrees, const std::string& engine = Engine()) {
  const double ax = kFace + 0.033;
  Stack s{testing::LoadXml(Scene(
      Robot("r", 0, 0, 0, true) + Cube("a", ax, 0) + Cube("b", ax + dx, dy, 0.075, yaw_degrees),
      engine))};
  Manipulator(*s.sim, "r").want_magnet = true;
  RunFor(*s.sim, 1.2);
  return s;
}

void LiftAndShake(Stack& s) {
  ManipulatorState& m = Manipulator(*s.sim, "r");
  ASSERT_EQ(m.held, SlotOf(*s.sim, "a"));
  m.target_elevation = 0.06;
  RunFor(*s.sim, 1);
  ASSERT_NEAR(PositionOf(*s.sim, "a").z(), 0.03, 0.003);
  double w = 0;
  for (int t = 0; t < 15; ++t) {
    const double target = t >= 10 ? 0.0 : (t / 2) % 2 == 0 ? 0.14 : -0.14;
    w += std::clamp(target - w, -0.3, 0.3);
    SetWheels(*s.sim, "r", -w, w);
    s.sim->Step();
  }
  RunFor(*s.sim, 0.5);
  EXPECT_EQ(m.held, SlotOf(*s.sim, "a")) << "the magnet still holds the stack";
}

TEST(Dynamics3d, CubeDroppedOnAnotherWithinToleranceEndsAlignedOnTopAndStaysThroughAShake) {
  Stack s = HeldStack(0.012, -0.008, 12);
  RunFor(*s.sim, 1);
  Vec3 d = s.Offset();
  EXPECT_NEAR(d.x(), 0.0, 1e-3) << "pulled into alignment";
  EXPECT_NEAR(d.y(), 0.0, 1e-3);
  EXPECT_NEAR(d.z(), 0.06, 1e-3) << "resting on top";
  EXPECT_NEAR(s.Turn(), 0.0, 0.01);
  EXPECT_TRUE(s.sim->space().in_contact(SlotOf(*s.sim, "b")));
  LiftAndShake(s);
  d = s.Offset();
  EXPECT_NEAR(d.x(), 0.0, 1e-3) << "still aligned after the shake";
  EXPECT_NEAR(d.y(), 0.0, 1e-3);
  EXPECT_NEAR(d.z(), 0.06, 1e-3);
  EXPECT_NEAR(s.Turn(), 0.0, 0.01);
}

TEST(Dynamics3d, WithoutSelfAlignmentTheSameShakeMovesTheUpperCube) {
  // cube_capture="0": B rests on A by friction alone and slides when shaken.
  Stack s = HeldStack(0.012, -0.008, 12, Engine("cube_capture=\"0\""));
  RunFor(*s.sim, 1);
  const Vec3 before = s.Offset();
  EXPECT_NEAR(before.x(), 0.012, 2e-3) << "it stays where it landed";
  LiftAndShake(s);
  EXPECT_GT((s.Offset() - before).head<2>().norm(), 0.005);
}

TEST(Dynamics3d, CubeDroppedTooFarOffDoesNotAlign) {
  // 2.4 cm off: beyond the 2 cm capture, its centre still over A: it stays
  // (about) half on.
  {
    Stack s = HeldStack(0.024, 0, 0);
    RunFor(*s.sim, 2);
    const Vec3 d = s.Offset();
    EXPECT_GT(d.x(), 0.02) << "not pulled into alignment";
    EXPECT_LT(d.x(), 0.03);
    EXPECT_GT(d.z(), 0.055) << "still on A";
    EXPECT_LT(s.sim->space().twist(SlotOf(*s.sim, "b")).linear.norm(), 5e-3) << "at rest";
  }
  // 4 cm off: its centre beyond A's edge, it tips off.
  {
    Stack s = HeldStack(0.04, 0, 0);
    RunFor(*s.sim, 2);
    EXPECT_LT(PositionOf(*s.sim, "b").z(), 0.03) << "fell off";
    EXPECT_GT(s.Offset().head<2>().norm(), 0.03);
  }
  // Within reach but turned 30 degrees (capture angle 20): not aligned.
  {
    Stack s = HeldStack(0.005, 0, 30);
    RunFor(*s.sim, 2);
    EXPECT_GT(std::abs(s.Turn()), 0.3);
  }
}

TEST(Dynamics3d, ThreeCubesStackIntoATower) {
  auto sim = testing::LoadXml(
      Scene(Cube("a", 0, 0) + Cube("b", 0.01, 0.005, 0.07, 8) + Cube("c", -0.01, 0.01, 0.14, -10)));
  RunFor(*sim, 2);
  for (const auto& [id, z] :
       std::vector<std::pair<std::string, double>>{{"a", 0}, {"b", 0.06}, {"c", 0.12}}) {
    const Vec3 p = PositionOf(*sim, id);
    EXPECT_NEAR(p.x(), 0, 1e-3) << id;
    EXPECT_NEAR(p.y(), 0, 1e-3) << id;
    EXPECT_NEAR(p.z(), z, 1e-3) << id;
    EXPECT_NEAR(std::remainder(YawOf(PoseOf(*sim, id).orientation), M_PI / 2), 0, 0.01) << id;
  }
}

// ---------------------------------------------------------------------------
// Objects.

TEST(Dynamics3d, ObjectsFallAndRestOnTheFloorAndFixedOnesStayPut) {
  auto sim = testing::LoadXml(Scene(
      "<box id=\"b\" size=\"0.2,0.1,0.1\" movable=\"true\" mass=\"0.5\"><body position=\"0,0,0.3\" "
      "orientation=\"30,0,0\"/></box>"
      "<cylinder id=\"c\" radius=\"0.05\" height=\"0.2\" movable=\"true\" mass=\"0.3\"><body "
      "position=\"0.5,0,0.1\"/>"
      "</cylinder>"
      "<cylinder id=\"f\" radius=\"0.1\" height=\"0.3\"><body position=\"-0.5,0,0.2\"/></cylinder>"
      "<box id=\"shelf\" size=\"0.2,0.2,0.02\"><body position=\"-0.8,0.5,0.3\"/></box>" +
      Cube("q", -0.8, 0.5, 0.4)));
  RunFor(*sim, 1.5);
  EXPECT_NEAR(PositionOf(*sim, "b").z(), 0.0, 0.002);
  EXPECT_NEAR(YawOf(PoseOf(*sim, "b").orientation), DegToRad(30), 0.01);
  EXPECT_NEAR(PositionOf(*sim, "c").z(), 0.0, 0.002);
  EXPECT_LT(TiltOf(*sim, "c"), 0.01) << "standing upright";
  EXPECT_EQ(PositionOf(*sim, "f"), Vec3(-0.5, 0, 0.2))
      << "a fixed cylinder floats where it was put";
  EXPECT_NEAR(PositionOf(*sim, "q").z(), 0.32, 0.002) << "the cube landed on the fixed shelf";
  EXPECT_LT(sim->space().twist(SlotOf(*sim, "b")).linear.norm(), 1e-3);
}

// The foot-bot's gripper in 3D: closing on a grounded hand-bot's docking
// ring, it drags the hand-bot; letting go leaves it.
TEST(Dynamics3d, AFootBotGripsAHandBotsRingAndDragsIt) {
  auto sim = testing::LoadXml(
      Scene(Robot("f", -0.3, 0) +
                "<handbot id=\"h\"><body position=\"-0.12,0,0\" orientation=\"180,0,0\"/>"
                "<controller config=\"idle\"/></handbot>",
            Engine("stepper=\"worldstep\""), "4,2,1"));
  GripperState& g = *sim->space().Get<GripperState>(SlotOf(*sim, "f"));
  RunFor(*sim, 0.5);
  g.want_grip = true;
  RunFor(*sim, 0.2);
  ASSERT_TRUE(g.holding());
  EXPECT_EQ(g.held, SlotOf(*sim, "h"));
  const Vec3 start = PositionOf(*sim, "h");
  SetWheels(*sim, "f", -0.1, -0.1);
  RunFor(*sim, 6);
  SetWheels(*sim, "f", 0, 0);
  RunFor(*sim, 0.5);
  EXPECT_LT(PositionOf(*sim, "h").x() - start.x(), -0.5) << "dragged backwards more than 0.5 m";
  EXPECT_NEAR(PositionOf(*sim, "h").x() - PositionOf(*sim, "f").x(), start.x() + 0.3, 0.01)
      << "still at the jaws";
  EXPECT_LT(TiltOf(*sim, "h"), 0.05) << "upright";
  g.want_grip = false;
  RunFor(*sim, 0.2);
  EXPECT_FALSE(g.holding());
  const Vec3 left = PositionOf(*sim, "h");
  SetWheels(*sim, "f", -0.1, -0.1);
  RunFor(*sim, 2);
  EXPECT_LT((PositionOf(*sim, "h") - left).norm(), 0.01) << "let go, it stays";
  // Nothing in front of the jaws: nothing held.
  auto alone = testing::LoadXml(Scene(Robot("f", 0, 0)));
  GripperState& ga = *alone->space().Get<GripperState>(SlotOf(*alone, "f"));
  ga.want_grip = true;
  RunFor(*alone, 0.5);
  EXPECT_FALSE(ga.holding());
}

TEST(Dynamics3d, TheCeilingIsSolid) {
  // Gravity reversed: a box "falls" up against a ceiling 0.8 m above the floor.
  auto sim = testing::LoadXml(
      Scene("<ceiling height=\"0.8\"/><box id=\"b\" size=\"0.2,0.1,0.1\" movable=\"true\" "
            "mass=\"0.5\"><body position=\"0,0,0.3\"/></box>",
            Engine("gravity=\"0,0,9.81\"")));
  RunFor(*sim, 1.5);
  EXPECT_NEAR(PositionOf(*sim, "b").z(), 0.7, 0.002) << "its top against the ceiling";
  EXPECT_LT(sim->space().twist(SlotOf(*sim, "b")).linear.norm(), 1e-3);
}

// ---------------------------------------------------------------------------
// Determinism and several engines.

std::string BusyScene(const std::string& engines) {
  return testing::Experiment(
      "<floor><ditch center=\"0.5,0\" size=\"0.065,0.8\" depth=\"0.06\"/></floor><walls/>" +
          Robot("m", -0.3, 0.5, 0, true) + Cube("c1", -0.3 + kFace + 0.033, 0.5) +
          Cube("c2", -0.3 + kFace + 0.035, 0.505, 0.07, 10) + Cube("c3", 0.5, 0.02) +
          Cube("c4", 0.5, -0.3, 0.01) +
          "<box id=\"b\" size=\"0.1,0.1,0.1\" movable=\"true\" mass=\"0.2\"><body "
          "position=\"1,-0.6,0\"/></box>"
          "<distribute><position method=\"uniform\" min=\"-1.3,-0.9,0\" max=\"1.3,0.9,0\"/>"
          "<orientation method=\"uniform\" min=\"0,0,0\" max=\"360,0,0\"/>"
          "<entity quantity=\"30\" max_trials=\"1000\"><marxbot id=\"mb\"><controller "
          "config=\"dc\"/></marxbot>"
          "</entity></distribute>",
      std::string(kIdle) +
          "<diffusion id=\"dc\" "
          "library=\"diffusion\"><actuators><differential_steering/></actuators>"
          "<sensors><proximity/></sensors><params velocity=\"0.2\"/></diffusion>",
      "3,2,1", "", engines);
}

void ExpectSameHashWhateverTheThreadCount(const std::string& xml) {
  uint64_t reference = 0;
  for (int threads : {0, 1, 2}) {
    auto sim = testing::LoadXml(xml, {}, threads);
    ManipulatorState& m = Manipulator(*sim, "m");
    m.want_magnet = true;
    for (int t = 0; t < 100; ++t) {
      if (t == 20) m.target_elevation = 0.15;
      if (t == 60) m.want_magnet = false;
      sim->Step();
    }
    const uint64_t hash = sim->StateHash();
    if (threads == 0) reference = hash;
    EXPECT_EQ(hash, reference) << threads << " threads";
  }
}

TEST(Dynamics3d, StateHashIsTheSameWith0_1And2Threads) {
  for (const std::string stepper : {"quickstep", "worldstep"}) {
    SCOPED_TRACE(stepper);
    ExpectSameHashWhateverTheThreadCount(BusyScene(Engine("stepper=\"" + stepper + "\"")));
  }
}

// <boundaries> over the rectangle [x0, x1] x [y0, y1].
std::string Boundaries(double x0, double y0, double x1, double y1) {
  auto v = [](double x, double y) { return "<vertex point=\"" + Num(x) + "," + Num(y) + "\"/>"; };
  return "<boundaries><top height=\"1\"/><bottom height=\"-0.5\"/><sides>" + v(x0, y0) + v(x1, y0) +
         v(x1, y1) + v(x0, y1) + "</sides></boundaries>";
}

std::string Halves(const std::string& attributes = "") {
  return "<dynamics3d id=\"west\" " + attributes + ">" + Boundaries(-1.5, -1, 0, 1) +
         "</dynamics3d><dynamics3d id=\"east\" " + attributes + ">" + Boundaries(0, -1, 1.5, 1) +
         "</dynamics3d>";
}

TEST(Dynamics3d, StateHashIsTheSameWith0_1And2ThreadsWithTwoEnginesSteppingInParallel) {
  ExpectSameHashWhateverTheThreadCount(BusyScene(Halves()));
}

TEST(Dynamics3d, RobotsCrossBetweenTwoEnginesKeepingTheirMotion) {
  for (const double heading : {0.0, 180.0}) {
    const double x0 = heading == 0 ? -0.3 : 0.3;
    auto sim = testing::LoadXml(Scene(Robot("r", x0, 0, heading, true), Halves()));
    const EntityHandle r = sim->space().Find("r");
    const std::string start = sim->EngineOf(r)->id();
    Manipulator(*sim, "r").target_elevation = 0.1;
    SetWheels(*sim, "r", 0.1, 0.1);
    RunFor(*sim, 1.5);
    std::vector<double> xs;
    for (int t = 0; t < 45; ++t) {
      sim->Step();
      xs.push_back(PositionOf(*sim, "r").x());
    }
    EXPECT_NE(sim->EngineOf(r)->id(), start);
    EXPECT_LT(xs.front() * xs.back(), 0.0) << "crossed x = 0";
    for (size_t t = 1; t < xs.size(); ++t) {
      EXPECT_NEAR(std::abs(xs[t] - xs[t - 1]), 0.01, 3e-4)
          << "tick " << t << ": no jump at the boundary";
    }
    EXPECT_NEAR(PositionOf(*sim, "r").y(), 0.0, 2e-3);
    EXPECT_NEAR(PositionOf(*sim, "r").z(), 0.0, 1e-3);
    EXPECT_NEAR(Manipulator(*sim, "r").elevation, 0.1, 2e-3) << "the head kept its height";
  }
}

TEST(Dynamics3d, MixingWithATwoDimensionalEngineIsRejectedAtLoadTime) {
  for (const std::string& engines :
       {Halves().substr(0, Halves().find("<dynamics3d id=\"east\"")) +
            "<kinematics2d id=\"east\">" + Boundaries(0, -1, 1.5, 1) + "</kinematics2d>",
        "<dynamics2d id=\"west\">" + Boundaries(-1.5, -1, 0, 1) + "</dynamics2d>" +
            Halves().substr(Halves().find("<dynamics3d id=\"east\""))}) {
    const std::string m = testing::LoadError(Scene(Robot("r", -0.5, 0), engines));
    EXPECT_NE(m.find("<string>:1:"), std::string::npos) << m;
    EXPECT_NE(m.find("cannot share an experiment"), std::string::npos) << m;
    EXPECT_NE(m.find("2D"), std::string::npos) << m;
  }
}

// ---------------------------------------------------------------------------
// Configuration.

TEST(Dynamics3d, BadParametersAreRejectedWithElementAndLine) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"substeps=\"0\"", "a whole number in [1, 1000]"},
      {"substeps=\"-2\"", "a whole number in [1, 1000]"},
      {"stepper=\"euler\"", "quickstep, worldstep"},
      {"iterations=\"x\"", ""},
      {"cube_friction=\"-1\"", ">= 0"},
      {"treel_max_torque=\"0\"", "> 0"},
      {"gravity=\"0,-9.81\"", ""},
      {"erp=\"2\"", ""},
      {"cube_capture_angle=\"1\"", ""},
  };
  for (const auto& [bad, accepted] : cases) {
    const std::string m = testing::LoadError(testing::Experiment("", "", "3,2,1", "", Engine(bad)));
    const std::string attribute = bad.substr(0, bad.find('='));
    EXPECT_NE(m.find("<string>:1: <dynamics3d id=\"d3d\"> attribute '" + attribute + "'"),
              std::string::npos)
        << bad << ": " << m;
    EXPECT_NE(m.find(accepted), std::string::npos) << bad << ": " << m;
  }
}

TEST(Dynamics3d, RegisteredAttributesMatchTheReadme) {
  const auto* entry = Registry<PhysicsEngine>::Get().Find("dynamics3d");
  ASSERT_NE(entry, nullptr);
  EXPECT_EQ(testing::ReadmeAttributes("engines/dynamics3d"), entry->info.AttributeNames());
  for (const char* model :
       {"dynamics3d:marxbot", "dynamics3d:box", "dynamics3d:cylinder", "dynamics3d:cube"}) {
    EXPECT_NE(Registry<PhysicsModel>::Get().Find(model), nullptr) << model;
  }
}

}  // namespace
}  // namespace colony
