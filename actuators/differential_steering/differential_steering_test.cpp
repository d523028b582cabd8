// Differential steering as a user sees it: wheel speed commands (m/s) move
// the robot, clamped to the robot's top speed and limited in acceleration.
#include "actuators/differential_steering/differential_steering.h"

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/device.h"
#include "core/registry.h"
#include "tests/test_util.h"

namespace colony {
namespace {

using testing::Experiment;
using testing::LoadError;
using testing::LoadXml;

// Drives at params left/right (m/s); the test may change the command.
class SteeringProbe : public Controller {
 public:
  void Init(const Params& params) override {
    wheels = &GetActuator<DifferentialSteering>("differential_steering");
    left = params.GetDouble("left", 0);
    right = params.GetDouble("right", 0);
    wheels->SetLinearVelocity(left, right);
  }
  void ControlStep() override { wheels->SetLinearVelocity(left, right); }
  DifferentialSteering* wheels = nullptr;
  double left = 0, right = 0;
};

COLONY_REGISTER_CONTROLLER(SteeringProbe, "steering_probe", "test: drives at fixed wheel speeds");

std::string Controllers(const std::string& params, const std::string& attributes = "") {
  return "<steering_probe id=\"sp\"><actuators><differential_steering " + attributes +
         "/></actuators><params " + params + "/></steering_probe>";
}

std::string Robot(const std::string& id, const std::string& position, double yaw_degrees = 0) {
  return "<marxbot id=\"" + id + "\"><body position=\"" + position + "\" orientation=\"" +
         std::to_string(yaw_degrees) + ",0,0\"/><controller config=\"sp\"/></marxbot>";
}

SteeringProbe& Probe(Simulation& sim, const std::string& robot) {
  auto* probe = dynamic_cast<SteeringProbe*>(sim.ControllerOf(sim.space().Find(robot)));
  EXPECT_NE(probe, nullptr);
  return *probe;
}

const Pose& PoseOf(Simulation& sim, const std::string& robot) {
  return sim.space().pose(sim.space().Find(robot).index);
}

TEST(DifferentialSteering, DrivesStraightAtTheCommandedSpeed) {
  auto sim = LoadXml(Experiment(Robot("r", "-1,0,0"), Controllers("left=\"0.1\" right=\"0.1\"")));
  for (int t = 0; t < 20; ++t) sim->Step();
  EXPECT_NEAR(PoseOf(*sim, "r").position.x(), -0.8, 1e-9);
  EXPECT_NEAR(PoseOf(*sim, "r").position.y(), 0.0, 1e-12);
  EXPECT_NEAR(sim->space().twist(sim->space().Find("r").index).linear.x(), 0.1, 1e-9);
  // The command the controller gave is what it reads back.
  EXPECT_EQ(Probe(*sim, "r").wheels->target_left(), 0.1);
}

TEST(DifferentialSteering, SpeedIsClampedToTheMarxbotsTopSpeed) {
  // 1 m/s asked, 0.3 m/s is the marXbot's top speed.
  auto sim = LoadXml(Experiment(Robot("r", "-1.5,0,0"), Controllers("left=\"1\" right=\"1\"")));
  Vec3 previous = PoseOf(*sim, "r").position;
  for (int t = 0; t < 10; ++t) {
    sim->Step();
    const Vec3 now = PoseOf(*sim, "r").position;
    EXPECT_LE((now - previous).norm(), 0.03 + 1e-12) << "tick " << t;
    previous = now;
  }
  EXPECT_NEAR(PoseOf(*sim, "r").position.x(), -1.5 + 0.3, 1e-9);
  const DriveState* d = sim->space().drive(sim->space().Find("r").index);
  ASSERT_NE(d, nullptr);
  EXPECT_DOUBLE_EQ(d->left, 0.3);
  EXPECT_DOUBLE_EQ(d->target_left, 0.3);
  // Backwards too.
  Probe(*sim, "r").left = Probe(*sim, "r").right = -5;
  for (int t = 0; t < 12; ++t) sim->Step();
  EXPECT_DOUBLE_EQ(d->left, -0.3);
  EXPECT_NEAR(sim->space().twist(sim->space().Find("r").index).linear.norm(), 0.3, 1e-9);
}

TEST(DifferentialSteering, MaxSpeedAttributeLowersTheLimitButNeverRaisesIt) {
  auto slow = LoadXml(Experiment(Robot("r", "-1.5,0,0"),
                                 Controllers("left=\"1\" right=\"1\"", "max_speed=\"0.1\"")));
  auto fast = LoadXml(
      Experiment(Robot("r", "-1.5,0,0"), Controllers("left=\"1\" right=\"1\"", "max_speed=\"2\"")));
  for (int t = 0; t < 10; ++t) {
    slow->Step();
    fast->Step();
  }
  EXPECT_NEAR(PoseOf(*slow, "r").position.x(), -1.5 + 0.1, 1e-9);
  // The robot's own 0.3 m/s still applies.
  EXPECT_NEAR(PoseOf(*fast, "r").position.x(), -1.5 + 0.3, 1e-9);
}

TEST(DifferentialSteering, AccelerationIsLimited) {
  // 1 m/s^2 at 10 ticks per second: +0.1 m/s per tick, 3 ticks to 0.3 m/s.
  auto sim = LoadXml(Experiment(
      Robot("r", "-1.5,0,0"), Controllers("left=\"0.3\" right=\"0.3\"", "max_acceleration=\"1\"")));
  const DriveState* d = sim->space().drive(sim->space().Find("r").index);
  const double speeds[] = {0.1, 0.2, 0.3, 0.3};
  for (double v : speeds) {
    sim->Step();
    EXPECT_NEAR(d->left, v, 1e-12);
    EXPECT_NEAR(d->right, v, 1e-12);
  }
  EXPECT_NEAR(PoseOf(*sim, "r").position.x(), -1.5 + 0.01 + 0.02 + 0.03 + 0.03, 1e-9);
  // Braking is limited as well: from 0.3 m/s to a stop takes 3 ticks.
  Probe(*sim, "r").left = Probe(*sim, "r").right = 0;
  sim->Step();  // the stop command is given at the end of this tick
  const double braking[] = {0.2, 0.1, 0.0, 0.0};
  for (double v : braking) {
    sim->Step();
    EXPECT_NEAR(d->left, v, 1e-12);
  }
}

TEST(DifferentialSteering, DefaultAccelerationReachesTopSpeedInOneTick) {
  // Default 3 m/s^2: 0.3 m/s per tick at 10 ticks per second.
  auto sim = LoadXml(Experiment(Robot("r", "-1.5,0,0"), Controllers("left=\"0.3\" right=\"0.3\"")));
  sim->Step();
  EXPECT_NEAR(sim->space().drive(sim->space().Find("r").index)->left, 0.3, 1e-12);
  EXPECT_NEAR(PoseOf(*sim, "r").position.x(), -1.5 + 0.03, 1e-12);
}

TEST(DifferentialSteering, SpinningInPlaceKeepsThePosition) {
  // (-v, v): turns counter-clockwise at 2v / 0.14 rad/s around its centre.
  auto sim = LoadXml(
      Experiment(Robot("r", "0.3,-0.2,0", 10), Controllers("left=\"-0.07\" right=\"0.07\"")));
  for (int t = 0; t < 25; ++t) {
    sim->Step();
    EXPECT_NEAR(PoseOf(*sim, "r").position.x(), 0.3, 1e-12);
    EXPECT_NEAR(PoseOf(*sim, "r").position.y(), -0.2, 1e-12);
  }
  // 25 ticks x 0.1 s x 1 rad/s = 2.5 rad.
  EXPECT_NEAR(YawOf(PoseOf(*sim, "r").orientation), WrapAngle(DegToRad(10) + 2.5), 1e-9);
  EXPECT_NEAR(sim->space().twist(sim->space().Find("r").index).angular.z(), 1.0, 1e-12);
  // Clockwise the other way round.
  auto cw = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers("left=\"0.07\" right=\"-0.07\"")));
  for (int t = 0; t < 5; ++t) cw->Step();
  EXPECT_NEAR(YawOf(PoseOf(*cw, "r").orientation), -0.5, 1e-9);
}

TEST(DifferentialSteering, ArcsFollowACircle) {
  // Left 0.05, right 0.1: v = 0.075 m/s, w = 0.05 / 0.14 rad/s, radius v / w,
  // centre to the robot's left. The engine integrates arcs exactly.
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers("left=\"0.05\" right=\"0.1\"")));
  const double radius = 0.075 / (0.05 / 0.14);
  const Vec2 centre(0, radius);
  for (int t = 0; t < 150; ++t) {
    sim->Step();
    EXPECT_NEAR((PoseOf(*sim, "r").position.head<2>() - centre).norm(), radius, 1e-9)
        << "tick " << t;
  }
}

TEST(DifferentialSteering, NonFiniteCommandsStopTheWheels) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers("left=\"0.1\" right=\"0.1\"")));
  sim->Step();
  Probe(*sim, "r").left = std::numeric_limits<double>::quiet_NaN();
  Probe(*sim, "r").right = std::numeric_limits<double>::infinity();
  for (int t = 0; t < 5; ++t) sim->Step();
  const Pose& p = PoseOf(*sim, "r");
  EXPECT_TRUE(std::isfinite(p.position.x()));
  const DriveState* d = sim->space().drive(sim->space().Find("r").index);
  EXPECT_EQ(d->left, 0.0);
  EXPECT_EQ(d->right, 0.0);
}

TEST(DifferentialSteering, UnpoweredRobotBrakesToAStopAndStays) {
  // Default max_acceleration 3 m/s^2: 0.3 m/s of change per tick.
  auto sim = LoadXml(Experiment(Robot("r", "-1,0,0"), Controllers("left=\"0.2\" right=\"0.2\"")));
  for (int t = 0; t < 3; ++t) sim->Step();
  DriveState* d = sim->space().drive(sim->space().Find("r").index);
  ASSERT_NE(d, nullptr);
  EXPECT_DOUBLE_EQ(d->left, 0.2);
  d->powered = false;  // what an empty battery does
  sim->Step();
  EXPECT_EQ(d->target_left, 0.0);
  EXPECT_EQ(d->target_right, 0.0);
  EXPECT_EQ(d->left, 0.0);
  EXPECT_EQ(d->right, 0.0);
  // The controller keeps asking; the robot does not move.
  const Vec3 stopped = PoseOf(*sim, "r").position;
  for (int t = 0; t < 10; ++t) sim->Step();
  EXPECT_EQ(PoseOf(*sim, "r").position, stopped);
  EXPECT_EQ(Probe(*sim, "r").wheels->target_left(), 0.2);
  // Power back: it drives again.
  d->powered = true;
  sim->Step();
  EXPECT_NEAR(PoseOf(*sim, "r").position.x(), stopped.x() + 0.02, 1e-9);
}

TEST(DifferentialSteering, UnpoweredRobotBrakesAtTheAccelerationLimit) {
  auto sim = LoadXml(Experiment(
      Robot("r", "-1,0,0"), Controllers("left=\"0.3\" right=\"0.3\"", "max_acceleration=\"1\"")));
  for (int t = 0; t < 5; ++t) sim->Step();
  DriveState* d = sim->space().drive(sim->space().Find("r").index);
  EXPECT_NEAR(d->left, 0.3, 1e-12);
  d->powered = false;
  sim->Step();
  EXPECT_NEAR(d->left, 0.2, 1e-12);  // 1 m/s^2 x 0.1 s
  EXPECT_NEAR(d->right, 0.2, 1e-12);
  sim->Step();
  sim->Step();
  EXPECT_NEAR(d->left, 0.0, 1e-12);
  sim->Step();
  EXPECT_NEAR(d->left, 0.0, 1e-12);
}

TEST(DifferentialSteering, BadAttributesAreReported) {
  const std::string speed =
      LoadError(Experiment(Robot("r", "0,0,0"), Controllers("", "max_speed=\"0\"")));
  EXPECT_NE(speed.find("attribute 'max_speed'"), std::string::npos) << speed;
  EXPECT_NE(speed.find("> 0"), std::string::npos) << speed;
  const std::string accel =
      LoadError(Experiment(Robot("r", "0,0,0"), Controllers("", "max_acceleration=\"fast\"")));
  EXPECT_NE(accel.find("attribute 'max_acceleration'"), std::string::npos) << accel;
  EXPECT_NE(accel.find("not a finite number"), std::string::npos) << accel;
}

TEST(DifferentialSteering, RegisteredAttributesMatchTheReadme) {
  // What `colony query differential_steering` lists (and README.md documents).
  const auto* entry = Registry<ActuatorSystem>::Get().Find("differential_steering");
  ASSERT_NE(entry, nullptr);
  EXPECT_EQ(entry->info.AttributeNames(),
            (std::vector<std::string>{"max_speed", "max_acceleration"}));
}

}  // namespace
}  // namespace colony
