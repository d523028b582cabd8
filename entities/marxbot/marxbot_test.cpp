// The marXbot (foot-bot) entity: its figures (ROBOTS.md), its devices, its
// XML element and the errors a user gets for a bad one.
#include "entities/marxbot/marxbot.h"

#include <cmath>
#include <string>

#include "core/entity_type.h"
#include "core/registry.h"
#include "tests/test_util.h"

namespace colony {
namespace {

using testing::Experiment;
using testing::LoadError;
using testing::LoadXml;

class MarxbotProbe : public Controller {
 public:
  void ControlStep() override {}
};

COLONY_REGISTER_CONTROLLER(MarxbotProbe, "marxbot_probe", "test: does nothing");

const std::string kController = "<marxbot_probe id=\"mp\"/>";

std::string Robot(const std::string& id, const std::string& position, const std::string& extra = "",
                  const std::string& element = "marxbot") {
  return "<" + element + " id=\"" + id + "\" " + extra + "><body position=\"" + position +
         "\"/><controller config=\"mp\"/></" + element + ">";
}

TEST(Marxbot, BodyFigures) {
  auto sim = LoadXml(Experiment(Robot("r", "0.5,0.25,0"), kController));
  const Space& space = sim->space();
  const uint32_t i = space.Find("r").index;
  const Geometry& g = space.geometry(i);
  EXPECT_EQ(g.shape, ShapeKind::kCylinder);
  EXPECT_DOUBLE_EQ(g.radius, 0.085);    // 17 cm diameter
  EXPECT_DOUBLE_EQ(g.height(), 0.147);  // the base, without the manipulator
  EXPECT_EQ(space.flags(i) & (kSolid | kMovable | kRobot), kSolid | kMovable | kRobot);
  EXPECT_EQ(space.TypeLabel(space.type(i)), "marxbot");
  EXPECT_EQ(space.pose(i).position, Vec3(0.5, 0.25, 0));
  EXPECT_EQ(space.color(i), (Color{60, 60, 60, 255}));
}

TEST(Marxbot, DriveFigures) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0"), kController));
  const DriveState* d = sim->space().drive(sim->space().Find("r").index);
  ASSERT_NE(d, nullptr);
  EXPECT_DOUBLE_EQ(d->wheel_base, 0.14);
  EXPECT_DOUBLE_EQ(d->wheel_radius, 0.029);
  EXPECT_DOUBLE_EQ(d->max_speed, 0.30);
  EXPECT_EQ(d->left, 0.0);
  EXPECT_EQ(d->right, 0.0);
}

TEST(Marxbot, DeviceFigures) {
  auto sim = LoadXml(Experiment(Robot("r", "0,0,0"), kController));
  const DeviceMounts& mounts = sim->MountsOf(sim->space().Find("r"));
  const RingMount* proximity = mounts.Ring("proximity");
  ASSERT_NE(proximity, nullptr);
  EXPECT_EQ(proximity->count, 24);
  EXPECT_DOUBLE_EQ(proximity->elevation, 0.055);
  EXPECT_DOUBLE_EQ(proximity->radius, 0.085);  // on the body's surface
  EXPECT_DOUBLE_EQ(proximity->range, 0.10);
  EXPECT_NEAR(proximity->AngleOf(1) - proximity->AngleOf(0), DegToRad(15), 1e-12);
  EXPECT_NEAR(proximity->AngleOf(0), DegToRad(7.5), 1e-12);
  const RingMount* ground = mounts.Ring("ground");
  ASSERT_NE(ground, nullptr);
  EXPECT_EQ(ground->count, 8);
  EXPECT_NEAR(ground->AngleOf(1) - ground->AngleOf(0), DegToRad(45), 1e-12);
  EXPECT_LT(ground->radius, 0.085);  // under the base
  const RingMount* leds = mounts.Ring("leds");
  ASSERT_NE(leds, nullptr);
  EXPECT_EQ(leds->count, 12);  // on the docking ring
  // 12 ring LEDs + the beacon in the space.
  EXPECT_EQ(sim->space().leds(sim->space().Find("r").index).size(), 13u);
  const RingMount* light = mounts.Ring("light");
  ASSERT_NE(light, nullptr);
  EXPECT_EQ(light->count, 24);
  EXPECT_NEAR(light->AngleOf(0), DegToRad(7.5), 1e-12);
  EXPECT_DOUBLE_EQ(light->elevation, 0.06);
  const RingMount* scanner = mounts.Ring("distance_scanner");
  ASSERT_NE(scanner, nullptr);
  EXPECT_EQ(scanner->count, 4);                // short, long, short, long on the rotor
  EXPECT_DOUBLE_EQ(scanner->elevation, 0.09);  // scan plane 9 cm above the floor
  EXPECT_DOUBLE_EQ(scanner->range, 1.5);
  EXPECT_EQ(mounts.Ring("camera"), nullptr);
}

TEST(Marxbot, HeaderMatchesRobotsMd) {
  EXPECT_DOUBLE_EQ(marxbot::kBodyRadius, 0.085);
  EXPECT_DOUBLE_EQ(marxbot::kWheelBase, 0.14);
  EXPECT_DOUBLE_EQ(marxbot::kWheelRadius, 0.029);
  EXPECT_DOUBLE_EQ(marxbot::kMaxSpeed, 0.30);
  EXPECT_EQ(marxbot::kProximityCount, 24);
  EXPECT_EQ(marxbot::kGroundCount, 8);
  EXPECT_EQ(marxbot::kRingLedCount, 12);
  EXPECT_EQ(marxbot::kLedCount, 13);
}

TEST(Marxbot, FootBotAliasIsAccepted) {
  auto sim =
      LoadXml(Experiment(Robot("fb", "0,0,0", "", "foot-bot") + Robot("mb", "1,0,0"), kController));
  const Space& space = sim->space();
  const uint32_t fb = space.Find("fb").index, mb = space.Find("mb").index;
  EXPECT_EQ(space.type(fb), space.type(mb));  // the same type, not a look-alike
  EXPECT_EQ(space.TypeLabel(space.type(fb)), "marxbot");
  EXPECT_DOUBLE_EQ(space.geometry(fb).radius, 0.085);
  EXPECT_NE(sim->ControllerOf(space.Find("fb")), nullptr);
  EXPECT_EQ(sim->robot_count(), 2u);
}

TEST(Marxbot, FootBotAliasWorksInDistribute) {
  auto sim = LoadXml(
      Experiment("<distribute><position method=\"uniform\" min=\"-1.5,-1.5,0\" max=\"1.5,1.5,0\"/>"
                 "<orientation method=\"uniform\" min=\"0,0,0\" max=\"360,0,0\"/>"
                 "<entity quantity=\"10\"><foot-bot id=\"fb\"><controller "
                 "config=\"mp\"/></foot-bot></entity></distribute>",
                 kController));
  EXPECT_EQ(sim->robot_count(), 10u);
  EXPECT_TRUE(sim->space().Find("fb0").valid());
  EXPECT_TRUE(sim->space().Find("fb9").valid());
}

TEST(Marxbot, ColorAttribute) {
  auto sim = LoadXml(
      Experiment(Robot("r", "0,0,0", "color=\"red\"") + Robot("s", "1,0,0", "color=\"10,20,30\""),
                 kController));
  EXPECT_EQ(sim->space().color(sim->space().Find("r").index), (Color{255, 0, 0, 255}));
  EXPECT_EQ(sim->space().color(sim->space().Find("s").index), (Color{10, 20, 30, 255}));
  const std::string bad =
      LoadError(Experiment(Robot("r", "0,0,0", "color=\"reddish\""), kController));
  EXPECT_NE(bad.find("<marxbot id=\"r\"> attribute 'color'"), std::string::npos) << bad;
  EXPECT_NE(bad.find("is not a colour"), std::string::npos) << bad;
}

TEST(Marxbot, OrientationIsYawPitchRollInDegrees) {
  auto sim =
      LoadXml(Experiment("<marxbot id=\"r\"><body position=\"0,0,0\" "
                         "orientation=\"30,0,0\"/><controller config=\"mp\"/></marxbot>",
                         kController));
  EXPECT_NEAR(YawOf(sim->space().pose(sim->space().Find("r").index).orientation), DegToRad(30),
              1e-12);
}

TEST(Marxbot, MistakesAreReported) {
  // No <controller>.
  const std::string no_controller =
      LoadError(Experiment("<marxbot id=\"r\"><body position=\"0,0,0\"/></marxbot>", kController));
  EXPECT_NE(no_controller.find("missing <controller config=\"ID\"/>"), std::string::npos)
      << no_controller;
  // No <body>.
  const std::string no_body =
      LoadError(Experiment("<marxbot id=\"r\"><controller config=\"mp\"/></marxbot>", kController));
  EXPECT_NE(no_body.find("missing <body"), std::string::npos) << no_body;
  // No id.
  const std::string no_id = LoadError(Experiment(
      "<marxbot><body position=\"0,0,0\"/><controller config=\"mp\"/></marxbot>", kController));
  EXPECT_NE(no_id.find("attribute 'id': required attribute is missing"), std::string::npos)
      << no_id;
  // Unknown controller, with a suggestion.
  const std::string unknown = LoadError(Experiment(
      "<marxbot id=\"r\"><body position=\"0,0,0\"/><controller config=\"pm\"/></marxbot>",
      kController));
  EXPECT_NE(unknown.find("no controller with id 'pm'"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("did you mean 'mp'"), std::string::npos) << unknown;
  // Unknown attribute, with a suggestion.
  const std::string typo =
      LoadError(Experiment(Robot("r", "0,0,0", "colour=\"red\""), kController));
  EXPECT_NE(typo.find("attribute 'colour': unknown attribute (did you mean 'color'?)"),
            std::string::npos)
      << typo;
  // Misspelt element name.
  const std::string element = LoadError(Experiment(Robot("r", "0,0,0", "", "marxbt"), kController));
  EXPECT_NE(element.find("did you mean <marxbot>"), std::string::npos) << element;
  // Duplicate id.
  const std::string duplicate =
      LoadError(Experiment(Robot("r", "0,0,0") + Robot("r", "1,0,0"), kController));
  EXPECT_NE(duplicate.find("duplicate entity id 'r'"), std::string::npos) << duplicate;
  // Bad position.
  const std::string position = LoadError(Experiment(Robot("r", "0,0"), kController));
  EXPECT_NE(position.find("attribute 'position'"), std::string::npos) << position;
  EXPECT_NE(position.find("is not three finite numbers"), std::string::npos) << position;
}

TEST(Marxbot, EveryMistakeIsReportedAtOnce) {
  const std::string message = LoadError(Experiment(
      Robot("a", "0,0,0", "color=\"nope\"") + Robot("b", "1,0,0", "colr=\"red\""), kController));
  EXPECT_NE(message.find("'nope' is not a colour"), std::string::npos) << message;
  EXPECT_NE(message.find("did you mean 'color'"), std::string::npos) << message;
}

TEST(Marxbot, RegisteredAttributesMatchTheReadme) {
  const auto* entry = Registry<EntityType>::Get().Find("marxbot");
  ASSERT_NE(entry, nullptr);
  EXPECT_EQ(entry->info.AttributeNames(), std::vector<std::string>({"color", "manipulator"}));
  EXPECT_EQ(entry->info.aliases, std::vector<std::string>{"foot-bot"});
  EXPECT_EQ(Registry<EntityType>::Get().Find("foot-bot"), entry);
}

}  // namespace
}  // namespace colony
