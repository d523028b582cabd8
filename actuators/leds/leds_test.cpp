// LEDs as a user sees them: colours a controller sets appear on the robot in
// the space (where cameras and renderers look) at the next tick.
#include "actuators/leds/leds.h"

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/registry.h"
#include "tests/test_util.h"

namespace colony {
namespace {

using testing::Experiment;
using testing::LoadError;
using testing::LoadXml;

// Applies whatever the test put in `next` at its next control step.
class LedProbe : public Controller {
 public:
  void Init(const Params& params) override { leds = &GetActuator<Leds>("leds"); }
  void ControlStep() override {
    if (all) leds->SetAllColors(*all);
    for (const auto& [index, color] : single) leds->SetSingleColor(index, color);
    all.reset();
    single.clear();
  }
  Leds* leds = nullptr;
  std::optional<Color> all;
  std::vector<std::pair<size_t, Color>> single;
};

COLONY_REGISTER_CONTROLLER(LedProbe, "led_probe", "test: sets LED colours on demand");

std::string Controllers(const std::string& attributes = "") {
  return "<led_probe id=\"lp\"><actuators><leds " + attributes + "/></actuators></led_probe>";
}

std::string Robot(const std::string& id, const std::string& position) {
  return "<marxbot id=\"" + id + "\"><body position=\"" + position +
         "\"/><controller config=\"lp\"/></marxbot>";
}

LedProbe& Probe(Simulation& sim, const std::string& robot) {
  auto* probe = dynamic_cast<LedProbe*>(sim.ControllerOf(sim.space().Find(robot)));
  EXPECT_NE(probe, nullptr);
  return *probe;
}

std::vector<Color> SpaceLeds(const Simulation& sim, const std::string& robot) {
  auto span = sim.space().leds(sim.space().Find(robot).index);
  return {span.begin(), span.end()};
}

constexpr Color kRed{255, 0, 0, 255};
constexpr Color kBlue{0, 0, 255, 255};
constexpr Color kGreen{0, 255, 0, 255};

TEST(Leds, MarxbotHasThirteenLeds) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers()));
  EXPECT_EQ(Probe(*sim, "r").leds->count(), 13u);  // 12 on the ring + the beacon
  EXPECT_EQ(SpaceLeds(*sim, "r").size(), 13u);
}

TEST(Leds, AllOffAtStartByDefault) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers()));
  sim->Step();
  for (const Color& c : SpaceLeds(*sim, "r")) EXPECT_EQ(c, Color::Black());
}

TEST(Leds, ColorAttributeSetsTheStartingColour) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers("color=\"green\"")));
  for (const Color& c : Probe(*sim, "r").leds->colors()) EXPECT_EQ(c, kGreen);
  // Lit before the first tick (a frame drawn at tick 0 shows them).
  for (const Color& c : SpaceLeds(*sim, "r")) EXPECT_EQ(c, kGreen);
  sim->Step();
  for (const Color& c : SpaceLeds(*sim, "r")) EXPECT_EQ(c, kGreen);
}

TEST(Leds, SetAllColorsShowsInTheSpaceAfterTheNextStep) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0") + Robot("other", "1,0,0"), Controllers()));
  sim->Step();
  Probe(*sim, "r").all = kRed;
  sim->Step();  // the controller sets the colour at the end of this tick...
  for (const Color& c : SpaceLeds(*sim, "r")) EXPECT_EQ(c, Color::Black());
  sim->Step();  // ...and the actuator writes it at the start of the next
  for (const Color& c : SpaceLeds(*sim, "r")) EXPECT_EQ(c, kRed);
  // Only that robot's LEDs.
  for (const Color& c : SpaceLeds(*sim, "other")) EXPECT_EQ(c, Color::Black());
  // Colours stay until changed.
  for (int t = 0; t < 3; ++t) sim->Step();
  for (const Color& c : SpaceLeds(*sim, "r")) EXPECT_EQ(c, kRed);
}

TEST(Leds, SetSingleColorChangesOneLed) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers()));
  Probe(*sim, "r").single = {{0, kRed}, {12, kBlue}};  // front of the ring, beacon
  sim->Step();
  sim->Step();
  const auto leds = SpaceLeds(*sim, "r");
  ASSERT_EQ(leds.size(), 13u);
  EXPECT_EQ(leds[0], kRed);
  EXPECT_EQ(leds[12], kBlue);
  for (size_t i = 1; i < 12; ++i) EXPECT_EQ(leds[i], Color::Black()) << "led " << i;
}

TEST(Leds, OutOfRangeIndexIsIgnored) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers("color=\"blue\"")));
  Probe(*sim, "r").single = {{13, kRed}, {1000, kRed}};
  sim->Step();
  sim->Step();
  for (const Color& c : SpaceLeds(*sim, "r")) EXPECT_EQ(c, kBlue);
}

TEST(Leds, ColoursAreInTheStateHash) {
  auto a = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers()));
  auto b = LoadXml(Experiment(Robot("r", "0,0,0"), Controllers()));
  Probe(*b, "r").all = kRed;
  a->Step();
  b->Step();
  EXPECT_EQ(a->StateHash(), b->StateHash());
  a->Step();
  b->Step();
  EXPECT_NE(a->StateHash(), b->StateHash());
}

TEST(Leds, BadColourIsReported) {
  const std::string message =
      LoadError(Experiment(Robot("r", "0,0,0"), Controllers("color=\"reddish\"")));
  EXPECT_NE(message.find("<leds>"), std::string::npos) << message;
  EXPECT_NE(message.find("attribute 'color'"), std::string::npos) << message;
  EXPECT_NE(message.find("is not a colour"), std::string::npos) << message;
}

}  // namespace
}  // namespace colony
