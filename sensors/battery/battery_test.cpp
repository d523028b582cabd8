// The battery as a controller sees it: a level falling with time and with
// wheel travel; an empty battery stops the robot unless told otherwise.
#include "sensors/battery/battery.h"

#include <cmath>
#include <regex>
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

// Drives at params left/right (m/s) and records the battery.
class BatteryProbe : public Controller {
 public:
  void Init(const Params& params) override {
    battery = &GetSensor<Battery>("battery");
    wheels_ = &GetActuator<DifferentialSteering>("differential_steering");
    left_ = params.GetDouble("left", 0);
    right_ = params.GetDouble("right", 0);
    wheels_->SetLinearVelocity(left_, right_);
    level_at_init = battery->level();
    remaining_at_init = battery->remaining_energy();
  }
  void ControlStep() override {
    wheels_->SetLinearVelocity(left_, right_);
    levels.push_back(battery->level());
  }
  const Battery* battery = nullptr;
  std::vector<double> levels;
  double level_at_init = -1, remaining_at_init = -1;

 private:
  DifferentialSteering* wheels_ = nullptr;
  double left_ = 0, right_ = 0;
};

COLONY_REGISTER_CONTROLLER(BatteryProbe, "battery_probe",
                           "test: drives and records the battery level");

std::string Controllers(const std::string& attributes, const std::string& params = "") {
  return "<battery_probe "
         "id=\"bp\"><actuators><differential_steering/></actuators><sensors><battery " +
         attributes + "/></sensors><params " + params + "/></battery_probe>";
}

std::string Robot(const std::string& id, const std::string& position) {
  return "<marxbot id=\"" + id + "\"><body position=\"" + position +
         "\"/><controller config=\"bp\"/></marxbot>";
}

BatteryProbe& Probe(Simulation& sim, const std::string& robot) {
  return *dynamic_cast<BatteryProbe*>(sim.ControllerOf(sim.space().Find(robot)));
}

const Vec3& PositionOf(Simulation& sim, const std::string& robot) {
  return sim.space().pose(sim.space().Find(robot).index).position;
}

void StepTimes(Simulation& sim, int ticks) {
  for (int t = 0; t < ticks; ++t) sim.Step();
}

TEST(Battery, IdleDrainFollowsIdlePower) {
  // 10 W from 1000 J: 1 J per tick of 0.1 s.
  auto sim = LoadXml(Experiment(
      Robot("r", "0,0,0"), Controllers("capacity=\"1000\" idle_power=\"10\" motion_energy=\"0\"")));
  const Battery& b = *Probe(*sim, "r").battery;
  EXPECT_EQ(b.level(), 1.0);
  EXPECT_EQ(b.capacity(), 1000.0);
  for (int t = 1; t <= 100; ++t) {
    sim->Step();
    EXPECT_NEAR(b.level(), 1.0 - 0.001 * t, 1e-12) << "tick " << t;
  }
  EXPECT_NEAR(b.remaining_energy(), 900.0, 1e-9);
  EXPECT_FALSE(b.empty());
}

TEST(Battery, MovingDrainsInProportionToWheelTravel) {
  // 1 W idle, 100 J per metre; 0.1 m/s is 1 cm per tick, 1 J.
  const std::string battery = "capacity=\"1000\" idle_power=\"1\" motion_energy=\"100\"";
  auto drive = LoadXml(
      Experiment(Robot("r", "-1.5,0,0"), Controllers(battery, "left=\"0.1\" right=\"0.1\"")));
  auto spin =
      LoadXml(Experiment(Robot("r", "0,0,0"), Controllers(battery, "left=\"-0.1\" right=\"0.1\"")));
  auto still = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers(battery)));
  StepTimes(*drive, 50);
  StepTimes(*spin, 50);
  StepTimes(*still, 50);
  // 5 s: 5 J idle for everyone, plus 50 J for 50 cm of wheel travel.
  EXPECT_NEAR(Probe(*still, "r").battery->level(), 1 - 5.0 / 1000, 1e-12);
  EXPECT_NEAR(Probe(*drive, "r").battery->level(), 1 - 55.0 / 1000, 1e-12);
  EXPECT_NEAR(PositionOf(*drive, "r").x(), -1.0, 1e-9);
  // Turning on the spot moves the wheels as much: the same drain.
  EXPECT_NEAR(Probe(*spin, "r").battery->level(), 1 - 55.0 / 1000, 1e-12);
}

TEST(Battery, MarxbotDefaultsLastSevenHoursAtTopSpeed) {
  // 38 Wh; 2.4 W idle + 10 J/m x 0.3 m/s = 5.4 W at top speed.
  auto drive =
      LoadXml(Experiment(Robot("r", "-1.5,0,0"), Controllers("", "left=\"0.3\" right=\"0.3\"")));
  auto still = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers("")));
  StepTimes(*drive, 10);
  StepTimes(*still, 10);
  const Battery& moving = *Probe(*drive, "r").battery;
  EXPECT_EQ(moving.capacity(), 38 * 3600.0);
  // One second (the robot reaches top speed within the first tick).
  const double used_per_second = (1 - moving.level()) * moving.capacity();
  EXPECT_NEAR(used_per_second, 5.4, 1e-6);
  EXPECT_NEAR(moving.capacity() / used_per_second / 3600, 7.0, 0.1);  // hours
  const Battery& idle = *Probe(*still, "r").battery;
  EXPECT_NEAR((1 - idle.level()) * idle.capacity(), 2.4, 1e-6);
}

TEST(Battery, RobotStopsWhenEmpty) {
  // 10 J at 10 W: empty after 1 s (10 ticks).
  auto sim = LoadXml(Experiment(Robot("r", "-1.5,0,0"),
                                Controllers("capacity=\"10\" idle_power=\"10\" motion_energy=\"0\"",
                                            "left=\"0.1\" right=\"0.1\"")));
  const Battery& b = *Probe(*sim, "r").battery;
  StepTimes(*sim, 9);
  EXPECT_FALSE(b.empty());
  EXPECT_NEAR(PositionOf(*sim, "r").x(), -1.5 + 0.09, 1e-9);
  sim->Step();
  EXPECT_TRUE(b.empty());
  EXPECT_EQ(b.level(), 0.0);
  EXPECT_EQ(b.remaining_energy(), 0.0);
  EXPECT_FALSE(sim->space().drive(sim->space().Find("r").index)->powered);
  EXPECT_NEAR(PositionOf(*sim, "r").x(), -1.4, 1e-9);
  // The controller keeps asking for 0.1 m/s; the robot stays where it stopped.
  StepTimes(*sim, 20);
  EXPECT_NEAR(PositionOf(*sim, "r").x(), -1.4, 1e-9);
  EXPECT_EQ(b.level(), 0.0);
}

TEST(Battery, RobotStopsWhenEmptyInDynamics2d) {
  if (!Registry<PhysicsEngine>::Get().Find("dynamics2d"))
    GTEST_SKIP() << "built without dynamics2d";
  // 10 J at 10 W: empty after 1 s; then the wheels are commanded to stop.
  auto sim = LoadXml(Experiment(Robot("r", "-1.5,0,0"),
                                Controllers("capacity=\"10\" idle_power=\"10\" motion_energy=\"0\"",
                                            "left=\"0.1\" right=\"0.1\""),
                                "4,4,1", "", "<dynamics2d id=\"d2d\"/>"));
  StepTimes(*sim, 10);
  EXPECT_TRUE(Probe(*sim, "r").battery->empty());
  EXPECT_GT(PositionOf(*sim, "r").x(), -1.5 + 0.05);  // it was driving
  StepTimes(*sim, 10);
  const double stopped = PositionOf(*sim, "r").x();
  StepTimes(*sim, 10);
  EXPECT_NEAR(PositionOf(*sim, "r").x(), stopped, 1e-6);
}

TEST(Battery, RobotKeepsGoingWhenStopWhenEmptyIsFalse) {
  auto sim = LoadXml(Experiment(
      Robot("r", "-1.5,0,0"),
      Controllers("capacity=\"10\" idle_power=\"10\" motion_energy=\"0\" stop_when_empty=\"false\"",
                  "left=\"0.1\" right=\"0.1\"")));
  StepTimes(*sim, 30);
  const Battery& b = *Probe(*sim, "r").battery;
  EXPECT_TRUE(b.empty());
  EXPECT_EQ(b.level(), 0.0);
  EXPECT_TRUE(sim->space().drive(sim->space().Find("r").index)->powered);
  EXPECT_NEAR(PositionOf(*sim, "r").x(), -1.2, 1e-9);
}

TEST(Battery, InitialLevelIsReadFromTheStart) {
  auto sim = LoadXml(Experiment(
      Robot("r", "-1.5,0,0"),
      Controllers("capacity=\"1000\" initial_level=\"0.5\"", "left=\"0.1\" right=\"0.1\"")));
  EXPECT_EQ(Probe(*sim, "r").level_at_init, 0.5);
  EXPECT_EQ(Probe(*sim, "r").remaining_at_init, 500.0);
  // An empty battery from the start: the robot never moves.
  auto flat = LoadXml(Experiment(Robot("r", "-1.5,0,0"),
                                 Controllers("initial_level=\"0\"", "left=\"0.1\" right=\"0.1\"")));
  EXPECT_TRUE(Probe(*flat, "r").battery->empty());
  EXPECT_EQ(Probe(*flat, "r").level_at_init, 0.0);
  StepTimes(*flat, 10);
  EXPECT_EQ(PositionOf(*flat, "r").x(), -1.5);
}

std::pair<double, double> MeanAndSd(const std::vector<double>& v, double truth) {
  double sum = 0, sum2 = 0;
  for (double x : v) {
    sum += x - truth;
    sum2 += (x - truth) * (x - truth);
  }
  const double mean = sum / v.size();
  return {mean, std::sqrt(sum2 / v.size() - mean * mean)};
}

TEST(Battery, NoiseOnTheLevelHasTheDeclaredSpread) {
  // Half full and not draining: every reading is 0.5 plus noise.
  const std::string base = "initial_level=\"0.5\" idle_power=\"0\" motion_energy=\"0\" ";
  auto clean = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers(base)));
  StepTimes(*clean, 10);
  for (double l : Probe(*clean, "r").levels) EXPECT_EQ(l, 0.5);
  auto gaussian = LoadXml(Experiment(
      Robot("r", "0,0,0"), Controllers(base + "noise=\"gaussian\" noise_std_dev=\"0.02\"")));
  StepTimes(*gaussian, 3000);
  const auto [mean, sd] = MeanAndSd(Probe(*gaussian, "r").levels, 0.5);
  EXPECT_NEAR(mean, 0.0, 0.002);
  EXPECT_NEAR(sd, 0.02, 0.001);
  auto uniform = LoadXml(Experiment(
      Robot("r", "0,0,0"), Controllers(base + "noise=\"uniform\" noise_range=\"-0.05,0.05\"")));
  StepTimes(*uniform, 3000);
  const auto [umean, usd] = MeanAndSd(Probe(*uniform, "r").levels, 0.5);
  EXPECT_NEAR(umean, 0.0, 0.003);
  EXPECT_NEAR(usd, 0.1 / std::sqrt(12.0), 0.002);
  for (double l : Probe(*uniform, "r").levels) EXPECT_LE(std::abs(l - 0.5), 0.05 + 1e-12);
  // Noise never takes the reading outside [0, 1].
  auto full =
      LoadXml(Experiment(Robot("r", "0,0,0"),
                         Controllers("idle_power=\"0\" noise=\"gaussian\" noise_std_dev=\"0.1\"")));
  StepTimes(*full, 200);
  for (double l : Probe(*full, "r").levels) EXPECT_LE(l, 1.0);
}

TEST(Battery, SameResultsWhateverTheThreadCount) {
  const std::string arena =
      "<walls thickness=\"0.1\" height=\"0.5\"/>"
      "<distribute><position method=\"uniform\" min=\"-3.5,-3.5,0\" max=\"3.5,3.5,0\"/>"
      "<orientation method=\"uniform\" min=\"0,0,0\" max=\"360,0,0\"/>"
      "<entity quantity=\"300\"><marxbot id=\"mb\"><controller config=\"bp\"/></marxbot></entity>"
      "</distribute>";
  // Small batteries that empty during the run, with noise on the level.
  const std::string xml =
      Experiment(arena,
                 Controllers("capacity=\"30\" idle_power=\"5\" motion_energy=\"100\" "
                             "noise=\"gaussian\" noise_std_dev=\"0.01\"",
                             "left=\"0.2\" right=\"0.15\""),
                 "8,8,1");
  std::vector<uint64_t> hashes;
  for (int threads : {0, 1, 2, 4}) {
    auto sim = LoadXml(xml, {}, threads);
    StepTimes(*sim, 30);
    hashes.push_back(sim->StateHash());
  }
  for (size_t i = 1; i < hashes.size(); ++i) EXPECT_EQ(hashes[i], hashes[0]) << "run " << i;
}

TEST(Battery, BadAttributesAreReportedWithElementAndLine) {
  const std::string robot = Robot("r", "0,0,0");
  // The sensor's element on line 3 of the file.
  const std::string capacity = LoadError(Experiment(
      robot,
      "<battery_probe id=\"bp\">\n<actuators><differential_steering/></actuators><sensors>\n"
      "<battery capacity=\"-1\"/></sensors></battery_probe>"));
  EXPECT_NE(capacity.find("<string>:3: <battery> attribute 'capacity': '-1' is out of range; "
                          "accepted: a number > 0"),
            std::string::npos)
      << capacity;
  const std::string level = LoadError(Experiment(robot, Controllers("initial_level=\"1.5\"")));
  EXPECT_NE(level.find("attribute 'initial_level'"), std::string::npos) << level;
  EXPECT_NE(level.find("[0, 1]"), std::string::npos) << level;
  const std::string power = LoadError(Experiment(robot, Controllers("idle_power=\"-2\"")));
  EXPECT_NE(power.find("attribute 'idle_power'"), std::string::npos) << power;
  const std::string stop = LoadError(Experiment(robot, Controllers("stop_when_empty=\"perhaps\"")));
  EXPECT_NE(stop.find("attribute 'stop_when_empty'"), std::string::npos) << stop;
  const std::string model =
      LoadError(Experiment(robot, Controllers("noise=\"gausian\" noise_std_dev=\"0.1\"")));
  EXPECT_NE(model.find("<battery>"), std::string::npos) << model;
  EXPECT_NE(model.find("did you mean 'gaussian'"), std::string::npos) << model;
  // A battery reading is never lost: no drop_probability.
  const std::string drop = LoadError(Experiment(robot, Controllers("drop_probability=\"0.1\"")));
  EXPECT_NE(drop.find("attribute 'drop_probability'"), std::string::npos) << drop;
  EXPECT_NE(drop.find("unknown attribute"), std::string::npos) << drop;
}

TEST(Battery, RegisteredAttributesMatchTheReadme) {
  const auto* entry = Registry<SensorSystem>::Get().Find("battery");
  ASSERT_NE(entry, nullptr);
  std::vector<std::string> registered = entry->info.AttributeNames();
  EXPECT_EQ(registered,
            (std::vector<std::string>{"capacity", "initial_level", "idle_power", "motion_energy",
                                      "stop_when_empty", "noise", "noise_std_dev", "noise_range"}));
  registered.push_back("implementation");
  EXPECT_EQ(testing::ReadmeAttributes("sensors/battery"), registered);
}

}  // namespace
}  // namespace colony
