// Positioning as a controller sees it: the robot's pose in the arena (x, y, z
// in metres, yaw in radians), ground truth plus optional noise.
#include "sensors/positioning/positioning.h"

#include <cmath>
#include <string>
#include <vector>

#include "actuators/differential_steering/differential_steering.h"
#include "core/registry.h"
#include "tests/test_util.h"

namespace colony {
namespace {

using testing::Experiment;
using testing::LoadError;
using testing::LoadXml;

struct Fix {
  double x, y, z, yaw;
};

// Records its positioning readings; drives at params left/right (m/s).
class PositioningProbe : public Controller {
 public:
  void Init(const Params& params) override {
    sensor_ = &GetSensor<PositioningSensor>("positioning");
    wheels_ = &GetActuator<DifferentialSteering>("differential_steering");
    left_ = params.GetDouble("left", 0);
    right_ = params.GetDouble("right", 0);
  }
  void ControlStep() override {
    fixes.push_back({sensor_->x(), sensor_->y(), sensor_->z(), sensor_->yaw()});
    wheels_->SetLinearVelocity(left_, right_);
  }
  std::vector<Fix> fixes;

 private:
  const PositioningSensor* sensor_ = nullptr;
  DifferentialSteering* wheels_ = nullptr;
  double left_ = 0, right_ = 0;
};

COLONY_REGISTER_CONTROLLER(PositioningProbe, "positioning_probe",
                           "test: records positioning readings");

std::string Controllers(const std::string& attributes = "", const std::string& params = "") {
  return "<positioning_probe id=\"pp\"><sensors><positioning " + attributes +
         "/></sensors><actuators><differential_steering/></actuators><params " + params +
         "/></positioning_probe>";
}

std::string Robot(const std::string& id, const std::string& position,
                  const std::string& orientation = "0,0,0") {
  return "<marxbot id=\"" + id + "\"><body position=\"" + position + "\" orientation=\"" +
         orientation + "\"/><controller config=\"pp\"/></marxbot>";
}

PositioningProbe& Probe(Simulation& sim, const std::string& robot) {
  auto* probe = dynamic_cast<PositioningProbe*>(sim.ControllerOf(sim.space().Find(robot)));
  EXPECT_NE(probe, nullptr);
  return *probe;
}

TEST(Positioning, ReportsThePoseGivenInBody) {
  auto sim =
      LoadXml(Experiment(Robot("a", "0.5,-0.3,0", "90,0,0") + Robot("b", "-1.2,1.1,0", "-45,0,0") +
                             Robot("c", "0,0,0.2", "200,0,0"),
                         Controllers()));
  sim->Step();
  const Fix a = Probe(*sim, "a").fixes.back();
  EXPECT_NEAR(a.x, 0.5, 1e-12);
  EXPECT_NEAR(a.y, -0.3, 1e-12);
  EXPECT_NEAR(a.z, 0.0, 1e-12);
  EXPECT_NEAR(a.yaw, M_PI / 2, 1e-12);  // radians, counter-clockwise from +x
  const Fix b = Probe(*sim, "b").fixes.back();
  EXPECT_NEAR(b.x, -1.2, 1e-12);
  EXPECT_NEAR(b.y, 1.1, 1e-12);
  EXPECT_NEAR(b.yaw, -M_PI / 4, 1e-12);
  const Fix c = Probe(*sim, "c").fixes.back();
  EXPECT_NEAR(c.z, 0.2, 1e-12);
  EXPECT_NEAR(c.yaw, DegToRad(200 - 360), 1e-12);  // wrapped into (-pi, pi]
}

TEST(Positioning, HeadingStaysInTheDocumentedInterval) {
  // positioning.h promises yaw in (-pi, pi]; a robot facing -x must read +pi,
  // whichever way its orientation was written. Exposes YawOf returning -pi.
  auto sim = LoadXml(Experiment(
      Robot("plus", "0,-1,0", "180,0,0") + Robot("minus", "0,1,0", "-180,0,0"), Controllers()));
  sim->Step();
  for (const char* id : {"plus", "minus"}) {
    const double yaw = Probe(*sim, id).fixes.back().yaw;
    EXPECT_NEAR(std::abs(yaw), M_PI, 1e-12) << id;
    EXPECT_GT(yaw, -M_PI) << id;
    EXPECT_LE(yaw, M_PI) << id;
  }
}

TEST(Positioning, FollowsTheRobotAsItMoves) {
  // Straight ahead along +y at 0.1 m/s; commands given at tick t apply from
  // tick t+1, so after 11 ticks the robot moved 10 ticks x 0.01 m.
  auto sim = LoadXml(
      Experiment(Robot("r", "0,0,0", "90,0,0"), Controllers("", "left=\"0.1\" right=\"0.1\"")));
  for (int t = 0; t < 11; ++t) sim->Step();
  const Fix f = Probe(*sim, "r").fixes.back();
  EXPECT_NEAR(f.x, 0.0, 1e-9);
  EXPECT_NEAR(f.y, 0.1, 1e-9);
  EXPECT_NEAR(f.yaw, M_PI / 2, 1e-9);
  const Pose& truth = sim->space().pose(sim->space().Find("r").index);
  EXPECT_DOUBLE_EQ(f.x, truth.position.x());
  EXPECT_DOUBLE_EQ(f.y, truth.position.y());
  EXPECT_DOUBLE_EQ(f.yaw, YawOf(truth.orientation));
}

TEST(Positioning, HeadingFollowsTurning) {
  // Spinning on the spot at 0.07 m/s per wheel: 1 rad/s.
  auto sim =
      LoadXml(Experiment(Robot("r", "0,0,0"), Controllers("", "left=\"-0.07\" right=\"0.07\"")));
  for (int t = 0; t < 6; ++t) sim->Step();
  const Fix f = Probe(*sim, "r").fixes.back();
  EXPECT_NEAR(f.yaw, 0.5, 1e-9);  // 5 ticks of 0.1 rad
  EXPECT_NEAR(f.x, 0.0, 1e-12);
  EXPECT_NEAR(f.y, 0.0, 1e-12);
}

TEST(Positioning, GaussianNoiseIsReproducibleAndSmall) {
  const std::string noisy =
      Controllers("noise=\"gaussian\" noise_std_dev=\"0.01\" angle_noise_std_dev=\"0.05\"");
  auto a = LoadXml(Experiment(Robot("r", "0.5,0.5,0", "30,0,0"), noisy));
  auto b = LoadXml(Experiment(Robot("r", "0.5,0.5,0", "30,0,0"), noisy));
  for (int t = 0; t < 50; ++t) {
    a->Step();
    b->Step();
  }
  const auto& fa = Probe(*a, "r").fixes;
  const auto& fb = Probe(*b, "r").fixes;
  ASSERT_EQ(fa.size(), 50u);
  double sx = 0, syaw = 0;
  int differ = 0;
  for (size_t i = 0; i < fa.size(); ++i) {
    EXPECT_EQ(fa[i].x, fb[i].x);
    EXPECT_EQ(fa[i].yaw, fb[i].yaw);
    EXPECT_NEAR(fa[i].x, 0.5, 0.06);
    EXPECT_NEAR(fa[i].y, 0.5, 0.06);
    EXPECT_NEAR(fa[i].yaw, DegToRad(30), 0.3);
    differ += fa[i].x != 0.5;
    sx += fa[i].x - 0.5;
    syaw += fa[i].yaw - DegToRad(30);
  }
  EXPECT_EQ(differ, 50);
  EXPECT_NEAR(sx / 50, 0.0, 0.006);  // unbiased: 4 standard errors
  EXPECT_NEAR(syaw / 50, 0.0, 0.03);
}

TEST(Positioning, UniformNoiseStaysWithinItsRangeAndHeadingIsExactWithoutAngleNoise) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0", "60,0,0"),
                                Controllers("noise=\"uniform\" noise_range=\"-0.02,0.02\"")));
  for (int t = 0; t < 30; ++t) sim->Step();
  for (const Fix& f : Probe(*sim, "r").fixes) {
    EXPECT_LE(std::abs(f.x), 0.02);
    EXPECT_LE(std::abs(f.y), 0.02);
    EXPECT_NEAR(f.yaw, DegToRad(60), 1e-12);
  }
}

TEST(Positioning, BadAngleNoiseIsReported) {
  const std::string message =
      LoadError(Experiment(Robot("r", "0,0,0"), Controllers("angle_noise_std_dev=\"-1\"")));
  EXPECT_NE(message.find("attribute 'angle_noise_std_dev'"), std::string::npos) << message;
  EXPECT_NE(message.find(">= 0"), std::string::npos) << message;
}

}  // namespace
}  // namespace colony
