// The range-and-bearing emitter as a controller uses it: the payload size
// from XML, what SetData/SetByte/Clear send, and the range it reaches.
#include "actuators/range_and_bearing/range_and_bearing.h"

#include <string>
#include <vector>

#include "core/registry.h"
#include "media/test_util.h"
#include "sensors/range_and_bearing/range_and_bearing.h"

namespace colony {
namespace {

using testing::ExpectMentions;
using testing::Experiment;
using testing::LoadError;
using testing::LoadXml;
using testing::ReadmeAttributes;

// The sender runs a script of actuator calls, one per control step (param
// "script": a letter per step: d = SetData("hello"), b = SetByte(1, 'X'),
// B = SetByte(99, 'X') (beyond the size), c = Clear, - = nothing). The
// receiver copies the payloads it hears.
class RabScript : public Controller {
 public:
  void Init(const Params& params) override {
    script_ = params.GetString("script", "");
    try {
      actuator_ = &GetActuator<RangeAndBearingActuator>("range_and_bearing");
      size = actuator_->size();
    } catch (const std::logic_error&) {
    }
    try {
      sensor_ = &GetSensor<RangeAndBearingSensor>("range_and_bearing");
    } catch (const std::logic_error&) {
    }
  }
  void ControlStep() override {
    heard.clear();
    if (sensor_) {
      for (const auto& p : sensor_->packets()) heard.emplace_back(p.data.begin(), p.data.end());
    }
    if (!actuator_ || step_ >= script_.size()) return;
    static const uint8_t kHello[] = {'h', 'e', 'l', 'l', 'o'};
    switch (script_[step_++]) {
      case 'd':
        actuator_->SetData(kHello);
        break;
      case 'b':
        actuator_->SetByte(1, 'X');
        break;
      case 'B':
        actuator_->SetByte(99, 'X');
        break;
      case 'c':
        actuator_->Clear();
        break;
      default:
        break;
    }
  }
  std::vector<std::vector<uint8_t>> heard;
  size_t size = 0;

 private:
  std::string script_;
  size_t step_ = 0;
  RangeAndBearingActuator* actuator_ = nullptr;
  const RangeAndBearingSensor* sensor_ = nullptr;
};

COLONY_REGISTER_CONTROLLER(RabScript, "rab_script",
                           "test: scripted range-and-bearing emitter and receiver");

std::string Scene(const std::string& actuator, const std::string& script, double distance = 1.0) {
  return Experiment(
      "<marxbot id=\"tx\"><body position=\"0,0,0\"/><controller config=\"tx\"/></marxbot>"
      "<marxbot id=\"rx\"><body position=\"" +
          std::to_string(distance) + ",0,0\"/><controller config=\"rx\"/></marxbot>",
      "<rab_script id=\"tx\"><actuators><range_and_bearing " + actuator +
          "/></actuators><params script=\"" + script +
          "\"/></rab_script>"
          "<rab_script id=\"rx\"><sensors><range_and_bearing/></sensors></rab_script>",
      "8,8,1");
}

RabScript& Probe(Simulation& sim, const std::string& robot) {
  return *dynamic_cast<RabScript*>(sim.ControllerOf(sim.space().Find(robot)));
}

std::vector<uint8_t> Bytes(const std::string& s) { return {s.begin(), s.end()}; }

TEST(RangeAndBearingActuator, PayloadSizeComesFromXml) {
  auto sim = LoadXml(Scene("", ""));
  EXPECT_EQ(Probe(*sim, "tx").size, 10u);  // default
  sim->Step();
  ASSERT_EQ(Probe(*sim, "rx").heard.size(), 1u);
  // Before anything is set, a robot sends zeros.
  EXPECT_EQ(Probe(*sim, "rx").heard[0], std::vector<uint8_t>(10, 0));
  auto three = LoadXml(Scene("data_size=\"3\"", ""));
  EXPECT_EQ(Probe(*three, "tx").size, 3u);
  three->Step();
  EXPECT_EQ(Probe(*three, "rx").heard[0].size(), 3u);
}

TEST(RangeAndBearingActuator, SetDataSetByteAndClear) {
  // Step k's call is heard at tick k + 1.
  auto sim = LoadXml(Scene("data_size=\"6\"", "dbBc-d"));
  std::vector<std::vector<std::vector<uint8_t>>> ticks;
  for (int t = 0; t < 7; ++t) {
    sim->Step();
    ticks.push_back(Probe(*sim, "rx").heard);
  }
  using V = std::vector<std::vector<uint8_t>>;
  EXPECT_EQ(ticks[0], V{std::vector<uint8_t>(6, 0)});
  EXPECT_EQ(ticks[1], V{Bytes(std::string("hello\0", 6))});  // the rest zeroed
  EXPECT_EQ(ticks[2], V{Bytes(std::string("hXllo\0", 6))});
  EXPECT_EQ(ticks[3], V{Bytes(std::string("hXllo\0", 6))});  // index beyond the size: ignored
  EXPECT_EQ(ticks[4], V{});                                  // cleared: silent
  EXPECT_EQ(ticks[5], V{});                                  // stays silent
  EXPECT_EQ(ticks[6], V{Bytes(std::string("hello\0", 6))});  // sending again
}

TEST(RangeAndBearingActuator, LongerDataIsCutToTheSize) {
  auto sim = LoadXml(Scene("data_size=\"2\"", "d"));
  sim->Step();
  sim->Step();
  EXPECT_EQ(Probe(*sim, "rx").heard, (std::vector<std::vector<uint8_t>>{Bytes("he")}));
}

TEST(RangeAndBearingActuator, RangeAttribute) {
  for (const auto& [range, distance, heard] :
       std::vector<std::tuple<std::string, double, bool>>{{"range=\"2\"", 1.999, true},
                                                          {"range=\"2\"", 2.001, false},
                                                          {"range=\"0.5\"", 0.499, true},
                                                          {"range=\"0.5\"", 0.501, false},
                                                          {"", 2.999, true},
                                                          {"", 3.001, false}}) {
    auto sim = LoadXml(Scene(range, "", distance));
    sim->Step();
    EXPECT_EQ(Probe(*sim, "rx").heard.size(), heard ? 1u : 0u) << range << " at " << distance;
  }
}

TEST(RangeAndBearingActuator, BadAttributesAreReported) {
  const std::string zero = LoadError(Scene("data_size=\"0\"", ""));
  EXPECT_NE(zero.find("<range_and_bearing> attribute 'data_size'"), std::string::npos) << zero;
  EXPECT_NE(zero.find("'0' is out of range"), std::string::npos) << zero;
  const std::string half = LoadError(Scene("data_size=\"2.5\"", ""));
  EXPECT_NE(half.find("not a whole number"), std::string::npos) << half;
  const std::string negative = LoadError(Scene("range=\"-1\"", ""));
  EXPECT_NE(negative.find("<range_and_bearing> attribute 'range'"), std::string::npos) << negative;
  EXPECT_NE(negative.find("> 0"), std::string::npos) << negative;
  const std::string medium = LoadError(Scene("medium=\"radio\"", ""));
  EXPECT_NE(medium.find("no medium with id 'radio'"), std::string::npos) << medium;
}

TEST(RangeAndBearingActuator, RegisteredAttributesMatchTheReadme) {
  const auto* entry = Registry<ActuatorSystem>::Get().Find("range_and_bearing");
  ASSERT_NE(entry, nullptr);
  auto names = entry->info.AttributeNames();
  names.push_back("implementation");
  EXPECT_EQ(ReadmeAttributes("actuators/range_and_bearing/README.md", "## XML"), names);
}

}  // namespace
}  // namespace colony
