// The LED medium's index: every lit LED (and landmark, and visible pocket)
// where it really is, and a grid whose cells hold everything a camera may
// see.
#include "media/led/led_medium.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "actuators/leds/leds.h"
#include "core/registry.h"
#include "entities/objects/pocket.h"
#include "media/test_util.h"

namespace colony {
namespace {

using testing::ExpectMentions;
using testing::Experiment;
using testing::LoadError;
using testing::LoadXml;
using testing::ReadmeAttributes;

// Does nothing; with param only_led="k" it lights LED k alone.
class LedIdle : public Controller {
 public:
  void Init(const Params& params) override {
    const int64_t only = params.GetInt("only_led", -1);
    if (only < 0) return;
    Leds& leds = GetActuator<Leds>("leds");
    const Color c = leds.colors()[0];
    leds.SetAllColors(Color::Black());
    leds.SetSingleColor(static_cast<size_t>(only), c);
  }
  void ControlStep() override {}
};

COLONY_REGISTER_CONTROLLER(LedIdle, "led_idle", "test: sets LEDs once");

LedMedium* LedIndex(Simulation& sim) {
  for (const auto& m : sim.media()) {
    if (m->label() == "led") return dynamic_cast<LedMedium*>(m.get());
  }
  return nullptr;
}

std::string Robot(const std::string& id, const std::string& position, double yaw,
                  const std::string& config) {
  return "<marxbot id=\"" + id + "\"><body position=\"" + position + "\" orientation=\"" +
         std::to_string(yaw) + ",0,0\"/><controller config=\"" + config + "\"/></marxbot>";
}

const std::string kControllers =
    "<led_idle id=\"red\"><actuators><leds color=\"red\"/></actuators></led_idle>"
    "<led_idle id=\"dark\"/>"
    "<led_idle id=\"one\"><actuators><leds color=\"blue\"/></actuators><params "
    "only_led=\"4\"/></led_idle>";

const std::string kMedia = "<media><led id=\"leds\"/></media>";

bool Near(const LedMedium::Led& l, const Vec3& p) {
  return (Vec3(l.x, l.y, l.z) - p).norm() < 1e-12;
}

TEST(LedMedium, IndexesEveryLitLedInTheWorldFrame) {
  auto sim = LoadXml(
      Experiment(Robot("a", "1,0.5,0", 30, "red") + Robot("b", "-1,0.5,0", 0, "dark") +
                     "<light id=\"sun\" position=\"0,0,0.5\" color=\"yellow\"/>"
                     "<landmark id=\"post\" height=\"0.4\" color=\"cyan\"><body "
                     "position=\"-1,-1,0\"/></landmark>"
                     "<box id=\"box\" size=\"0.2,0.2,0.2\"><body position=\"1,-1,0\"/></box>",
                 kControllers, "4,4,1", kMedia));
  sim->Step();
  const LedMedium* medium = LedIndex(*sim);
  ASSERT_NE(medium, nullptr);
  EXPECT_EQ(medium->id(), "leds");
  const auto& leds = medium->leds();
  ASSERT_EQ(leds.size(), 13u + 1u + 1u);  // a's ring and beacon, the light, the landmark
  const uint32_t a = sim->space().Find("a").index;
  // a's ring: 12 LEDs 30 degrees apart, 7.5 cm from its axis, 13 cm up, turned with the robot.
  for (int i = 0; i < 12; ++i) {
    const double angle = DegToRad(30.0 + 30.0 * i);
    const Vec3 expected(1 + 0.075 * std::cos(angle), 0.5 + 0.075 * std::sin(angle), 0.13);
    const auto found = std::count_if(leds.begin(), leds.end(), [&](const LedMedium::Led& l) {
      return l.owner == a && Near(l, expected) && l.color == Color{255, 0, 0, 255};
    });
    EXPECT_EQ(found, 1) << "ring LED " << i;
  }
  // Beacon on top of the axis.
  EXPECT_EQ(
      std::count_if(leds.begin(), leds.end(),
                    [&](const auto& l) { return l.owner == a && Near(l, Vec3(1, 0.5, 0.147)); }),
      1);
  // The light where it is, in its colour; the landmark at half its height.
  EXPECT_EQ(std::count_if(leds.begin(), leds.end(),
                          [&](const auto& l) {
                            return Near(l, Vec3(0, 0, 0.5)) && l.color == Color{255, 255, 0, 255};
                          }),
            1);
  EXPECT_EQ(std::count_if(leds.begin(), leds.end(),
                          [&](const auto& l) {
                            return Near(l, Vec3(-1, -1, 0.2)) && l.color == Color{0, 255, 255, 255};
                          }),
            1);
}

// A pocket is one red point owned by it on its top: at the top's centre when
// bare, at the centre of its uncovered part when partly covered; none when
// covered beyond its threshold or held.
TEST(LedMedium, IndexesVisiblePocketsOnTheirUncoveredTop) {
  auto pocket = [](const std::string& id, const std::string& position) {
    return "<pocket id=\"" + id + "\"><body position=\"" + position + "\"/></pocket>";
  };
  auto sim = LoadXml(Experiment(pocket("low", "1,1,0") + pocket("half", "1.06,1,0.05") +
                                    pocket("bare", "-1,1,0") + pocket("held", "-1,-1,0"),
                                kControllers, "4,4,1", kMedia));
  Space& space = sim->space();
  const uint32_t held = space.Find("held").index;
  space.Get<PocketState>(held)->holder = 0;
  sim->Step();
  const auto& leds = LedIndex(*sim)->leds();
  const Color red{255, 0, 0, 255};
  auto at = [&](const std::string& id, const Vec3& p) {
    const uint32_t owner = space.Find(id).index;
    return std::count_if(leds.begin(), leds.end(), [&](const LedMedium::Led& l) {
      return l.owner == owner && Near(l, p) && l.color == red;
    });
  };
  ASSERT_EQ(leds.size(), 3u);
  EXPECT_EQ(at("bare", Vec3(-1, 1, 0.015)), 1);
  EXPECT_EQ(at("half", Vec3(1.06, 1, 0.03)), 1);  // settled on "low"
  EXPECT_EQ(at("low", Vec3(0.97, 1, 0.015)), 1);  // its bare half's centre
  // Covered entirely: gone.
  space.pose(space.Find("half").index).position = Vec3(1, 1, 0.1);
  SettlePocket(space, space.Find("half").index);
  sim->Step();
  EXPECT_EQ(LedIndex(*sim)->leds().size(), 2u);
}

TEST(LedMedium, OnlyLitLedsAreIndexedAndTheyFollowTheRobot) {
  auto sim = LoadXml(Experiment(Robot("a", "0,0,0", 90, "one"), kControllers, "4,4,1", kMedia));
  sim->Step();
  const auto& leds = LedIndex(*sim)->leds();
  ASSERT_EQ(leds.size(), 1u);
  // LED 4 is 120 degrees left of the front; the robot faces +y: 210 degrees in the world.
  EXPECT_TRUE(
      Near(leds[0], Vec3(0.075 * std::cos(DegToRad(210)), 0.075 * std::sin(DegToRad(210)), 0.13)));
  EXPECT_EQ(leds[0].color, (Color{0, 0, 255, 255}));
  sim->RemoveEntity(sim->space().Find("a"));
  sim->Step();
  EXPECT_TRUE(LedIndex(*sim)->leds().empty());
}

TEST(LedMedium, CandidateRunsHoldEverythingWithinReach) {
  // 400 landmarks at random; for random query points, every landmark within
  // reach must be in a run, and runs must not repeat an index.
  std::mt19937 gen(5);
  std::uniform_real_distribution<double> coordinate(-4.9, 4.9);
  std::string arena;
  for (int i = 0; i < 400; ++i) {
    arena += "<landmark id=\"l" + std::to_string(i) + "\"><body position=\"" +
             std::to_string(coordinate(gen)) + "," + std::to_string(coordinate(gen)) +
             ",0\"/></landmark>";
  }
  for (const std::string media :
       {"<media><led id=\"m\"/></media>", "<media><led id=\"m\" cell_size=\"0.3\"/></media>",
        "<media><led id=\"m\" cell_size=\"7\"/></media>"}) {
    auto sim = LoadXml(Experiment(arena, "", "10,10,1", media));
    sim->Step();
    const LedMedium& medium = *LedIndex(*sim);
    ASSERT_EQ(medium.leds().size(), 400u);
    for (int q = 0; q < 200; ++q) {
      const double x = coordinate(gen) * 1.1, y = coordinate(gen) * 1.1,
                   reach = 0.2 + 2.0 * (q % 5) / 4;
      std::vector<uint32_t> seen;
      medium.ForEachCandidateRun(x, y, reach, [&](uint32_t b, uint32_t e) {
        for (uint32_t i = b; i < e; ++i) seen.push_back(i);
      });
      std::sort(seen.begin(), seen.end());
      EXPECT_EQ(std::adjacent_find(seen.begin(), seen.end()), seen.end());
      for (uint32_t i = 0; i < medium.leds().size(); ++i) {
        const auto& l = medium.leds()[i];
        if (std::hypot(l.x - x, l.y - y) > reach) continue;
        EXPECT_TRUE(std::binary_search(seen.begin(), seen.end(), i)) << media << " query " << q;
      }
    }
  }
}

TEST(LedMedium, CellsFollowTheLargestCameraRangeOrTheAttribute) {
  const std::string robot = Robot("a", "0,0,0", 0, "eyes");
  const std::string two_cameras =
      "<led_idle id=\"eyes\"><sensors><omnidirectional_camera range=\"0.7\"/></sensors></led_idle>"
      "<led_idle id=\"far\"><sensors><omnidirectional_camera range=\"2.5\"/></sensors></led_idle>";
  auto sim = LoadXml(Experiment(robot, two_cameras));
  sim->Step();
  ASSERT_EQ(sim->media().size(), 1u);  // none declared: one with default settings, shared
  EXPECT_EQ(sim->media()[0]->id(), "led");
  EXPECT_DOUBLE_EQ(LedIndex(*sim)->cell_size(), 2.5);
  auto set = LoadXml(
      Experiment(robot, two_cameras, "4,4,1", "<media><led id=\"m\" cell_size=\"0.4\"/></media>"));
  set->Step();
  EXPECT_DOUBLE_EQ(LedIndex(*set)->cell_size(), 0.4);
}

TEST(LedMedium, BadMediaAreReported) {
  ExpectMentions(LoadError(Experiment("", "", "4,4,1", "<media><ledd id=\"m\"/></media>")),
                 {"did you mean 'led'"});
  ExpectMentions(
      LoadError(Experiment("", "", "4,4,1", "<media><led id=\"m\" cellsize=\"1\"/></media>")),
      {"<led id=\"m\"> attribute 'cellsize'", "did you mean 'cell_size'"});
  ExpectMentions(
      LoadError(Experiment("", "", "4,4,1",
                           "<media><led id=\"m\"/><range_and_bearing id=\"m\"/></media>")),
      {"duplicate medium id 'm'"});
}

TEST(LedMedium, RegisteredAttributesMatchTheReadme) {
  const auto* entry = Registry<colony::Medium>::Get().Find("led");
  ASSERT_NE(entry, nullptr);
  auto names = entry->info.AttributeNames();
  names.insert(names.begin(), "id");
  EXPECT_EQ(ReadmeAttributes("media/led/README.md", "## XML"), names);
}

}  // namespace
}  // namespace colony
