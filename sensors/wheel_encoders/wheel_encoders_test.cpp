// Wheel encoders as a controller sees them: how far each wheel moved during
// the last tick (m), as the engine reports it, with optional slip and noise.
#include "sensors/wheel_encoders/wheel_encoders.h"

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

// Drives at params left/right (m/s) from the start and sums its encoders.
class EncoderProbe : public Controller {
 public:
  void Init(const Params& params) override {
    encoders_ = &GetSensor<WheelEncoders>("wheel_encoders");
    wheels_ = &GetActuator<DifferentialSteering>("differential_steering");
    // Commanded in Init: the wheels turn from the first tick on.
    wheels_->SetLinearVelocity(params.GetDouble("left", 0), params.GetDouble("right", 0));
  }
  void ControlStep() override {
    left.push_back(encoders_->distance_left());
    right.push_back(encoders_->distance_right());
    wheel_base = encoders_->wheel_base();
  }
  double SumLeft() const { return Sum(left); }
  double SumRight() const { return Sum(right); }
  std::vector<double> left, right;
  double wheel_base = 0;

 private:
  static double Sum(const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x;
    return s;
  }
  const WheelEncoders* encoders_ = nullptr;
  DifferentialSteering* wheels_ = nullptr;
};

COLONY_REGISTER_CONTROLLER(EncoderProbe, "encoder_probe",
                           "test: drives and sums wheel encoder readings");

std::string Controllers(const std::string& params, const std::string& encoder_attributes = "",
                        const std::string& steering_attributes = "") {
  return "<encoder_probe id=\"ep\"><sensors><wheel_encoders " + encoder_attributes +
         "/></sensors><actuators><differential_steering " + steering_attributes +
         "/></actuators><params " + params + "/></encoder_probe>";
}

std::string Robot(const std::string& id, const std::string& position, double yaw_degrees = 0) {
  return "<marxbot id=\"" + id + "\"><body position=\"" + position + "\" orientation=\"" +
         std::to_string(yaw_degrees) + ",0,0\"/><controller config=\"ep\"/></marxbot>";
}

EncoderProbe& Probe(Simulation& sim, const std::string& robot) {
  auto* probe = dynamic_cast<EncoderProbe*>(sim.ControllerOf(sim.space().Find(robot)));
  EXPECT_NE(probe, nullptr);
  return *probe;
}

Vec2 Position(Simulation& sim, const std::string& robot) {
  return sim.space().pose(sim.space().Find(robot).index).position.head<2>();
}

TEST(WheelEncoders, OneSecondAtTenCentimetresPerSecondIsTenCentimetres) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers("left=\"0.1\" right=\"0.1\"")));
  for (int t = 0; t < 10; ++t) sim->Step();  // 1 s at 10 ticks per second
  const EncoderProbe& p = Probe(*sim, "r");
  // The default acceleration limit (3 m/s^2, 0.3 m/s per tick) reaches
  // 0.1 m/s within the first tick.
  EXPECT_NEAR(p.SumLeft(), 0.1, 1e-9);
  EXPECT_NEAR(p.SumRight(), 0.1, 1e-9);
  for (double d : p.left) EXPECT_NEAR(d, 0.01, 1e-12);
  EXPECT_NEAR(Position(*sim, "r").x(), 0.1, 1e-9);
  EXPECT_DOUBLE_EQ(p.wheel_base, 0.14);
}

TEST(WheelEncoders, AccelerationLimitShowsInTheFirstTicks) {
  // 0.5 m/s^2 at 10 ticks per second: +0.05 m/s per tick up to 0.2 m/s.
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers("left=\"0.2\" right=\"0.2\"", "",
                                                                 "max_acceleration=\"0.5\"")));
  for (int t = 0; t < 10; ++t) sim->Step();
  const EncoderProbe& p = Probe(*sim, "r");
  const double expected[] = {0.005, 0.01, 0.015, 0.02, 0.02, 0.02, 0.02, 0.02, 0.02, 0.02};
  ASSERT_EQ(p.left.size(), 10u);
  for (int t = 0; t < 10; ++t) {
    EXPECT_NEAR(p.left[t], expected[t], 1e-12) << "tick " << t;
    EXPECT_NEAR(p.right[t], expected[t], 1e-12) << "tick " << t;
  }
  EXPECT_NEAR(p.SumLeft(), 0.17, 1e-9);
  EXPECT_NEAR(Position(*sim, "r").x(), 0.17, 1e-9);
}

TEST(WheelEncoders, BackwardsIsNegative) {
  auto sim =
      LoadXml(Experiment(Robot("r", "0,0,0"), Controllers("left=\"-0.05\" right=\"-0.05\"")));
  for (int t = 0; t < 10; ++t) sim->Step();
  EXPECT_NEAR(Probe(*sim, "r").SumLeft(), -0.05, 1e-9);
  EXPECT_NEAR(Position(*sim, "r").x(), -0.05, 1e-9);
}

TEST(WheelEncoders, TurningGivesDifferentDistancesThatMatchTheHeading) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers("left=\"0.05\" right=\"0.1\"")));
  for (int t = 0; t < 20; ++t) sim->Step();
  const EncoderProbe& p = Probe(*sim, "r");
  EXPECT_NEAR(p.SumLeft(), 0.1, 1e-9);
  EXPECT_NEAR(p.SumRight(), 0.2, 1e-9);
  // Odometry: heading change = (right - left) / wheel base.
  const double yaw = YawOf(sim->space().pose(sim->space().Find("r").index).orientation);
  EXPECT_NEAR((p.SumRight() - p.SumLeft()) / p.wheel_base, yaw, 1e-9);
}

TEST(WheelEncoders, RobotBlockedByAWallReportsLess) {
  // The east wall's inner face is at x = 1.9; the free robot drives in the
  // open, the blocked one starts 1 cm from the wall.
  auto sim =
      LoadXml(Experiment("<walls thickness=\"0.1\" height=\"0.5\"/>" + Robot("free", "0,0,0") +
                             Robot("blocked", std::to_string(1.9 - 0.085 - 0.01) + ",1,0"),
                         Controllers("left=\"0.1\" right=\"0.1\"")));
  for (int t = 0; t < 10; ++t) sim->Step();
  const EncoderProbe& free_robot = Probe(*sim, "free");
  const EncoderProbe& blocked = Probe(*sim, "blocked");
  EXPECT_NEAR(free_robot.SumLeft(), 0.1, 1e-9);
  EXPECT_LT(blocked.SumLeft(), 0.05);
  EXPECT_LT(blocked.SumRight(), 0.05);
  // What the encoders report matches how far it really went.
  const double moved = Position(*sim, "blocked").x() - (1.9 - 0.085 - 0.01);
  EXPECT_NEAR(blocked.SumLeft(), moved, 1e-9);
  EXPECT_LE(Position(*sim, "blocked").x() + 0.085, 1.9);
  EXPECT_TRUE(sim->space().in_contact(sim->space().Find("blocked").index));
}

TEST(WheelEncoders, BlockedRobotTurningOnTheSpotStillCountsTheTurn) {
  // Pressed against the wall and spinning: the wheels turn in opposite
  // directions as much as commanded.
  auto sim =
      LoadXml(Experiment("<walls thickness=\"0.1\" height=\"0.5\"/>" + Robot("r", "1.814,0,0"),
                         Controllers("left=\"-0.05\" right=\"0.05\"")));
  for (int t = 0; t < 10; ++t) sim->Step();
  EXPECT_NEAR(Probe(*sim, "r").SumLeft(), -0.05, 1e-9);
  EXPECT_NEAR(Probe(*sim, "r").SumRight(), 0.05, 1e-9);
}

TEST(WheelEncoders, SlipShortensTheReadingsReproducibly) {
  const std::string arena = Robot("r", "0,0,0");
  const std::string controllers = Controllers("left=\"0.1\" right=\"0.1\"", "slip=\"0.2\"");
  auto a = LoadXml(Experiment(arena, controllers));
  auto b = LoadXml(Experiment(arena, controllers));
  for (int t = 0; t < 20; ++t) {
    a->Step();
    b->Step();
  }
  const EncoderProbe& pa = Probe(*a, "r");
  const EncoderProbe& pb = Probe(*b, "r");
  EXPECT_EQ(pa.left, pb.left);
  EXPECT_EQ(pa.right, pb.right);
  // The robot really moved 0.2 m; the encoders count less, never more.
  EXPECT_NEAR(Position(*a, "r").x(), 0.2, 1e-9);
  EXPECT_LT(pa.SumLeft(), 0.2);
  EXPECT_LT(pa.SumRight(), 0.2);
  EXPECT_GT(pa.SumLeft(), 0.1);
  for (size_t t = 0; t < pa.left.size(); ++t) {
    EXPECT_LE(pa.left[t], 0.01 + 1e-15);
    EXPECT_GE(pa.left[t], 0.0);
  }
  EXPECT_NE(pa.left, pa.right);  // each wheel slips on its own
}

TEST(WheelEncoders, NoiseIsAdded) {
  auto sim = LoadXml(Experiment(
      Robot("r", "0,0,0"),
      Controllers("left=\"0.1\" right=\"0.1\"", "noise=\"uniform\" noise_range=\"-0.001,0.001\"")));
  for (int t = 0; t < 10; ++t) sim->Step();
  int differ = 0;
  for (double d : Probe(*sim, "r").left) {
    EXPECT_NEAR(d, 0.01, 0.001 + 1e-12);
    differ += d != 0.01;
  }
  EXPECT_GT(differ, 5);
}

TEST(WheelEncoders, BadSlipIsReported) {
  const std::string message =
      LoadError(Experiment(Robot("r", "0,0,0"), Controllers("", "slip=\"2\"")));
  EXPECT_NE(message.find("attribute 'slip'"), std::string::npos) << message;
  EXPECT_NE(message.find("[0, 1]"), std::string::npos) << message;
}

}  // namespace
}  // namespace colony
