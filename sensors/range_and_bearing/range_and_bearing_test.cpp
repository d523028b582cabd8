// The range-and-bearing receiver as a controller sees it: who is heard, at
// what range and bearing in the robot's frame, through walls or not, with
// noise and losses as declared.
#include "sensors/range_and_bearing/range_and_bearing.h"

#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "actuators/range_and_bearing/range_and_bearing.h"
#include "core/registry.h"
#include "media/test_util.h"

namespace colony {
namespace {

using testing::ExpectMentions;
using testing::Experiment;
using testing::LoadError;
using testing::LoadXml;
using testing::ReadmeAttributes;

struct Heard {
  float range, bearing, elevation;
  std::string sender;  // the payload up to its first 0 byte
  size_t size;
};

// Broadcasts its id (as many bytes as fit) and records what it hears. With
// param stamp="true", byte 0 is instead the number of control steps done.
class RabProbe : public Controller {
 public:
  void Init(const Params& params) override {
    stamp_ = params.GetBool("stamp", false);
    silent_ = params.GetBool("silent", false);
    try {
      sensor_ = &GetSensor<RangeAndBearingSensor>("range_and_bearing");
    } catch (const std::logic_error&) {
    }
    try {
      actuator_ = &GetActuator<RangeAndBearingActuator>("range_and_bearing");
    } catch (const std::logic_error&) {
    }
    Send();
  }
  void ControlStep() override {
    ++steps;
    heard.clear();
    if (sensor_) {
      for (const auto& p : sensor_->packets()) {
        std::string s;
        for (uint8_t c : p.data) {
          if (!c) break;
          s += static_cast<char>(c);
        }
        if (stamp_) s = std::to_string(p.data[0]);
        heard.push_back({p.range, p.bearing, p.elevation, s, p.data.size()});
      }
    }
    Send();
  }
  std::vector<Heard> heard;
  int steps = 0;

 private:
  void Send() {
    if (!actuator_) return;
    if (silent_) {
      actuator_->Clear();
    } else if (stamp_) {
      actuator_->SetByte(0, static_cast<uint8_t>(steps));
    } else {
      actuator_->SetData({reinterpret_cast<const uint8_t*>(id().data()), id().size()});
    }
  }
  bool stamp_ = false, silent_ = false;
  const RangeAndBearingSensor* sensor_ = nullptr;
  RangeAndBearingActuator* actuator_ = nullptr;
};

COLONY_REGISTER_CONTROLLER(RabProbe, "rab_probe",
                           "test: broadcasts its id, records range-and-bearing packets");

// Controller configurations: "both" (sensor + actuator), "tx" (actuator only), "rx" (sensor only).
std::string Controllers(const std::string& sensor = "", const std::string& actuator = "",
                        const std::string& params = "") {
  return "<rab_probe id=\"both\"><sensors><range_and_bearing " + sensor +
         "/></sensors><actuators><range_and_bearing " + actuator + "/></actuators><params " +
         params +
         "/></rab_probe>"
         "<rab_probe id=\"tx\"><actuators><range_and_bearing " +
         actuator + "/></actuators><params " + params +
         "/></rab_probe>"
         "<rab_probe id=\"rx\"><sensors><range_and_bearing " +
         sensor + "/></sensors></rab_probe>";
}

std::string Robot(const std::string& id, double x, double y, double yaw_degrees = 0,
                  const std::string& config = "both") {
  return "<marxbot id=\"" + id + "\"><body position=\"" + std::to_string(x) + "," +
         std::to_string(y) + ",0\" orientation=\"" + std::to_string(yaw_degrees) +
         ",0,0\"/><controller config=\"" + config + "\"/></marxbot>";
}

std::string Box(const std::string& id, const std::string& size, const std::string& position) {
  return "<box id=\"" + id + "\" size=\"" + size + "\"><body position=\"" + position + "\"/></box>";
}

std::string Media(const std::string& attributes) {
  return "<media><range_and_bearing id=\"rab\" " + attributes + "/></media>";
}

RabProbe& Probe(Simulation& sim, const std::string& robot) {
  auto* probe = dynamic_cast<RabProbe*>(sim.ControllerOf(sim.space().Find(robot)));
  if (!probe) throw std::runtime_error("no probe on " + robot);
  return *probe;
}

std::map<std::string, Heard> HeardBy(Simulation& sim, const std::string& robot) {
  std::map<std::string, Heard> out;
  for (const auto& h : Probe(sim, robot).heard) out[h.sender] = h;
  return out;
}

std::set<std::string> Senders(Simulation& sim, const std::string& robot) {
  std::set<std::string> out;
  for (const auto& h : Probe(sim, robot).heard) out.insert(h.sender);
  return out;
}

TEST(RangeAndBearing, FrontLeftBehindRightInTheReceiversFrame) {
  auto sim = LoadXml(
      Experiment(Robot("r", 0, 0) + Robot("front", 1, 0, 0, "tx") + Robot("left", 0, 1.5, 0, "tx") +
                     Robot("behind", -0.5, 0, 0, "tx") + Robot("right", 0, -1, 0, "tx"),
                 Controllers()));
  sim->Step();
  auto heard = HeardBy(*sim, "r");
  ASSERT_EQ(heard.size(), 4u);
  EXPECT_NEAR(heard["front"].range, 1.0, 1e-6);
  EXPECT_NEAR(heard["front"].bearing, 0.0, 1e-6);
  EXPECT_NEAR(heard["left"].range, 1.5, 1e-6);
  EXPECT_NEAR(heard["left"].bearing, M_PI / 2, 1e-6);
  EXPECT_NEAR(heard["behind"].range, 0.5, 1e-6);
  EXPECT_NEAR(heard["behind"].bearing, M_PI, 1e-6);  // (-pi, pi]: behind is +pi
  EXPECT_GT(heard["behind"].bearing, 0.0f);
  EXPECT_NEAR(heard["right"].range, 1.0, 1e-6);
  EXPECT_NEAR(heard["right"].bearing, -M_PI / 2, 1e-6);
  for (auto& [id, h] : heard) {
    EXPECT_EQ(h.elevation, 0.0f) << id;  // same height
    EXPECT_EQ(h.size, 10u) << id;        // default payload size
  }
}

TEST(RangeAndBearing, BearingFollowsTheReceiversHeading) {
  // Receiver facing +y (90 degrees): a sender at +x is on its right, one at
  // +y in front. Another receiver facing 225 degrees (south-west) hears a
  // sender to its north-east straight behind, and one to its south-east on its left.
  // (Ids are the payloads: at most 10 bytes.)
  auto sim =
      LoadXml(Experiment(Robot("north", 0, 0, 90) + Robot("east", 1, 0, 0, "tx") +
                             Robot("ahead", 0, 0.8, 0, "tx") + Robot("sw", -5, -5, 225) +
                             Robot("ne", -4.4, -4.4, 0, "tx") + Robot("se", -4.4, -5.6, 0, "tx"),
                         Controllers(), "14,14,1"));
  sim->Step();
  auto north = HeardBy(*sim, "north");
  ASSERT_EQ(north.size(), 2u);
  EXPECT_NEAR(north["east"].bearing, -M_PI / 2, 1e-6);
  EXPECT_NEAR(north["east"].range, 1.0, 1e-6);
  EXPECT_NEAR(north["ahead"].bearing, 0.0, 1e-6);
  auto sw = HeardBy(*sim, "sw");
  ASSERT_EQ(sw.size(), 2u);
  EXPECT_NEAR(std::abs(sw["ne"].bearing), M_PI, 1e-6);
  EXPECT_NEAR(sw["ne"].range, 0.6 * std::sqrt(2.0), 1e-6);
  EXPECT_NEAR(sw["se"].bearing, M_PI / 2, 1e-6);
  // Transmitters only (no sensor) hear nothing.
  EXPECT_TRUE(HeardBy(*sim, "ne").empty());
}

TEST(RangeAndBearing, ElevationOfASenderAbove) {
  // A sender lifted 0.2 m (on something) 1 m ahead: elevation atan(0.2 / 1).
  auto sim = LoadXml(Experiment(
      Robot("r", 0, 0) +
          "<marxbot id=\"up\"><body position=\"1,0,0.2\"/><controller config=\"tx\"/></marxbot>",
      Controllers()));
  sim->Step();
  ASSERT_DOUBLE_EQ(sim->space().pose(sim->space().Find("up").index).position.z(),
                   0.2);  // kinematics2d keeps it there
  auto heard = HeardBy(*sim, "r");
  ASSERT_EQ(heard.size(), 1u);
  EXPECT_NEAR(heard["up"].elevation, std::atan2(0.2, 1.0), 1e-6);
  EXPECT_NEAR(heard["up"].range, std::hypot(0.2, 1.0), 1e-6);
  EXPECT_NEAR(heard["up"].bearing, 0.0, 1e-6);
}

TEST(RangeAndBearing, EveryoneHearsEveryoneElseNotItself) {
  auto sim = LoadXml(
      Experiment(Robot("a", 0, 0) + Robot("b", 0.5, 0.5) + Robot("c", -0.5, 0.5), Controllers()));
  sim->Step();
  EXPECT_EQ(Senders(*sim, "a"), (std::set<std::string>{"b", "c"}));
  EXPECT_EQ(Senders(*sim, "b"), (std::set<std::string>{"a", "c"}));
  EXPECT_EQ(Senders(*sim, "c"), (std::set<std::string>{"a", "b"}));
  // Symmetric geometry: b hears a at a's bearing + pi.
  auto a = HeardBy(*sim, "a");
  auto b = HeardBy(*sim, "b");
  EXPECT_NEAR(a["b"].range, b["a"].range, 1e-6);
  EXPECT_NEAR(a["b"].bearing, M_PI / 4, 1e-6);
  EXPECT_NEAR(b["a"].bearing, -3 * M_PI / 4, 1e-6);
}

TEST(RangeAndBearing, RangeLimitIsExact) {
  // Default range 3 m: a sender 1 um inside is heard, one 1 um outside is not.
  const double in = 3.0 - 1e-6, out = 3.0 + 1e-6;
  auto sim =
      LoadXml(Experiment(Robot("r1", -4, 0, 0, "rx") + Robot("in", -4 + in, 0, 0, "tx") +
                             Robot("r2", -4, 3, 0, "rx") + Robot("out", -4 + out, 3, 0, "tx"),
                         Controllers(), "10,10,1"));
  sim->Step();
  EXPECT_EQ(Senders(*sim, "r1"), (std::set<std::string>{"in"}));
  EXPECT_TRUE(Senders(*sim, "r2").empty());
  // The actuator's range attribute (here 1 m).
  auto short_range =
      LoadXml(Experiment(Robot("r1", 0, 0, 0, "rx") + Robot("in", 1 - 1e-6, 0, 0, "tx") +
                             Robot("r2", 0, 2, 0, "rx") + Robot("out", 1 + 1e-6, 2, 0, "tx"),
                         Controllers("", "range=\"1\""), "6,6,1"));
  short_range->Step();
  EXPECT_EQ(Senders(*short_range, "r1"), (std::set<std::string>{"in"}));
  EXPECT_TRUE(Senders(*short_range, "r2").empty());
  // The medium's range applies to actuators that set none.
  auto medium_range =
      LoadXml(Experiment(Robot("r1", 0, 0, 0, "rx") + Robot("in", 0.5 - 1e-6, 0, 0, "tx") +
                             Robot("r2", 0, 1, 0, "rx") + Robot("out", 0.5 + 1e-6, 1, 0, "tx"),
                         Controllers(), "4,4,1", Media("range=\"0.5\"")));
  medium_range->Step();
  EXPECT_EQ(Senders(*medium_range, "r1"), (std::set<std::string>{"in"}));
  EXPECT_TRUE(Senders(*medium_range, "r2").empty());
}

TEST(RangeAndBearing, RangeIsTheSendersSoAsymmetricLinksWork) {
  // "far" reaches 2 m, "near" only 0.5 m; they are 1 m apart.
  auto sim = LoadXml(Experiment(
      "<marxbot id=\"far\"><body position=\"0,0,0\"/><controller config=\"far\"/></marxbot>"
      "<marxbot id=\"near\"><body position=\"1,0,0\"/><controller config=\"near\"/></marxbot>",
      "<rab_probe id=\"far\"><sensors><range_and_bearing/></sensors><actuators>"
      "<range_and_bearing range=\"2\"/></actuators></rab_probe>"
      "<rab_probe id=\"near\"><sensors><range_and_bearing/></sensors><actuators>"
      "<range_and_bearing range=\"0.5\"/></actuators></rab_probe>"));
  sim->Step();
  EXPECT_EQ(Senders(*sim, "near"), (std::set<std::string>{"far"}));
  EXPECT_TRUE(Senders(*sim, "far").empty());
}

TEST(RangeAndBearing, AWallBlocksMessagesWhenOcclusionsAreChecked) {
  // A 20 cm wall between r and s (1 m apart); t is in the open.
  const std::string arena = Robot("r", 0, 0, 0, "rx") + Robot("s", 1, 0, 0, "tx") +
                            Robot("t", 0, 1, 0, "tx") + Box("wall", "0.1,0.6,0.2", "0.5,0,0");
  auto checked = LoadXml(Experiment(arena, Controllers()));
  checked->Step();
  EXPECT_EQ(Senders(*checked, "r"), (std::set<std::string>{"t"}));
  // The default medium checks occlusions; so does one declared without the attribute.
  auto declared = LoadXml(Experiment(arena, Controllers(), "4,4,1", Media("")));
  declared->Step();
  EXPECT_EQ(Senders(*declared, "r"), (std::set<std::string>{"t"}));
  auto unchecked =
      LoadXml(Experiment(arena, Controllers(), "4,4,1", Media("check_occlusions=\"false\"")));
  unchecked->Step();
  EXPECT_EQ(Senders(*unchecked, "r"), (std::set<std::string>{"s", "t"}));
  EXPECT_NEAR(HeardBy(*unchecked, "r")["s"].range, 1.0, 1e-6);
}

TEST(RangeAndBearing, LowObstaclesDoNotBlockRobotsInBetweenDo) {
  // The devices sit at mid-height of the body (7.35 cm): a 5 cm box does not
  // block; a robot in between does (ARGoS convention).
  // The two scenes are 6 m apart, out of each other's range.
  auto sim =
      LoadXml(Experiment(Robot("r", 0, -3, 0, "rx") + Robot("s", 1, -3, 0, "tx") +
                             Box("low", "0.1,0.6,0.05", "0.5,-3,0") + Robot("r2", 0, 3, 0, "rx") +
                             Robot("between", 0.5, 3, 0, "rx") + Robot("s2", 1, 3, 0, "tx"),
                         Controllers(), "10,10,1"));
  sim->Step();
  EXPECT_EQ(Senders(*sim, "r"), (std::set<std::string>{"s"}));
  EXPECT_EQ(Senders(*sim, "r2"), std::set<std::string>{});
  EXPECT_EQ(Senders(*sim, "between"), (std::set<std::string>{"s2"}));
}

TEST(RangeAndBearing, DiagonalWallAndCylinderBlock) {
  // A wall turned 45 degrees and a pillar, each on a line of sight.
  auto sim = LoadXml(Experiment(
      Robot("r", 0, 0, 0, "rx") + Robot("s1", 1, 1, 0, "tx") + Robot("s2", -1, 0, 0, "tx") +
          Robot("s3", 0, -1, 0, "tx") +
          "<box id=\"w\" size=\"0.05,0.5,0.3\"><body position=\"0.5,0.5,0\" "
          "orientation=\"45,0,0\"/></box>"
          "<cylinder id=\"p\" radius=\"0.05\" height=\"0.3\"><body position=\"-0.5,0.04,0\"/>"
          "</cylinder>",
      Controllers()));
  sim->Step();
  EXPECT_EQ(Senders(*sim, "r"), (std::set<std::string>{"s3"}));
}

TEST(RangeAndBearing, PayloadIsTheSendersAndSilentRobotsAreNotHeard) {
  auto sim =
      LoadXml(Experiment(Robot("r", 0, 0, 0, "rx") + Robot("talker", 1, 0, 0, "tx") +
                             "<marxbot id=\"quiet\"><body position=\"0,1,0\"/><controller "
                             "config=\"quiet\"/></marxbot>",
                         Controllers("", "data_size=\"4\"") +
                             "<rab_probe id=\"quiet\"><actuators><range_and_bearing/></actuators>"
                             "<params silent=\"true\"/></rab_probe>"));
  sim->Step();
  const auto& heard = Probe(*sim, "r").heard;
  ASSERT_EQ(heard.size(), 1u);
  EXPECT_EQ(heard[0].size, 4u);        // data_size of the sender
  EXPECT_EQ(heard[0].sender, "talk");  // its id, cut to 4 bytes
}

TEST(RangeAndBearing, AMessageSetAtOneStepIsReceivedAtTheNext) {
  // Each robot stamps byte 0 with its number of control steps done. During
  // tick t the sensors read what was set at the end of tick t-1.
  auto sim = LoadXml(
      Experiment(Robot("a", 0, 0) + Robot("b", 1, 0), Controllers("", "", "stamp=\"true\"")));
  for (int t = 1; t <= 5; ++t) {
    sim->Step();
    const auto& heard = Probe(*sim, "a").heard;
    ASSERT_EQ(heard.size(), 1u);
    EXPECT_EQ(heard[0].sender, std::to_string(t - 1)) << "tick " << t;
  }
}

TEST(RangeAndBearing, MessagesFollowMovingRobots) {
  // b is removed and added elsewhere at run time: heard from its new place.
  auto sim =
      LoadXml(Experiment(Robot("a", 0, 0, 0, "rx") + Robot("b", 1, 0, 0, "tx"), Controllers()));
  sim->Step();
  EXPECT_NEAR(HeardBy(*sim, "a")["b"].bearing, 0.0, 1e-6);
  sim->RemoveEntity(sim->space().Find("b"));
  sim->Step();
  EXPECT_TRUE(Senders(*sim, "a").empty());
  sim->AddEntity(Robot("b", 0, -1.2, 0, "tx"));
  sim->Step();
  auto heard = HeardBy(*sim, "a");
  ASSERT_EQ(heard.size(), 1u);
  EXPECT_NEAR(heard["b"].bearing, -M_PI / 2, 1e-6);
  EXPECT_NEAR(heard["b"].range, 1.2, 1e-6);
}

// --- noise and losses

// n senders on a circle of radius 1.5 around a receiver at the origin.
std::string Ring(int n) {
  std::string arena = Robot("r", 0, 0, 0, "rx");
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    arena += Robot("s" + std::to_string(i), 1.5 * std::cos(a), 1.5 * std::sin(a), 0, "tx");
  }
  return arena;
}

struct Spread {
  double mean = 0, std_dev = 0;
  size_t count = 0;
};
Spread SpreadOf(const std::vector<double>& v) {
  Spread s;
  s.count = v.size();
  for (double x : v) s.mean += x;
  s.mean /= v.size();
  for (double x : v) s.std_dev += (x - s.mean) * (x - s.mean);
  s.std_dev = std::sqrt(s.std_dev / (v.size() - 1));
  return s;
}

// Range and bearing errors of every packet over `ticks` ticks.
void Errors(const std::string& sensor_attributes, int ticks, std::vector<double>& range_errors,
            std::vector<double>& bearing_errors, size_t* packets = nullptr) {
  const int n = 36;
  auto sim = LoadXml(Experiment(Ring(n), Controllers(sensor_attributes)));
  size_t total = 0;
  for (int t = 0; t < ticks; ++t) {
    sim->Step();
    for (const auto& h : Probe(*sim, "r").heard) {
      const int i = std::stoi(h.sender.substr(1));
      range_errors.push_back(h.range - 1.5);
      bearing_errors.push_back(WrapAngle(h.bearing - WrapAngle(2 * M_PI * i / n)));
      EXPECT_GT(h.bearing, -M_PI);
      EXPECT_LE(h.bearing, static_cast<float>(M_PI));
      ++total;
    }
  }
  if (packets) *packets = total;
}

TEST(RangeAndBearing, NoNoiseGivesExactValues) {
  std::vector<double> range_errors, bearing_errors;
  size_t packets = 0;
  Errors("", 3, range_errors, bearing_errors, &packets);
  EXPECT_EQ(packets, 3u * 36);
  for (double e : range_errors) EXPECT_NEAR(e, 0, 1e-6);
  for (double e : bearing_errors) EXPECT_NEAR(e, 0, 1e-6);
}

TEST(RangeAndBearing, GaussianNoiseHasTheDeclaredSpread) {
  std::vector<double> range_errors, bearing_errors;
  Errors("noise=\"gaussian\" noise_std_dev=\"0.05\" bearing_noise_std_dev=\"0.1\"", 150,
         range_errors, bearing_errors);
  ASSERT_EQ(range_errors.size(), 150u * 36);
  const Spread range = SpreadOf(range_errors), bearing = SpreadOf(bearing_errors);
  EXPECT_NEAR(range.mean, 0, 0.003);
  EXPECT_NEAR(range.std_dev, 0.05, 0.05 * 0.04);
  EXPECT_NEAR(bearing.mean, 0, 0.006);
  EXPECT_NEAR(bearing.std_dev, 0.1, 0.1 * 0.04);
}

TEST(RangeAndBearing, UniformNoiseStaysInItsRangeWithTheRightSpread) {
  std::vector<double> range_errors, bearing_errors;
  Errors("noise=\"uniform\" noise_range=\"-0.1,0.1\"", 150, range_errors, bearing_errors);
  for (double e : range_errors) {
    ASSERT_GE(e, -0.1 - 1e-6);
    ASSERT_LE(e, 0.1 + 1e-6);
  }
  EXPECT_NEAR(SpreadOf(range_errors).std_dev, 0.2 / std::sqrt(12.0), 0.2 / std::sqrt(12.0) * 0.04);
  for (double e : bearing_errors) EXPECT_NEAR(e, 0, 1e-6);  // no bearing noise declared
}

TEST(RangeAndBearing, LossProbabilityIsAsDeclared) {
  std::vector<double> range_errors, bearing_errors;
  size_t packets = 0;
  Errors("drop_probability=\"0.3\"", 150, range_errors, bearing_errors, &packets);
  const double received = static_cast<double>(packets) / (150 * 36);
  EXPECT_NEAR(received, 0.7, 0.025);                      // 5400 draws: 3.5 standard deviations
  for (double e : range_errors) EXPECT_NEAR(e, 0, 1e-6);  // what arrives is exact
}

TEST(RangeAndBearing, NoiseIsReproducibleAndDependsOnTheSeed) {
  auto run = [](uint64_t seed) {
    auto sim = LoadXml(
        Experiment(
            Ring(10),
            Controllers("noise=\"gaussian\" noise_std_dev=\"0.05\" drop_probability=\"0.2\"")),
        {"framework.experiment.random_seed=" + std::to_string(seed)});
    std::vector<float> out;
    for (int t = 0; t < 5; ++t) {
      sim->Step();
      for (const auto& h : Probe(*sim, "r").heard) out.push_back(h.range);
    }
    return out;
  };
  EXPECT_EQ(run(1), run(1));
  EXPECT_NE(run(1), run(2));
}

TEST(RangeAndBearing, SameStateHashWhateverTheThreadCount) {
  // 200 robots, noise, losses and occlusions: packets and their order must not depend on threads.
  const std::string xml = Experiment(
      "<walls thickness=\"0.1\" height=\"0.5\"/>" + Box("b", "0.2,1,0.3", "0,0,0") +
          "<distribute><position method=\"uniform\" min=\"-2.3,-2.3,0\" max=\"2.3,2.3,0\"/>"
          "<orientation method=\"uniform\" min=\"0,0,0\" max=\"360,0,0\"/>"
          "<entity quantity=\"200\" max_trials=\"1000\"><marxbot id=\"mb\"><controller "
          "config=\"both\"/></marxbot>"
          "</entity></distribute>",
      Controllers("noise=\"gaussian\" noise_std_dev=\"0.02\" bearing_noise_std_dev=\"0.05\" "
                  "drop_probability=\"0.1\"",
                  "range=\"1.2\""),
      "5,5,1");
  uint64_t reference = 0;
  for (int threads : {0, 1, 2, 4}) {
    auto sim = LoadXml(xml, {}, threads);
    for (int t = 0; t < 5; ++t) sim->Step();
    size_t heard = 0;
    for (int i = 0; i < 200; ++i) heard += Probe(*sim, "mb" + std::to_string(i)).heard.size();
    EXPECT_GT(heard, 200u);
    if (threads == 0) reference = sim->StateHash();
    EXPECT_EQ(sim->StateHash(), reference) << threads << " threads";
  }
}

// --- bad input

// A three-line experiment: the controller's devices on line 2.
std::string Lines(const std::string& sensor, const std::string& actuator,
                  const std::string& media = "") {
  return "<colony><framework><experiment length=\"1\" ticks_per_second=\"10\" "
         "random_seed=\"1\"/></framework>\n"
         "<controllers><rab_probe id=\"both\"><sensors><range_and_bearing " +
         sensor + "/></sensors><actuators><range_and_bearing " + actuator +
         "/></actuators></rab_probe></controllers>\n" + media +
         "<arena size=\"4,4,1\"><marxbot id=\"r\"><body position=\"0,0,0\"/><controller "
         "config=\"both\"/></marxbot>"
         "</arena><physics_engines><kinematics2d id=\"k\"/></physics_engines></colony>";
}

TEST(RangeAndBearing, BadAttributesAreReportedWithElementAndLine) {
  ExpectMentions(
      LoadError(Lines("", "data_size=\"0\"")),
      {":2: <range_and_bearing> attribute 'data_size'", "'0' is out of range", "[1, 65536]"});
  ExpectMentions(LoadError(Lines("", "range=\"-1\"")),
                 {":2: <range_and_bearing> attribute 'range'", "> 0"});
  ExpectMentions(LoadError(Lines("", "range=\"0\"")),
                 {":2: <range_and_bearing> attribute 'range'", "> 0"});
  ExpectMentions(LoadError(Lines("noise=\"gausian\" noise_std_dev=\"0.1\"", "")),
                 {":2: <range_and_bearing> attribute 'noise'", "did you mean 'gaussian'"});
  ExpectMentions(LoadError(Lines("noise=\"gaussian\"", "")),
                 {":2: <range_and_bearing> attribute 'noise_std_dev'"});
  ExpectMentions(LoadError(Lines("bearing_noise_std_dev=\"-0.1\"", "")),
                 {":2: <range_and_bearing> attribute 'bearing_noise_std_dev'", ">= 0"});
  ExpectMentions(LoadError(Lines("drop_probability=\"2\"", "")),
                 {":2: <range_and_bearing> attribute 'drop_probability'", "[0, 1]"});
  ExpectMentions(LoadError(Lines("rnage=\"1\"", "")),
                 {":2: <range_and_bearing> attribute 'rnage'"});
  // Media: a missing id, a medium of the wrong kind, bad medium attributes (line 3).
  ExpectMentions(LoadError(Lines("medium=\"nope\"", "")),
                 {":2: <range_and_bearing> attribute 'medium'", "no medium with id 'nope'"});
  ExpectMentions(
      LoadError(Lines("", "medium=\"nope\"", "<media><range_and_bearing id=\"rab\"/></media>\n")),
      {":2: <range_and_bearing> attribute 'medium'", "no medium with id 'nope'", "accepted: rab"});
  ExpectMentions(LoadError(Lines("medium=\"leds\"", "", "<media><led id=\"leds\"/></media>\n")),
                 {"medium 'leds' is a <led>, not a <range_and_bearing>"});
  ExpectMentions(
      LoadError(Lines("", "", "<media><range_and_bearing id=\"rab\" range=\"-3\"/></media>\n")),
      {":3: <range_and_bearing id=\"rab\"> attribute 'range'", "> 0"});
  ExpectMentions(
      LoadError(Lines(
          "", "", "<media><range_and_bearing id=\"rab\" check_occlusions=\"maybe\"/></media>\n")),
      {":3: <range_and_bearing id=\"rab\"> attribute 'check_occlusions'"});
  ExpectMentions(
      LoadError(Lines("", "", "<media><range_and_bearing id=\"rab\" cell_size=\"0\"/></media>\n")),
      {":3: <range_and_bearing id=\"rab\"> attribute 'cell_size'"});
  ExpectMentions(
      LoadError(Lines(
          "", "", "<media><range_and_bearing id=\"a\"/><range_and_bearing id=\"b\"/></media>\n")),
      {":2: <range_and_bearing>",
       "several <range_and_bearing> media; say which with medium=\"id\""});
  // Two media and a device naming one: fine.
  EXPECT_EQ(LoadError(Lines(
                "medium=\"b\"", "medium=\"b\"",
                "<media><range_and_bearing id=\"a\"/><range_and_bearing id=\"b\"/></media>\n")),
            "");
}

// --- documentation

TEST(RangeAndBearing, RegisteredAttributesMatchTheReadme) {
  const auto* entry = Registry<SensorSystem>::Get().Find("range_and_bearing");
  ASSERT_NE(entry, nullptr);
  auto names = entry->info.AttributeNames();
  names.push_back("implementation");
  EXPECT_EQ(ReadmeAttributes("sensors/range_and_bearing/README.md", "## XML"), names);
}

}  // namespace
}  // namespace colony
