// Gripping: a gripped cylinder follows the robot and stays behind when
// released; the turret turns at its speed; engines that do not simulate
// gripping reject it at load time.
#include "actuators/gripper/gripper.h"

#include "actuators/differential_steering/differential_steering.h"
#include "sensors/gripper/gripper.h"
#include "tests/test_util.h"

namespace colony {
namespace {

// Does what the test tells it through its public fields.
class GripProbe : public Controller {
 public:
  void Init(const Params&) override {
    wheels_ = &GetActuator<DifferentialSteering>("differential_steering");
    gripper_ = &GetActuator<GripperActuator>("gripper");
    sensor = &GetSensor<GripperSensor>("gripper");
  }
  void ControlStep() override {
    wheels_->SetLinearVelocity(speed, speed);
    gripper_->SetTurretAngle(turret);
    if (grip) {
      gripper_->Grip();
    } else {
      gripper_->Release();
    }
  }
  double speed = 0, turret = 0;
  bool grip = false;
  const GripperSensor* sensor = nullptr;

 private:
  DifferentialSteering* wheels_ = nullptr;
  GripperActuator* gripper_ = nullptr;
};
COLONY_REGISTER_CONTROLLER(GripProbe, "grip_probe", "test: scripted gripping");

const char* kProbe =
    "<grip_probe id=\"g\"><actuators><differential_steering/><gripper "
    "turret_speed=\"1\"/></actuators>"
    "<sensors><gripper/></sensors></grip_probe>";

std::string Scene(const std::string& engine) {
  // A movable cylinder just in front of the robot's jaws (robot radius 0.085).
  return testing::Experiment(
      "<marxbot id=\"r\"><body position=\"0,0,0\"/><controller config=\"g\"/></marxbot>"
      "<cylinder id=\"c\" radius=\"0.05\" height=\"0.1\" movable=\"true\" mass=\"0.2\"><body "
      "position=\"0.145,0,0\"/></cylinder>",
      kProbe, "4,4,1", "", engine);
}

GripProbe& Probe(Simulation& sim) {
  return dynamic_cast<GripProbe&>(*sim.ControllerOf(sim.space().Find("r")));
}
Vec3 At(Simulation& sim, const char* id) {
  return sim.space().pose(sim.space().Find(id).index).position;
}

TEST(Gripper, GrippedCylinderFollowsAndStaysBehindWhenReleased) {
  auto sim = testing::LoadXml(Scene("<dynamics2d id=\"d2d\"/>"));
  GripProbe& probe = Probe(*sim);
  probe.grip = true;
  for (int t = 0; t < 3; ++t) sim->Step();
  ASSERT_TRUE(probe.sensor->holding());
  // Drive backwards 1 s at 0.1 m/s: the cylinder comes along.
  probe.speed = -0.1;
  for (int t = 0; t < 10; ++t) sim->Step();
  const double gap_held = At(*sim, "c").x() - At(*sim, "r").x();
  EXPECT_LT(At(*sim, "r").x(), -0.05) << "it backed off, dragging the cylinder";
  EXPECT_NEAR(gap_held, 0.145, 0.01) << "the held cylinder keeps its place at the jaws";
  // Release and keep backing off: the cylinder stays where it was dropped.
  probe.grip = false;
  sim->Step();
  sim->Step();
  EXPECT_FALSE(probe.sensor->holding());
  const double dropped = At(*sim, "c").x();
  for (int t = 0; t < 10; ++t) sim->Step();
  EXPECT_NEAR(At(*sim, "c").x(), dropped, 0.01);
  EXPECT_GT(At(*sim, "c").x() - At(*sim, "r").x(), 0.2);
}

TEST(Gripper, NothingInReachMeansNothingHeld) {
  auto sim = testing::LoadXml(Scene("<dynamics2d id=\"d2d\"/>"));
  GripProbe& probe = Probe(*sim);
  probe.turret = M_PI;  // jaws to the back, away from the cylinder
  for (int t = 0; t < 40; ++t) sim->Step();
  probe.grip = true;
  for (int t = 0; t < 5; ++t) sim->Step();
  EXPECT_FALSE(probe.sensor->holding());
}

TEST(Gripper, TurretTurnsAtItsSpeed) {
  auto sim = testing::LoadXml(Scene("<dynamics2d id=\"d2d\"/>"));
  GripProbe& probe = Probe(*sim);
  probe.turret = 1.0;
  for (int t = 0; t < 6; ++t) sim->Step();
  // 1 rad/s from tick 2 (the command reaches the actuator a tick later).
  EXPECT_NEAR(probe.sensor->turret_angle(), 0.5, 0.11);
  for (int t = 0; t < 10; ++t) sim->Step();
  EXPECT_DOUBLE_EQ(probe.sensor->turret_angle(), 1.0);
}

TEST(Gripper, Kinematics2dRejectsGrippingAtLoadTime) {
  const std::string m = testing::LoadError(Scene("<kinematics2d id=\"k2d\"/>"));
  EXPECT_NE(m.find("<gripper>: robot 'r' (a marxbot"), std::string::npos) << m;
  EXPECT_NE(
      m.find("kinematics2d 'k2d') does not simulate the gripper of a marxbot; use dynamics2d"),
      std::string::npos)
      << m;
}

// A gripping robot that drives out of the dynamics2d half of the arena into
// the kinematics2d half: the run stops with a message naming robot, tick and
// engines, instead of grips that nothing simulates.
TEST(Gripper, DrivingIntoAnEngineThatCannotGripStopsTheRun) {
  auto region = [](const char* x0, const char* x1) {
    return std::string("<boundaries><top height=\"1\"/><bottom height=\"0\"/><sides size=\"4\">") +
           "<vertex point=\"" + x0 + ",-2\"/><vertex point=\"" + x1 + ",-2\"/><vertex point=\"" +
           x1 + ",2\"/><vertex point=\"" + x0 + ",2\"/></sides></boundaries>";
  };
  const std::string engines = "<dynamics2d id=\"d2d\">" + region("-2", "0") +
                              "</dynamics2d><kinematics2d id=\"k2d\">" + region("0", "2") +
                              "</kinematics2d>";
  auto sim = testing::LoadXml(testing::Experiment(
      "<marxbot id=\"r\"><body position=\"-0.3,0,0\"/><controller config=\"g\"/></marxbot>", kProbe,
      "4,4,1", "", engines));
  GripProbe& probe = Probe(*sim);
  probe.speed = 0.1;
  std::string message;
  try {
    for (int t = 0; t < 60; ++t) sim->Step();
  } catch (const RuntimeFailure& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("robot 'r' crossed at tick "), std::string::npos) << message;
  // The gripper sensor needs the gripper too; it is checked first.
  EXPECT_NE(
      message.find(
          "from dynamics2d 'd2d' into the region of kinematics2d 'k2d', which cannot simulate its "
          "sensor 'gripper': kinematics2d 'k2d' does not simulate the gripper of a marxbot; use "
          "dynamics2d"),
      std::string::npos)
      << message;
  EXPECT_LT(At(*sim, "r").x(), 0.1) << "it stopped at the boundary";
}

}  // namespace
}  // namespace colony
