// Ground sensors over a ditch on the dynamics3d engine: a sensor over the
// hole reads 0, the others the floor; cubes dropped into the ditch fill it
// up to the floor, and a sensor over them reads their grey.
#include <cmath>
#include <string>
#include <vector>

#include "actuators/differential_steering/differential_steering.h"
#include "sensors/ground/ground.h"
#include "tests/test_util.h"

namespace colony {
namespace {

// Drives at the wheel speed in its public field; records the ground readings.
class GroundDriver : public Controller {
 public:
  void Init(const Params&) override {
    wheels_ = &GetActuator<DifferentialSteering>("differential_steering");
    sensor_ = &GetSensor<GroundSensor>("ground");
  }
  void ControlStep() override {
    last = sensor_->readings();
    wheels_->SetLinearVelocity(speed, speed);
  }
  double speed = 0;
  std::vector<GroundSensor::Reading> last;

 private:
  DifferentialSteering* wheels_ = nullptr;
  const GroundSensor* sensor_ = nullptr;
};
COLONY_REGISTER_CONTROLLER(GroundDriver, "ground_driver",
                           "test: drives straight, records ground readings");

std::string Robot(const std::string& id, const std::string& position) {
  return "<marxbot id=\"" + id + "\"><body position=\"" + position +
         "\"/><controller config=\"gd\"/></marxbot>";
}

std::string Cube(const std::string& id, const std::string& position) {
  return "<cube id=\"" + id + "\" color=\"white\"><body position=\"" + position + "\"/></cube>";
}

GroundDriver& Driver(Simulation& sim, const std::string& id) {
  return dynamic_cast<GroundDriver&>(*sim.ControllerOf(sim.space().Find(id)));
}
using testing::PositionOf;

TEST(GroundOnDynamics3d, SensorsOverADitchReadNoGroundAndOverCubesInItTheirGrey) {
  // A trench 6.2 cm wide and 6 cm deep along y at x = 0.3, on a gray50 floor.
  // Three cubes are dropped into it side by side at y = 0.04 .. 0.16; the
  // rest of the trench stays open. Robot "open" stands with its front sensor
  // (6.5 cm ahead of its axis) over the open part; robot "bridge" drives up
  // until its front sensor is over the cubes.
  const std::string arena =
      "<floor color=\"gray50\"><ditch center=\"0.3,0\" size=\"0.062,0.6\" "
      "depth=\"0.06\"/></floor>" +
      Robot("open", "0.22,-0.15,0") + Robot("bridge", "0.05,0.1,0") + Cube("c1", "0.3,0.039,0") +
      Cube("c2", "0.3,0.1,0") + Cube("c3", "0.3,0.161,0");
  auto sim = testing::LoadXml(testing::Experiment(
      arena,
      "<ground_driver "
      "id=\"gd\"><actuators><differential_steering/></actuators><sensors><ground/></sensors>"
      "</ground_driver>",
      "3,3,1", "", "<dynamics3d id=\"d3d\"/>"));
  for (int t = 0; t < 10; ++t) sim->Step();
  for (const char* c : {"c1", "c2", "c3"}) {
    EXPECT_NEAR(PositionOf(*sim, c).z(), -0.06, 0.005)
        << c << " fell into the ditch, flush with the floor";
  }
  const auto& open = Driver(*sim, "open").last;
  ASSERT_EQ(open.size(), 8u);
  EXPECT_EQ(open[0].value, 0.0f) << "the front sensor is over the open ditch";
  for (int i = 1; i < 8; ++i)
    EXPECT_NEAR(open[i].value, 127 / 255.0, 1e-6) << "sensor " << i << " on the floor";

  // Drive "bridge" until its front sensor is over the cubes (the sensors
  // beside it, 45 degrees off, stay 1 cm or more short of the ditch).
  GroundDriver& bridge = Driver(*sim, "bridge");
  bridge.speed = 0.05;
  for (int t = 0; t < 100 && PositionOf(*sim, "bridge").x() < 0.21; ++t) sim->Step();
  bridge.speed = 0;
  for (int t = 0; t < 5; ++t) sim->Step();
  const Pose& pose = sim->space().pose(sim->space().Find("bridge").index);
  const double yaw = YawOf(pose.orientation);
  int over_cubes = 0;
  for (int i = 0; i < 8; ++i) {
    const double a = yaw + M_PI / 4 * i;
    const double x = pose.position.x() + 0.065 * std::cos(a),
                 y = pose.position.y() + 0.065 * std::sin(a);
    const bool over_ditch = x > 0.269 && x < 0.331;
    ASSERT_TRUE(!over_ditch || (y > 0.01 && y < 0.19))
        << "sensor " << i << " is over the cubes' span";
    over_cubes += over_ditch;
    // White cubes read 1, the floor gray50.
    EXPECT_NEAR(bridge.last[i].value, over_ditch ? 1.0 : 127 / 255.0, 1e-6)
        << "sensor " << i << " at x " << x;
  }
  EXPECT_EQ(over_cubes, 1) << "the front sensor is over the cubes, robot at x "
                           << pose.position.x();
}

}  // namespace
}  // namespace colony
