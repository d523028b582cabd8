// The rotating distance scanner as a controller sees it: (angle, distance)
// readings of 2 short-range and 2 long-range Sharp sensors on a rotor, with
// each sensor's folded response curve, and the last full scan of each type.
#include "sensors/distance_scanner/distance_scanner.h"

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

constexpr float kNone = DistanceScanner::kNoReading;
constexpr double kRotorRadius = 0.065;  // the sensors' faces, from the robot's axis

class ScannerProbe : public Controller {
 public:
  void Init(const Params& params) override {
    sensor = &GetSensor<DistanceScanner>("distance_scanner");
  }
  void ControlStep() override { last = sensor->readings(); }
  const DistanceScanner* sensor = nullptr;
  std::vector<DistanceScanner::Reading> last;
};

COLONY_REGISTER_CONTROLLER(ScannerProbe, "scanner_probe",
                           "test: records distance scanner readings");

std::string Controllers(const std::string& attributes = "") {
  return "<scanner_probe id=\"sp\"><sensors><distance_scanner " + attributes +
         "/></sensors></scanner_probe>";
}

std::string Robot(const std::string& id, const std::string& position, double yaw_degrees = 0) {
  return "<marxbot id=\"" + id + "\"><body position=\"" + position + "\" orientation=\"" +
         std::to_string(yaw_degrees) + ",0,0\"/><controller config=\"sp\"/></marxbot>";
}

// A fixed wall 3.8 m wide and 0.5 m high whose near face is the plane x = face.
std::string WallAt(double face, const std::string& id = "wall") {
  return "<box id=\"" + id + "\" size=\"0.1,3.8,0.5\" movable=\"false\"><body position=\"" +
         std::to_string(face + 0.05) + ",0,0\"/></box>";
}

ScannerProbe& Probe(Simulation& sim, const std::string& robot) {
  return *dynamic_cast<ScannerProbe*>(sim.ControllerOf(sim.space().Find(robot)));
}

const std::vector<float>& Scan(Simulation& sim, const std::string& robot,
                               DistanceScanner::SensorType type) {
  return Probe(sim, robot).sensor->scan(type);
}

void StepTimes(Simulation& sim, int ticks) {
  for (int t = 0; t < ticks; ++t) sim.Step();
}

TEST(DistanceScanner, OneScanEveryHalfTurnAtTheDeclaredSpeed) {
  // 10 ticks per second. A scan (half a rotor turn) takes 1 / scans_per_second.
  for (const double sps : {0.5, 1.0, 2.0}) {
    auto sim = LoadXml(Experiment(Robot("r", "0,0,0"),
                                  Controllers("scans_per_second=\"" + std::to_string(sps) + "\"")));
    const int ticks_per_scan = static_cast<int>(std::lround(10 / sps));
    const DistanceScanner& s = *Probe(*sim, "r").sensor;
    EXPECT_NEAR(s.bin_width(), DegToRad(3 * sps), 1e-12) << sps;
    ASSERT_EQ(s.scan(DistanceScanner::kShortRange).size(),
              static_cast<size_t>(std::lround(120 / sps)));
    StepTimes(*sim, ticks_per_scan - 1);
    EXPECT_EQ(s.scans_completed(), 0u) << sps;
    // The rotor turned by pi x sps x t.
    EXPECT_NEAR(s.rotor_angle(), M_PI * sps * (ticks_per_scan - 1) * 0.1, 1e-9) << sps;
    StepTimes(*sim, 1);
    EXPECT_EQ(s.scans_completed(), 1u) << sps;
    EXPECT_NEAR(s.rotor_angle(), M_PI, 1e-9) << sps;
    StepTimes(*sim, ticks_per_scan);
    EXPECT_EQ(s.scans_completed(), 2u) << sps;
    EXPECT_NEAR(s.rotor_angle(), 0.0, 1e-9) << sps;
    // About 60 samples per second per sensor: 6 per tick, 24 readings.
    EXPECT_EQ(Probe(*sim, "r").last.size(), 24u) << sps;
  }
}

TEST(DistanceScanner, ReadingsOfATickComeInOrderFromTheFourSensors) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers()));
  sim->Step();
  const auto& r = Probe(*sim, "r").last;
  ASSERT_EQ(r.size(), 24u);
  // Samples 1..6 of the first tick: rotor at 3, 6, ..., 18 degrees; sensor j
  // looks j quarter turns further, types alternate short/long.
  for (int k = 0; k < 6; ++k) {
    for (int j = 0; j < 4; ++j) {
      const auto& x = r[4 * k + j];
      EXPECT_EQ(x.sensor, j);
      EXPECT_EQ(x.type, j % 2 == 0 ? DistanceScanner::kShortRange : DistanceScanner::kLongRange);
      EXPECT_NEAR(x.angle, WrapAngle(DegToRad(3.0 * (k + 1) + 90.0 * j)), 1e-6) << k << " " << j;
      EXPECT_EQ(x.distance, kNone);  // nothing around
    }
  }
}

TEST(DistanceScanner, WallIsReadAtItsDistance) {
  // Face 0.5 m ahead: beyond the short sensors' 30 cm, within the long ones'.
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0") + WallAt(0.5), Controllers()));
  StepTimes(*sim, 10);
  const auto& longs = Scan(*sim, "r", DistanceScanner::kLongRange);
  const auto& shorts = Scan(*sim, "r", DistanceScanner::kShortRange);
  ASSERT_EQ(longs.size(), 120u);
  EXPECT_NEAR(longs[0], 0.5, 1e-6);
  // Each ray at angle a meets the plane 0.5 / cos(a) from the axis; rays up
  // to 69 degrees (max_incidence 70) read it, every point on the plane.
  for (int i = -23; i <= 23; ++i) {
    const double a = DegToRad(3.0 * i);
    const float d = longs[(i + 120) % 120];
    EXPECT_NEAR(d, 0.5 / std::cos(a), 1e-5) << "bin at " << 3 * i << " degrees";
    EXPECT_NEAR(d * std::cos(a), 0.5, 1e-5);
  }
  EXPECT_EQ(longs[24], kNone);  // 72 degrees: too oblique
  EXPECT_EQ(longs[120 - 24], kNone);
  for (int i = 31; i < 90; ++i) EXPECT_EQ(longs[i], kNone) << "nothing behind, bin " << i;
  for (float d : shorts) EXPECT_EQ(d, kNone);
}

TEST(DistanceScanner, NearWallIsReadByTheShortSensorsAndFoldsTheLongOnes) {
  // Face 0.2 m from the axis: 0.135 m from the sensors' faces.
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0") + WallAt(0.2), Controllers()));
  StepTimes(*sim, 10);
  EXPECT_NEAR(Scan(*sim, "r", DistanceScanner::kShortRange)[0], 0.2, 1e-6);
  // The long sensor is inside its 20 cm dead zone: V / Vp = 0.2 + 0.8 x
  // 0.135 / 0.2 = 0.74, read back as (0.2 + 0.085) / 0.74 - 0.085 from its face.
  const double folded = kRotorRadius + 0.285 / 0.74 - 0.085;
  EXPECT_NEAR(Scan(*sim, "r", DistanceScanner::kLongRange)[0], folded, 1e-6);
  EXPECT_GT(folded, 0.36);
}

TEST(DistanceScanner, ObjectNearerThanTheShortMinimumReadsFartherAsTheCurveSays) {
  // Face 9 cm from the axis (5 mm from the body): 2.5 cm from the sensors'
  // faces, below the short sensor's 4 cm minimum. On the fold V / Vp = 0.2 +
  // 0.8 x 2.5 / 4 = 0.7; the robot inverts the monotonic branch:
  // (0.04 + 0.0042) / 0.7 - 0.0042 = 5.89 cm from the face, 12.39 cm from the axis.
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0") + WallAt(0.09), Controllers()));
  StepTimes(*sim, 10);
  const double short_reads = kRotorRadius + 0.0442 / 0.7 - 0.0042;
  EXPECT_NEAR(short_reads, 0.123943, 1e-6);
  EXPECT_NEAR(Scan(*sim, "r", DistanceScanner::kShortRange)[0], short_reads, 1e-6);
  // The long sensor: V / Vp = 0.2 + 0.8 x 0.025 / 0.2 = 0.3, read as 0.865 m.
  EXPECT_NEAR(Scan(*sim, "r", DistanceScanner::kLongRange)[0], kRotorRadius + 0.285 / 0.3 - 0.085,
              1e-6);
  // Moved to 6 cm from the face (12.5 cm from the axis) it reads right.
  auto right = LoadXml(Experiment(Robot("r", "0,0,0") + WallAt(0.125), Controllers()));
  StepTimes(*right, 10);
  EXPECT_NEAR(Scan(*right, "r", DistanceScanner::kShortRange)[0], 0.125, 1e-6);
}

TEST(DistanceScanner, BeyondRangeThereIsNoReading) {
  {
    // Face 1.56 m from the axis: 1.495 m from the face, just in range head-on;
    // at 3 degrees 1.4971 m, at 6 degrees 1.5036 m: out.
    auto sim = LoadXml(Experiment(Robot("r", "0,0,0") + WallAt(1.56), Controllers()));
    StepTimes(*sim, 10);
    const auto& longs = Scan(*sim, "r", DistanceScanner::kLongRange);
    EXPECT_NEAR(longs[0], 1.56, 1e-6);
    EXPECT_NEAR(longs[1], 1.56 / std::cos(DegToRad(3)), 1e-6);
    EXPECT_EQ(longs[2], kNone);
    EXPECT_EQ(longs[118], kNone);
  }
  {
    auto sim = LoadXml(Experiment(Robot("r", "0,0,0") + WallAt(1.7), Controllers()));
    StepTimes(*sim, 10);
    for (auto type : {DistanceScanner::kShortRange, DistanceScanner::kLongRange}) {
      for (float d : Scan(*sim, "r", type)) EXPECT_EQ(d, kNone);
    }
  }
  {
    // Ranges can be narrowed: a 1 m long range misses the wall at 1.2 m.
    auto sim =
        LoadXml(Experiment(Robot("r", "0,0,0") + WallAt(1.2), Controllers("long_range=\"0.2,1\"")));
    StepTimes(*sim, 10);
    EXPECT_EQ(Scan(*sim, "r", DistanceScanner::kLongRange)[0], kNone);
    auto wide = LoadXml(Experiment(Robot("r", "0,0,0") + WallAt(1.2), Controllers()));
    StepTimes(*wide, 10);
    EXPECT_NEAR(Scan(*wide, "r", DistanceScanner::kLongRange)[0], 1.2, 1e-6);
  }
}

TEST(DistanceScanner, ObliqueSurfacesReadAsHoles) {
  auto sim =
      LoadXml(Experiment(Robot("r", "0,0,0") + WallAt(0.5), Controllers("max_incidence=\"30\"")));
  StepTimes(*sim, 10);
  const auto& longs = Scan(*sim, "r", DistanceScanner::kLongRange);
  EXPECT_NEAR(longs[9], 0.5 / std::cos(DegToRad(27)), 1e-5);
  EXPECT_EQ(longs[11], kNone);
  EXPECT_EQ(longs[120 - 11], kNone);
}

TEST(DistanceScanner, AnglesAreInTheRobotsFrame) {
  // Facing +y with a wall whose face is 0.5 m along +y: seen straight ahead.
  auto sim = LoadXml(Experiment(
      Robot("r", "0,0,0", 90) +
          "<box id=\"w\" size=\"2,0.1,0.5\" movable=\"false\"><body position=\"0,0.55,0\"/></box>",
      Controllers()));
  StepTimes(*sim, 10);
  const auto& longs = Scan(*sim, "r", DistanceScanner::kLongRange);
  EXPECT_NEAR(longs[0], 0.5, 1e-6);
  EXPECT_EQ(longs[60], kNone);  // behind
  EXPECT_EQ(longs[30], kNone);  // left (-x): nothing
}

TEST(DistanceScanner, SeesRobotsAndTallObjectsNotLowOnes) {
  // Another marXbot 0.4 m ahead (14.7 cm tall, spans the 9 cm plane); a 5 cm
  // box 0.5 m to the left (under the plane); a box hanging from 12 cm to the right.
  auto sim = LoadXml(Experiment(
      Robot("r", "0,0,0") + Robot("other", "0.4,0,0") +
          "<box id=\"low\" size=\"0.1,0.1,0.05\"><body position=\"0,0.55,0\"/></box>"
          "<box id=\"high\" size=\"0.1,0.1,0.2\"><body position=\"0,-0.55,0.12\"/></box>",
      Controllers()));
  StepTimes(*sim, 10);
  const auto& longs = Scan(*sim, "r", DistanceScanner::kLongRange);
  EXPECT_NEAR(longs[0], 0.4 - 0.085, 1e-6);
  EXPECT_EQ(longs[30], kNone);
  EXPECT_EQ(longs[90], kNone);
  // The other robot sees this one behind it.
  EXPECT_NEAR(Scan(*sim, "other", DistanceScanner::kLongRange)[60], 0.4 - 0.085, 1e-6);
}

TEST(DistanceScanner, ReadsTheSameInDynamics2d) {
  if (!Registry<PhysicsEngine>::Get().Find("dynamics2d"))
    GTEST_SKIP() << "built without dynamics2d";
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0") + WallAt(0.5) + WallAt(-0.3 - 0.1, "behind"),
                                Controllers(), "4,4,1", "", "<dynamics2d id=\"d2d\"/>"));
  StepTimes(*sim, 10);
  EXPECT_NEAR(Scan(*sim, "r", DistanceScanner::kLongRange)[0], 0.5, 1e-6);
  EXPECT_EQ(Scan(*sim, "r", DistanceScanner::kShortRange)[0], kNone);
  // The wall behind: its face 0.3 m away along -x.
  EXPECT_NEAR(Scan(*sim, "r", DistanceScanner::kShortRange)[60], 0.3, 1e-6);
}

TEST(DistanceScanner, RobotAddedLaterPublishesOnlyFullScans) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0") + WallAt(1.0), Controllers()));
  StepTimes(*sim, 3);
  sim->AddEntity(Robot("late", "0,-1,0"));
  StepTimes(*sim, 7);  // t = 1 s: the first robot's first scan is complete, the late one's is not
  EXPECT_EQ(Probe(*sim, "r").sensor->scans_completed(), 1u);
  EXPECT_EQ(Probe(*sim, "late").sensor->scans_completed(), 0u);
  EXPECT_EQ(Scan(*sim, "late", DistanceScanner::kLongRange)[0], kNone);
  StepTimes(*sim, 10);
  EXPECT_EQ(Probe(*sim, "late").sensor->scans_completed(), 1u);
  EXPECT_NEAR(Scan(*sim, "late", DistanceScanner::kLongRange)[0], 1.0, 1e-6);
  // Its rotor turns in phase with the others'.
  EXPECT_EQ(Probe(*sim, "late").sensor->rotor_angle(), Probe(*sim, "r").sensor->rotor_angle());
}

// The long sensors' readings of the wall 0.5 m ahead within +-30 degrees,
// minus the true value 0.5 / cos(angle), over `ticks` ticks.
std::vector<double> LongErrors(const std::string& attributes, int ticks, int* lost = nullptr) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0") + WallAt(0.5), Controllers(attributes)));
  std::vector<double> errors;
  for (int t = 0; t < ticks; ++t) {
    sim->Step();
    for (const auto& x : Probe(*sim, "r").last) {
      if (x.type != DistanceScanner::kLongRange || std::abs(x.angle) > DegToRad(30.5)) continue;
      if (x.distance == kNone) {
        if (lost) ++*lost;
        continue;
      }
      errors.push_back(x.distance - 0.5 / std::cos(x.angle));
    }
  }
  return errors;
}

std::pair<double, double> MeanAndSd(const std::vector<double>& v) {
  double sum = 0, sum2 = 0;
  for (double x : v) {
    sum += x;
    sum2 += x * x;
  }
  const double mean = sum / v.size();
  return {mean, std::sqrt(sum2 / v.size() - mean * mean)};
}

TEST(DistanceScanner, NoiseOffIsExactNoiseOnHasTheDeclaredSpread) {
  const auto exact = LongErrors("", 100);
  ASSERT_GT(exact.size(), 100u);
  for (double e : exact) EXPECT_NEAR(e, 0.0, 1e-6);
  const auto gaussian = LongErrors("noise=\"gaussian\" noise_std_dev=\"0.01\"", 1000);
  ASSERT_GT(gaussian.size(), 1500u);
  const auto [mean, sd] = MeanAndSd(gaussian);
  EXPECT_NEAR(mean, 0.0, 0.001);
  EXPECT_NEAR(sd, 0.01, 0.001);
  const auto uniform = LongErrors("noise=\"uniform\" noise_range=\"-0.02,0.02\"", 1000);
  const auto [umean, usd] = MeanAndSd(uniform);
  EXPECT_NEAR(umean, 0.0, 0.002);
  EXPECT_NEAR(usd, 0.04 / std::sqrt(12.0), 0.001);
  for (double e : uniform) EXPECT_LE(std::abs(e), 0.02 + 1e-6);
  int lost = 0;
  const auto dropped = LongErrors("drop_probability=\"0.2\"", 1000, &lost);
  EXPECT_NEAR(static_cast<double>(lost) / (lost + dropped.size()), 0.2, 0.03);
}

TEST(DistanceScanner, SameResultsWhateverTheThreadCount) {
  std::string arena =
      "<walls thickness=\"0.1\" height=\"0.5\"/>"
      "<distribute><position method=\"uniform\" min=\"-3.5,-3.5,0\" max=\"3.5,3.5,0\"/>"
      "<orientation method=\"uniform\" min=\"0,0,0\" max=\"360,0,0\"/>"
      "<entity quantity=\"300\"><marxbot id=\"mb\"><controller config=\"sp\"/></marxbot></entity>"
      "</distribute>";
  const std::string xml = Experiment(
      arena, Controllers("noise=\"gaussian\" noise_std_dev=\"0.01\" drop_probability=\"0.1\""),
      "8,8,1");
  std::vector<uint64_t> hashes;
  for (int threads : {0, 1, 2, 4}) {
    auto sim = LoadXml(xml, {}, threads);
    StepTimes(*sim, 12);
    hashes.push_back(sim->StateHash());
  }
  for (size_t i = 1; i < hashes.size(); ++i) EXPECT_EQ(hashes[i], hashes[0]) << "run " << i;
}

TEST(DistanceScanner, BadAttributesAreReportedWithElementAndLine) {
  const std::string robot = Robot("r", "0,0,0");
  // The sensor's element on line 3 of the file.
  const std::string fast =
      LoadError(Experiment(robot,
                           "<scanner_probe id=\"sp\">\n<sensors>\n<distance_scanner "
                           "scans_per_second=\"3\"/></sensors></scanner_probe>"));
  EXPECT_NE(
      fast.find("<string>:3: <distance_scanner> attribute 'scans_per_second': '3' is out of range; "
                "accepted: a number in [0.01, 2]"),
      std::string::npos)
      << fast;
  const std::string zero = LoadError(Experiment(robot, Controllers("scans_per_second=\"0\"")));
  EXPECT_NE(zero.find("attribute 'scans_per_second'"), std::string::npos) << zero;
  const std::string negative =
      LoadError(Experiment(robot, Controllers("short_range=\"-0.04,0.3\"")));
  EXPECT_NE(negative.find("attribute 'short_range'"), std::string::npos) << negative;
  EXPECT_NE(negative.find("'-0.04,0.3' is out of range"), std::string::npos) << negative;
  const std::string swapped = LoadError(Experiment(robot, Controllers("long_range=\"1.5,0.2\"")));
  EXPECT_NE(swapped.find("attribute 'long_range'"), std::string::npos) << swapped;
  EXPECT_NE(swapped.find("the minimum range must be below the maximum"), std::string::npos)
      << swapped;
  const std::string single = LoadError(Experiment(robot, Controllers("long_range=\"1.5\"")));
  EXPECT_NE(single.find("is not two finite numbers"), std::string::npos) << single;
  const std::string incidence = LoadError(Experiment(robot, Controllers("max_incidence=\"100\"")));
  EXPECT_NE(incidence.find("attribute 'max_incidence'"), std::string::npos) << incidence;
  const std::string model =
      LoadError(Experiment(robot, Controllers("noise=\"gausian\" noise_std_dev=\"0.1\"")));
  EXPECT_NE(model.find("<distance_scanner>"), std::string::npos) << model;
  EXPECT_NE(model.find("attribute 'noise'"), std::string::npos) << model;
  EXPECT_NE(model.find("did you mean 'gaussian'"), std::string::npos) << model;
}

TEST(DistanceScanner, RegisteredAttributesMatchTheReadme) {
  const auto* entry = Registry<SensorSystem>::Get().Find("distance_scanner");
  ASSERT_NE(entry, nullptr);
  std::vector<std::string> registered = entry->info.AttributeNames();
  EXPECT_EQ(registered, (std::vector<std::string>{"scans_per_second", "short_range", "long_range",
                                                  "max_incidence", "noise", "noise_std_dev",
                                                  "noise_range", "drop_probability"}));
  registered.push_back("implementation");
  EXPECT_EQ(testing::ReadmeAttributes("sensors/distance_scanner"), registered);
}

}  // namespace
}  // namespace colony
