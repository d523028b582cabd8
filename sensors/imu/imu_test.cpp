// IMU: what a gyroscope and an accelerometer on a marXbot would read.
#include "sensors/imu/imu.h"

#include "actuators/differential_steering/differential_steering.h"
#include "core/engine.h"
#include "tests/test_util.h"

namespace colony {
namespace {

class ImuProbe : public Controller {
 public:
  void Init(const Params&) override {
    imu = &GetSensor<Imu>("imu");
    wheels_ = &GetActuator<DifferentialSteering>("differential_steering");
  }
  void ControlStep() override { wheels_->SetLinearVelocity(left, right); }
  double left = 0, right = 0;
  const Imu* imu = nullptr;

 private:
  DifferentialSteering* wheels_ = nullptr;
};
COLONY_REGISTER_CONTROLLER(ImuProbe, "imu_probe", "test: reads the IMU");

std::unique_ptr<Simulation> Scene(const std::string& imu_attributes = "",
                                  const std::string& heading = "0") {
  return testing::LoadXml(testing::Experiment(
      "<marxbot id=\"r\"><body position=\"0,0,0\" orientation=\"" + heading +
          ",0,0\"/><controller config=\"p\"/></marxbot>",
      "<imu_probe id=\"p\"><actuators><differential_steering max_acceleration=\"0.5\"/></actuators>"
      "<sensors><imu " +
          imu_attributes + "/></sensors></imu_probe>"));
}

ImuProbe& Probe(Simulation& sim) {
  return dynamic_cast<ImuProbe&>(*sim.ControllerOf(sim.space().Find("r")));
}

TEST(Imu, AtRestFeelsOnlyGravity) {
  auto sim = Scene();
  for (int t = 0; t < 3; ++t) sim->Step();
  const auto& a = Probe(*sim).imu->acceleration();
  EXPECT_DOUBLE_EQ(a[0], 0.0);
  EXPECT_DOUBLE_EQ(a[1], 0.0);
  EXPECT_DOUBLE_EQ(a[2], 9.81);
  EXPECT_DOUBLE_EQ(Probe(*sim).imu->angular_velocity()[2], 0.0);
}

TEST(Imu, SpeedingUpReadsForwardsInTheRobotsFrame) {
  // Facing +y: the world acceleration is along y, the robot feels it along its x.
  auto sim = Scene("", "90");
  ImuProbe& probe = Probe(*sim);
  probe.left = probe.right = 0.2;
  sim->Step();  // the command reaches the wheels at the next tick
  sim->Step();
  const auto& a = probe.imu->acceleration();
  EXPECT_NEAR(a[0], 0.5, 1e-9);  // the actuator's max_acceleration
  EXPECT_NEAR(a[1], 0.0, 1e-9);
  for (int t = 0; t < 10; ++t) sim->Step();  // cruising at 0.2 m/s
  EXPECT_NEAR(probe.imu->acceleration()[0], 0.0, 1e-9);
}

TEST(Imu, GyroscopeReadsTheTurnRate) {
  auto sim = Scene();
  ImuProbe& probe = Probe(*sim);
  probe.left = -0.07;
  probe.right = 0.07;  // turn left on the spot at 0.14 / 0.14 = 1 rad/s
  for (int t = 0; t < 5; ++t) sim->Step();
  EXPECT_NEAR(probe.imu->angular_velocity()[2], 1.0, 1e-9);
  probe.left = 0.07;
  probe.right = -0.07;
  for (int t = 0; t < 5; ++t) sim->Step();
  EXPECT_NEAR(probe.imu->angular_velocity()[2], -1.0, 1e-9);
}

// In 3D the IMU reads what ODE makes of the body: resting on its treels,
// then turning on the spot.
TEST(Imu, ReadsTheBodyInDynamics3d) {
  if (!Registry<PhysicsEngine>::Get().Find("dynamics3d"))
    GTEST_SKIP() << "built without dynamics3d";
  auto sim = testing::LoadXml(testing::Experiment(
      "<marxbot id=\"r\"><body position=\"0,0,0\"/><controller config=\"p\"/></marxbot>",
      "<imu_probe "
      "id=\"p\"><actuators><differential_steering/></actuators><sensors><imu/></sensors></"
      "imu_probe>",
      "4,4,1", "", "<dynamics3d id=\"d3d\"/>"));
  ImuProbe& probe = Probe(*sim);
  for (int t = 0; t < 20; ++t) sim->Step();
  EXPECT_NEAR(probe.imu->acceleration()[2], 9.81, 0.05);
  EXPECT_NEAR(probe.imu->acceleration()[0], 0.0, 0.05);
  EXPECT_NEAR(probe.imu->angular_velocity()[2], 0.0, 0.01);
  probe.left = -0.07;
  probe.right = 0.07;  // 1 rad/s to the left
  for (int t = 0; t < 20; ++t) sim->Step();
  EXPECT_NEAR(probe.imu->angular_velocity()[2], 1.0, 0.1);
  EXPECT_NEAR(probe.imu->acceleration()[2], 9.81, 0.2);
}

TEST(Imu, NoiseHasTheDeclaredSpread) {
  auto sim = Scene("gyro_noise_std_dev=\"0.01\" accel_noise_std_dev=\"0.1\"");
  double sum = 0, sum2 = 0;
  const int n = 2000;
  for (int t = 0; t < n; ++t) {
    sim->Step();
    const double v = Probe(*sim).imu->acceleration()[2] - 9.81;
    sum += v;
    sum2 += v * v;
  }
  EXPECT_NEAR(sum / n, 0.0, 0.01);
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.1, 0.01);
}

TEST(Imu, NegativeNoiseIsRejected) {
  try {
    Scene("gyro_noise_std_dev=\"-1\"");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(
        std::string(e.what()).find("<imu> attribute 'gyro_noise_std_dev': '-1' is out of range"),
        std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace colony
