// Light sensors as a controller sees them: a ring of 24 readings on the
// marXbot, each intensity / (1 + d^2) x cos(angle to the light), summed over
// the lights it sees, in [0, 1].
#include "sensors/light/light.h"

#include <cmath>
#include <regex>
#include <string>
#include <vector>

#include "core/registry.h"
#include "tests/test_util.h"

namespace colony {
namespace {

using testing::Experiment;
using testing::LoadError;
using testing::LoadXml;

// Copies what its light ring read at every control step.
class LightProbe : public Controller {
 public:
  void Init(const Params& params) override { sensor_ = &GetSensor<LightSensor>("light"); }
  void ControlStep() override { last = sensor_->readings(); }
  std::vector<LightSensor::Reading> last;

 private:
  const LightSensor* sensor_ = nullptr;
};

COLONY_REGISTER_CONTROLLER(LightProbe, "light_probe", "test: records light readings");

std::string Controllers(const std::string& attributes = "") {
  return "<light_probe id=\"lp\"><sensors><light " + attributes + "/></sensors></light_probe>";
}

std::string Robot(const std::string& id, const std::string& position, double yaw_degrees = 0) {
  return "<marxbot id=\"" + id + "\"><body position=\"" + position + "\" orientation=\"" +
         std::to_string(yaw_degrees) + ",0,0\"/><controller config=\"lp\"/></marxbot>";
}

std::string Light(const std::string& id, const std::string& position, double intensity = 1) {
  return "<light id=\"" + id + "\" position=\"" + position + "\" intensity=\"" +
         std::to_string(intensity) + "\"/>";
}

std::string Box(const std::string& id, const std::string& size, const std::string& position) {
  return "<box id=\"" + id + "\" size=\"" + size + "\" movable=\"false\"><body position=\"" +
         position + "\"/></box>";
}

const std::vector<LightSensor::Reading>& Readings(Simulation& sim, const std::string& robot) {
  auto* probe = dynamic_cast<LightProbe*>(sim.ControllerOf(sim.space().Find(robot)));
  EXPECT_NE(probe, nullptr) << robot;
  static const std::vector<LightSensor::Reading> kNone;
  return probe ? probe->last : kNone;
}

float MaxOf(const std::vector<LightSensor::Reading>& r) {
  float m = 0;
  for (const auto& x : r) m = std::max(m, x.value);
  return m;
}

// The ring is 6 cm above the floor: a light at that height and distance d,
// straight ahead, gives sensor i (at 7.5 + 15 i degrees) 1/(1+d^2) cos(angle).
double Expected(double d, double sensor_degrees, double intensity = 1) {
  const double c = std::cos(DegToRad(sensor_degrees));
  return c > 0 ? intensity / (1 + d * d) * c : 0.0;
}

TEST(Light, MarxbotHas24SensorsFifteenDegreesApart) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers()));
  sim->Step();
  const auto& r = Readings(*sim, "r");
  ASSERT_EQ(r.size(), 24u);
  for (size_t i = 0; i < r.size(); ++i) {
    EXPECT_NEAR(r[i].angle, WrapAngle(DegToRad(7.5 + 15.0 * i)), 1e-6) << "sensor " << i;
  }
}

TEST(Light, NoLightReadsZero) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers()));
  sim->Step();
  EXPECT_EQ(MaxOf(Readings(*sim, "r")), 0.0f);
}

TEST(Light, LightInFrontIsReadByTheFrontSensorsNotTheRear) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0") + Light("l", "1,0,0.06"), Controllers()));
  sim->Step();
  const auto& r = Readings(*sim, "r");
  ASSERT_EQ(r.size(), 24u);
  for (size_t i = 0; i < r.size(); ++i) {
    EXPECT_NEAR(r[i].value, Expected(1.0, 7.5 + 15.0 * i), 1e-6) << "sensor " << i;
  }
  EXPECT_NEAR(r[0].value, 0.5 * std::cos(DegToRad(7.5)), 1e-6);
  EXPECT_EQ(r[0].value, r[23].value);
  EXPECT_EQ(MaxOf(r), r[0].value);
  // Everything facing backwards (sensors 6..17: 97.5 to 262.5 degrees) reads 0.
  for (size_t i = 6; i <= 17; ++i) EXPECT_EQ(r[i].value, 0.0f) << "sensor " << i;
  EXPECT_GT(r[5].value, 0.0f);  // 82.5 degrees still sees it
}

TEST(Light, ReadingsFollowTheRobotsHeading) {
  // Facing +y, with the light at +x: the light is on the robot's right.
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0", 90) + Light("l", "1,0,0.06"), Controllers()));
  sim->Step();
  const auto& r = Readings(*sim, "r");
  // Sensors 17 and 18 are at -97.5 and -82.5 degrees.
  EXPECT_NEAR(r[17].value, Expected(1.0, 7.5), 1e-6);
  EXPECT_NEAR(r[18].value, Expected(1.0, 7.5), 1e-6);
  EXPECT_EQ(r[0].value, 0.0f);  // 7.5 degrees from the front: 97.5 degrees from the light
  EXPECT_EQ(r[5].value, 0.0f);
}

TEST(Light, ReadingsFallWithDistance) {
  std::vector<float> front;
  for (double d : {0.5, 1.0, 2.0, 3.0}) {
    auto sim = LoadXml(
        Experiment(Robot("r", "-1.5,0,0") + Light("l", std::to_string(-1.5 + d) + ",0,0.06"),
                   Controllers(), "8,8,2"));
    sim->Step();
    front.push_back(Readings(*sim, "r")[0].value);
    EXPECT_NEAR(front.back(), Expected(d, 7.5), 1e-6) << "distance " << d;
  }
  for (size_t i = 1; i < front.size(); ++i) EXPECT_LT(front[i], front[i - 1]);
}

TEST(Light, DistanceCountsTheLightsHeight) {
  // 1 m ahead and 1 m above the ring: d^2 = 2, bearing still straight ahead.
  auto sim =
      LoadXml(Experiment(Robot("r", "0,0,0") + Light("l", "1,0,1.06"), Controllers(), "4,4,3"));
  sim->Step();
  EXPECT_NEAR(Readings(*sim, "r")[0].value, 1.0 / 3.0 * std::cos(DegToRad(7.5)), 1e-6);
}

TEST(Light, IntensityScalesAndLightsAddUpToAtMostOne) {
  {
    auto sim =
        LoadXml(Experiment(Robot("r", "0,0,0") + Light("l", "1,0,0.06", 1.5), Controllers()));
    sim->Step();
    EXPECT_NEAR(Readings(*sim, "r")[0].value, Expected(1.0, 7.5, 1.5), 1e-6);
  }
  {
    // One light ahead, one on the left: sensor 5 (82.5 degrees) sees both.
    auto sim = LoadXml(Experiment(
        Robot("r", "0,0,0") + Light("a", "1,0,0.06") + Light("b", "0,1,0.06"), Controllers()));
    sim->Step();
    const auto& r = Readings(*sim, "r");
    EXPECT_NEAR(r[5].value, Expected(1.0, 82.5) + Expected(1.0, 7.5), 1e-6);
    EXPECT_NEAR(r[0].value, Expected(1.0, 7.5) + Expected(1.0, 82.5), 1e-6);
    EXPECT_EQ(r[12].value, 0.0f);  // 187.5 degrees: behind and to the right
  }
  {
    // A strong light close by saturates the sensors facing it at 1.
    auto sim =
        LoadXml(Experiment(Robot("r", "0,0,0") + Light("l", "0.3,0,0.06", 5), Controllers()));
    sim->Step();
    const auto& r = Readings(*sim, "r");
    EXPECT_EQ(r[0].value, 1.0f);
    EXPECT_EQ(r[23].value, 1.0f);
    EXPECT_LT(r[5].value, 1.0f);  // 5 / 1.09 x cos 82.5 = 0.6
  }
}

TEST(Light, LightBehindAWallReadsZeroWithOcclusionsChecked) {
  const std::string arena =
      Robot("r", "0,0,0") + Light("l", "1,0,0.06") + Box("wall", "0.1,1,0.5", "0.5,0,0");
  {
    auto sim = LoadXml(Experiment(arena, Controllers()));
    sim->Step();
    EXPECT_EQ(MaxOf(Readings(*sim, "r")), 0.0f);
  }
  {
    auto sim = LoadXml(Experiment(arena, Controllers("check_occlusions=\"false\"")));
    sim->Step();
    EXPECT_NEAR(Readings(*sim, "r")[0].value, Expected(1.0, 7.5), 1e-6);
  }
}

TEST(Light, OtherRobotsHideALightButLowBoxesAndHighLightsPassOver) {
  {
    // Another marXbot (14.7 cm tall) halfway: the light at ring height is hidden.
    auto sim = LoadXml(Experiment(
        Robot("r", "0,0,0") + Robot("other", "0.5,0,0") + Light("l", "1,0,0.06"), Controllers()));
    sim->Step();
    EXPECT_EQ(MaxOf(Readings(*sim, "r")), 0.0f);
    // The other robot sees it (its own body does not hide it).
    EXPECT_NEAR(Readings(*sim, "other")[0].value, Expected(0.5, 7.5), 1e-6);
  }
  {
    // A 3 cm box is below the line from the ring (6 cm) to the light.
    auto sim = LoadXml(Experiment(
        Robot("r", "0,0,0") + Light("l", "1,0,0.06") + Box("low", "0.1,1,0.03", "0.5,0,0"),
        Controllers()));
    sim->Step();
    EXPECT_NEAR(Readings(*sim, "r")[0].value, Expected(1.0, 7.5), 1e-6);
  }
  {
    // A 20 cm wall 0.5 m ahead hides a light 2 m ahead at 30 cm, not one at 2 m
    // high (the line passes the wall at about 0.5 m).
    const std::string wall = Box("wall", "0.1,1,0.2", "0.5,0,0");
    auto low = LoadXml(
        Experiment(Robot("r", "0,0,0") + wall + Light("l", "2,0,0.3"), Controllers(), "6,6,3"));
    low->Step();
    EXPECT_EQ(MaxOf(Readings(*low, "r")), 0.0f);
    auto high = LoadXml(
        Experiment(Robot("r", "0,0,0") + wall + Light("l", "2,0,2"), Controllers(), "6,6,3"));
    high->Step();
    const double d2 = 4 + 1.94 * 1.94;
    EXPECT_NEAR(Readings(*high, "r")[0].value, 1 / (1 + d2) * std::cos(DegToRad(7.5)), 1e-6);
  }
  {
    // A wall beside the line, not across it, hides nothing.
    auto sim = LoadXml(Experiment(
        Robot("r", "0,0,0") + Light("l", "1,0,0.06") + Box("side", "1,0.1,0.5", "0.5,0.3,0"),
        Controllers()));
    sim->Step();
    EXPECT_NEAR(Readings(*sim, "r")[0].value, Expected(1.0, 7.5), 1e-6);
  }
}

TEST(Light, TallWallsHideLightsAboveTheRobotsWhateverTheirNumber) {
  // A light 2 m ahead and 2 m high; a 1 m wall 1 m ahead cuts the line at
  // about 0.98 m, far above any robot. Many tall pillars elsewhere (more
  // than are tested one by one) must not change the answer.
  std::string pillars;
  for (int i = 0; i < 70; ++i) {
    pillars += "<cylinder id=\"p" + std::to_string(i) +
               "\" radius=\"0.02\" height=\"1.5\" movable=\"false\"><body position=\"" +
               std::to_string(-2.8 + 0.08 * i) + ",-2.5,0\"/></cylinder>";
  }
  const std::string wall = Box("wall", "0.1,1,1", "1,0,0");
  const std::string light = Light("l", "2,0,2");
  const double clear = 1 / (1 + 4 + 1.94 * 1.94) * std::cos(DegToRad(7.5));
  for (const std::string& extra : {std::string(), pillars}) {
    auto hidden =
        LoadXml(Experiment(Robot("r", "0,0,0") + light + wall + extra, Controllers(), "6,6,3"));
    hidden->Step();
    EXPECT_EQ(MaxOf(Readings(*hidden, "r")), 0.0f)
        << (extra.empty() ? "few tall bodies" : "many tall bodies");
    auto seen = LoadXml(Experiment(Robot("r", "0,0,0") + light + extra, Controllers(), "6,6,3"));
    seen->Step();
    EXPECT_NEAR(Readings(*seen, "r")[0].value, clear, 1e-6)
        << (extra.empty() ? "few tall bodies" : "many tall bodies");
  }
}

TEST(Light, LongLinesAcrossManyGridCellsAreChecked) {
  // 7 m to the light, past a thin pole near the light: the line crosses a
  // dozen grid cells before meeting it. From 1 m aside, the line misses it.
  const std::string arena =
      Robot("r", "-3.5,0,0") + Light("l", "3.5,0,0.06") +
      "<cylinder id=\"pole\" radius=\"0.02\" height=\"1\" movable=\"false\"><body "
      "position=\"3,0,0\"/></cylinder>";
  auto sim = LoadXml(Experiment(arena, Controllers(), "8,8,2"));
  sim->Step();
  EXPECT_EQ(MaxOf(Readings(*sim, "r")), 0.0f);
  auto moved = LoadXml(
      Experiment(Robot("r", "-3.5,1,0") + Light("l", "3.5,0,0.06") +
                     "<cylinder id=\"pole\" radius=\"0.02\" height=\"1\" movable=\"false\"><body "
                     "position=\"3,0,0\"/></cylinder>",
                 Controllers(), "8,8,2"));
  moved->Step();
  EXPECT_GT(Readings(*moved, "r")[0].value, 0.01f);
}

TEST(Light, LightsAddedAtRunTimeAreSeenFromTheNextTick) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers()));
  sim->Step();
  EXPECT_EQ(MaxOf(Readings(*sim, "r")), 0.0f);
  const EntityHandle light = sim->AddEntity(Light("l", "1,0,0.06"));
  sim->Step();
  EXPECT_NEAR(Readings(*sim, "r")[0].value, Expected(1.0, 7.5), 1e-6);
  sim->RemoveEntity(light);
  sim->Step();
  EXPECT_EQ(MaxOf(Readings(*sim, "r")), 0.0f);
}

// Mean and standard deviation of the four front sensors' noisy readings minus
// their clean values, over `ticks` ticks.
std::pair<double, double> NoiseStats(const std::string& attributes, int ticks,
                                     double* lowest_offset = nullptr,
                                     double* highest_offset = nullptr, int* zeros = nullptr) {
  auto sim =
      LoadXml(Experiment(Robot("r", "0,0,0") + Light("l", "1,0,0.06"), Controllers(attributes)));
  const int sensors[] = {0, 1, 22, 23};
  double sum = 0, sum2 = 0;
  int n = 0;
  for (int t = 0; t < ticks; ++t) {
    sim->Step();
    const auto& r = Readings(*sim, "r");
    for (int i : sensors) {
      if (zeros && r[i].value == 0.0f) {
        ++*zeros;
        continue;
      }
      const double e = r[i].value - Expected(1.0, 7.5 + 15.0 * i);
      sum += e;
      sum2 += e * e;
      ++n;
      if (lowest_offset) *lowest_offset = std::min(*lowest_offset, e);
      if (highest_offset) *highest_offset = std::max(*highest_offset, e);
    }
  }
  const double mean = sum / n;
  return {mean, std::sqrt(sum2 / n - mean * mean)};
}

TEST(Light, GaussianNoiseHasTheDeclaredSpread) {
  const auto [mean, sd] = NoiseStats("noise=\"gaussian\" noise_std_dev=\"0.05\"", 1000);
  EXPECT_NEAR(mean, 0.0, 0.005);
  EXPECT_NEAR(sd, 0.05, 0.005);
}

TEST(Light, UniformNoiseStaysInItsRangeWithItsSpread) {
  double lo = 1, hi = -1;
  const auto [mean, sd] = NoiseStats("noise=\"uniform\" noise_range=\"-0.1,0.1\"", 1000, &lo, &hi);
  EXPECT_GE(lo, -0.1 - 1e-6);
  EXPECT_LE(hi, 0.1 + 1e-6);
  EXPECT_LT(lo, -0.09);
  EXPECT_GT(hi, 0.09);
  EXPECT_NEAR(mean, 0.0, 0.008);
  EXPECT_NEAR(sd, 0.2 / std::sqrt(12.0), 0.005);
}

TEST(Light, DroppedReadingsReadZero) {
  int zeros = 0;
  NoiseStats("drop_probability=\"0.25\"", 1000, nullptr, nullptr, &zeros);
  EXPECT_NEAR(zeros / 4000.0, 0.25, 0.03);
}

TEST(Light, NoiseIsReproducibleAndIndependentOfThreads) {
  std::string arena =
      Light("l1", "0,0,0.5") + Light("l2", "2,2,0.3") + Box("wall", "0.1,2,0.5", "-1,0,0");
  arena +=
      "<distribute><position method=\"uniform\" min=\"-3.5,-3.5,0\" max=\"3.5,3.5,0\"/>"
      "<orientation method=\"uniform\" min=\"0,0,0\" max=\"360,0,0\"/>"
      "<entity quantity=\"200\"><marxbot id=\"mb\"><controller "
      "config=\"lp\"/></marxbot></entity></distribute>";
  const std::string xml =
      Experiment(arena, Controllers("noise=\"gaussian\" noise_std_dev=\"0.02\""), "8,8,2");
  std::vector<uint64_t> hashes;
  for (int threads : {0, 1, 2, 4}) {
    auto sim = LoadXml(xml, {}, threads);
    for (int t = 0; t < 5; ++t) sim->Step();
    hashes.push_back(sim->StateHash());
  }
  for (size_t i = 1; i < hashes.size(); ++i) EXPECT_EQ(hashes[i], hashes[0]) << "run " << i;
  auto other_seed = LoadXml(xml, {"framework.experiment.random_seed=8"});
  for (int t = 0; t < 5; ++t) other_seed->Step();
  EXPECT_NE(other_seed->StateHash(), hashes[0]);
}

TEST(Light, BadAttributesAreReportedWithElementAndLine) {
  const std::string robot = Robot("r", "0,0,0");
  // The sensor's element on line 3 of the file.
  const std::string occlusions =
      LoadError(Experiment(robot,
                           "<light_probe id=\"lp\">\n<sensors>\n<light "
                           "check_occlusions=\"maybe\"/></sensors></light_probe>"));
  EXPECT_NE(
      occlusions.find("<string>:3: <light> attribute 'check_occlusions': 'maybe' is not a boolean"),
      std::string::npos)
      << occlusions;
  const std::string model =
      LoadError(Experiment(robot, Controllers("noise=\"gausian\" noise_std_dev=\"0.1\"")));
  EXPECT_NE(model.find("<light>"), std::string::npos) << model;
  EXPECT_NE(model.find("attribute 'noise'"), std::string::npos) << model;
  EXPECT_NE(model.find("did you mean 'gaussian'"), std::string::npos) << model;
  const std::string spread =
      LoadError(Experiment(robot, Controllers("noise=\"gaussian\" noise_std_dev=\"-1\"")));
  EXPECT_NE(spread.find("attribute 'noise_std_dev'"), std::string::npos) << spread;
  EXPECT_NE(spread.find(">= 0"), std::string::npos) << spread;
  const std::string typo = LoadError(Experiment(robot, Controllers("check_occlusion=\"true\"")));
  EXPECT_NE(typo.find("did you mean 'check_occlusions'"), std::string::npos) << typo;
}

TEST(Light, RegisteredAttributesMatchTheReadme) {
  const auto* entry = Registry<SensorSystem>::Get().Find("light");
  ASSERT_NE(entry, nullptr);
  std::vector<std::string> registered = entry->info.AttributeNames();
  EXPECT_EQ(registered, (std::vector<std::string>{"check_occlusions", "noise", "noise_std_dev",
                                                  "noise_range", "drop_probability"}));
  registered.push_back("implementation");
  EXPECT_EQ(testing::ReadmeAttributes("sensors/light"), registered);
}

}  // namespace
}  // namespace colony
