// What `colony query` tells a controller's author: for a sensor or actuator,
// the header to include, the class to ask for and what it reads or calls;
// for a controller, the <params> it declares. And what keeps the declarations
// true: every device has one that names a real header, class and members,
// and a controller that declares its parameters cannot read another one or
// read one with another default.
#include <regex>
#include <string>

#include "core/plugin_loader.h"
#include "core/registry.h"
#include "tests/test_util.h"

namespace colony::testing {
namespace {

// Passes when `text` holds `part`.
::testing::AssertionResult Shows(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "no \"" << part << "\" in:\n" << text;
}

CommandResult Colony(const std::string& args) {
  return RunCommand(std::string(COLONY_EXE) + " " + args);
}

TEST(Query, ShowsTheHeaderClassAndReadingsOfASensor) {
  const CommandResult r = Colony("query proximity");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(Shows(r.output, "header: #include \"sensors/proximity/proximity.h\""));
  EXPECT_TRUE(Shows(r.output,
                    "class: colony::ProximitySensor, from "
                    "GetSensor<colony::ProximitySensor>(\"proximity\")"));
  EXPECT_TRUE(Shows(r.output, "a controller reads:\n        readings(): one Reading per sensor"));
  EXPECT_TRUE(Shows(r.output, "value (0 nothing in range .. 1 touching), angle (rad"));
  // The XML attributes still follow.
  EXPECT_TRUE(Shows(r.output, "XML attributes:\n      range = a number > 0 (m)"));
}

TEST(Query, ShowsWhatAControllerCallsOnAnActuator) {
  const CommandResult r = Colony("query differential_steering");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(Shows(
      r.output, "header: #include \"actuators/differential_steering/differential_steering.h\""));
  EXPECT_TRUE(Shows(r.output, "GetActuator<colony::DifferentialSteering>"));
  EXPECT_TRUE(Shows(r.output, "a controller calls:\n        SetLinearVelocity(left, right)"));
}

TEST(Query, ListsAControllersParametersWithTheirDefaults) {
  const CommandResult r = Colony("query diffusion");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(Shows(r.output, "parameters (<params> attributes):\n"));
  EXPECT_TRUE(Shows(r.output, "velocity = a number in [0, 10] (m/s)  [default: 0.05]"));
  EXPECT_TRUE(Shows(r.output, "alpha = a number in [0, 180] (degrees)  [default: 7.5]"));
  EXPECT_TRUE(Shows(r.output, "delta = a number >= 0  [default: 0.1]"));
}

// The member a description starts with: "readings(): ..." -> "readings".
std::string LeadingName(const std::string& member) {
  const size_t end = member.find_first_of("(:, ");
  return member.substr(0, end);
}

TEST(Query, EverySensorAndActuatorNamesItsHeaderClassAndMembers) {
  int devices = 0;
  for (const PluginInfo* p : AllPlugins()) {
    if (p->kind != PluginKind::kSensor && p->kind != PluginKind::kActuator) continue;
    ++devices;
    const std::string what = std::string(PluginKindName(p->kind)) + " " + p->label;
    const DeviceInterface& device = p->control_interface;
    ASSERT_FALSE(device.header.empty()) << what << " does not name its header";
    ASSERT_FALSE(device.members.empty()) << what << " does not say what a controller reads";
    ASSERT_EQ(device.cpp_class.rfind("colony::", 0), 0u) << what << ": " << device.cpp_class;
    // The header is the device's own control interface, and declares the class
    // and every member named.
    EXPECT_EQ(device.header.rfind(
                  std::string(p->kind == PluginKind::kSensor ? "sensors/" : "actuators/") +
                      p->label + "/",
                  0),
              0u)
        << what << ": " << device.header;
    const std::string header = ReadFile(std::string(COLONY_SOURCE_DIR) + "/" + device.header);
    ASSERT_FALSE(header.empty()) << what << ": no file " << device.header;
    const std::string name = device.cpp_class.substr(8);
    EXPECT_TRUE(Shows(header, "class " + name + " : public ")) << what;
    for (const std::string& member : device.members) {
      // "SetSingleColor(index, color), SetAllColors(color): ..." names two.
      const std::regex call(R"(([A-Za-z_]+)\()");
      const std::string head = member.substr(0, member.find(": "));
      int named = 0;
      for (auto it = std::sregex_iterator(head.begin(), head.end(), call);
           it != std::sregex_iterator(); ++it, ++named) {
        EXPECT_TRUE(Shows(header, " " + (*it)[1].str() + "("))
            << what << ": " << (*it)[1] << " is not in " << device.header;
      }
      EXPECT_GT(named, 0) << what << ": '" << member << "' names no member";
      EXPECT_FALSE(LeadingName(member).empty()) << what;
    }
  }
  EXPECT_GE(devices, 20);  // all are linked into this test (fewer without dynamics3d)
}

// The controllers shipped in controllers/ each declare their parameters.
TEST(Query, EveryShippedControllerDeclaresItsParameters) {
  for (const char* label :
       {"diffusion", "fetch", "flocking", "aggregation", "foraging", "construction", "handbot_rope",
        "handbot_climb", "pushpull_footbot", "pushpull_handbot", "eyebot_guide",
        "footbot_follow_spot", "eyebot_waypoints", "pocket_builder"}) {
    const std::string error = LoadPluginLibrary(label, "");
    ASSERT_TRUE(error.empty()) << error;
    const auto* entry = Registry<Controller>::Get().Find(label);
    ASSERT_NE(entry, nullptr) << label;
    EXPECT_FALSE(entry->info.attributes.empty()) << label << " declares no parameter";
    for (const AttributeDoc& a : entry->info.attributes) {
      EXPECT_FALSE(a.accepted.empty()) << label << "." << a.name;
      EXPECT_FALSE(a.summary.empty()) << label << "." << a.name;
    }
  }
}

// Test controllers: one declares what it reads, the others read more or
// with another default.
class Declared : public Controller {
 public:
  void Init(const Params& params) override {
    speed_ = params.GetDouble("speed", 0.1, 0, 1);
    mode_ = params.GetString("mode", "walk");
  }
  void ControlStep() override {}

 private:
  double speed_ = 0;
  std::string mode_;
};
COLONY_REGISTER_CONTROLLER(Declared, "query_test_declared", "test: reads what it declares",
                           {{"speed", "a number in [0, 1] (m/s)", "0.1", "speed"},
                            {"mode", "walk, run", "walk", "gait"}});

class ReadsMore : public Declared {
 public:
  void Init(const Params& params) override {
    Declared::Init(params);
    params.GetDouble("gain", 1);
  }
};
COLONY_REGISTER_CONTROLLER(ReadsMore, "query_test_reads_more", "test: reads 'gain' undeclared",
                           {{"speed", "a number in [0, 1] (m/s)", "0.1", "speed"},
                            {"mode", "walk, run", "walk", "gait"}});

COLONY_REGISTER_CONTROLLER(Declared, "query_test_other_default",
                           "test: declares another default than it reads",
                           {{"speed", "a number in [0, 1] (m/s)", "0.2", "speed"},
                            {"mode", "walk, run", "walk", "gait"}});

std::string WithController(const std::string& label, const std::string& params = "") {
  return Experiment(
      "<marxbot id=\"r\"><body position=\"0,0,0\"/><controller config=\"c\"/>"
      "</marxbot>",
      "<" + label + " id=\"c\"><params " + params + "/></" + label + ">");
}

TEST(DeclaredParams, AControllerReadingWhatItDeclaresLoads) {
  EXPECT_EQ(LoadError(WithController("query_test_declared", "speed=\"0.3\"")), "");
}

TEST(DeclaredParams, ReadingAnUndeclaredParameterIsRefusedNamingTheController) {
  const std::string error = LoadError(WithController("query_test_reads_more"));
  EXPECT_TRUE(Shows(error,
                    "controller 'query_test_reads_more' reads parameter 'gain', which "
                    "it does not declare (COLONY_REGISTER_CONTROLLER); it declares: "
                    "speed, mode"));
}

TEST(DeclaredParams, ADeclaredDefaultThatIsNotTheCodesIsRefused) {
  const std::string error = LoadError(WithController("query_test_other_default"));
  EXPECT_TRUE(Shows(error,
                    "controller 'query_test_other_default' reads parameter 'speed' "
                    "with default 0.1, but declares it with default 0.2"));
}

TEST(DeclaredParams, DefaultsCompareAsNumbersAndListsWithoutSpaces) {
  Params params;
  params.GetDouble("a", 0.1);
  params.GetInt("b", 20);
  params.GetNumbers("c", "25,50,75");
  params.GetBool("d", false);
  EXPECT_THROW(params.GetString("e"), ParamError);  // required, and missing
  const PluginInfo info(PluginKind::kController, "x", "default", "",
                        {{"a", "", "0.10", ""},
                         {"b", "", "2e1", ""},
                         {"c", "", "25, 50, 75", ""},
                         {"d", "", "false", ""},
                         {"e", "", "required when f is g", ""}});
  EXPECT_TRUE(UndeclaredParamReads(info, params).empty());
  const PluginInfo wrong(PluginKind::kController, "x", "default", "",
                         {{"a", "", "0.2", ""},
                          {"b", "", "20", ""},
                          {"c", "", "25,50", ""},
                          {"d", "", "true", ""},
                          {"e", "", "1", ""}});
  EXPECT_EQ(UndeclaredParamReads(wrong, params).size(), 4u);
}

}  // namespace
}  // namespace colony::testing
