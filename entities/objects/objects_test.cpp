// Passive things: box, cylinder, light. Their attributes, what they become in
// the space, and the errors a user gets for a bad one.
#include <string>
#include <vector>

#include "core/entity_type.h"
#include "core/registry.h"
#include "tests/test_util.h"

namespace colony {
namespace {

using testing::Experiment;
using testing::LoadError;
using testing::LoadXml;

class ObjectsProbe : public Controller {
 public:
  void ControlStep() override {}
};

COLONY_REGISTER_CONTROLLER(ObjectsProbe, "objects_probe", "test: does nothing");

const std::string kController = "<objects_probe id=\"op\"/>";

std::string Box(const std::string& id, const std::string& attributes,
                const std::string& position = "0,0,0", const std::string& orientation = "0,0,0") {
  return "<box id=\"" + id + "\" " + attributes + "><body position=\"" + position +
         "\" orientation=\"" + orientation + "\"/></box>";
}

std::string Cylinder(const std::string& id, const std::string& attributes,
                     const std::string& position = "0,0,0") {
  return "<cylinder id=\"" + id + "\" " + attributes + "><body position=\"" + position +
         "\"/></cylinder>";
}

std::string Robot(const std::string& id, const std::string& position) {
  return "<marxbot id=\"" + id + "\"><body position=\"" + position +
         "\"/><controller config=\"op\"/></marxbot>";
}

std::string Error(const std::string& arena) { return LoadError(Experiment(arena, kController)); }

void ExpectMentions(const std::string& message, const std::vector<std::string>& parts) {
  EXPECT_FALSE(message.empty()) << "expected an error";
  for (const auto& p : parts)
    EXPECT_NE(message.find(p), std::string::npos) << "'" << p << "' not in: " << message;
}

// --- box

TEST(Box, SizePoseAndDefaults) {
  auto sim =
      LoadXml(Experiment(Box("b", "size=\"0.4,0.2,0.3\"", "0.5,-0.5,0", "30,0,0"), kController));
  const Space& space = sim->space();
  const uint32_t i = space.Find("b").index;
  EXPECT_EQ(space.geometry(i).shape, ShapeKind::kBox);
  EXPECT_EQ(space.geometry(i).size, Vec3(0.4, 0.2, 0.3));
  EXPECT_EQ(space.pose(i).position, Vec3(0.5, -0.5, 0));
  EXPECT_NEAR(YawOf(space.pose(i).orientation), DegToRad(30), 1e-12);
  // Not movable, solid, grey, no LEDs, no drive by default.
  EXPECT_EQ(space.flags(i) & (kSolid | kMovable | kRobot), kSolid);
  EXPECT_EQ(space.color(i), (Color{128, 128, 128, 255}));
  EXPECT_TRUE(space.leds(i).empty());
  EXPECT_EQ(space.drive(i), nullptr);
  EXPECT_EQ(space.TypeLabel(space.type(i)), "box");
}

TEST(Box, MovableAndColour) {
  auto sim = LoadXml(
      Experiment(Box("b", "size=\"0.2,0.2,0.2\" movable=\"true\" mass=\"2.5\" color=\"blue\"") +
                     Box("c", "size=\"0.2,0.2,0.2\" movable=\"false\" color=\"gray70\"", "1,0,0"),
                 kController));
  const Space& space = sim->space();
  const uint32_t b = space.Find("b").index, c = space.Find("c").index;
  EXPECT_TRUE(space.movable(b));
  EXPECT_EQ(space.color(b), (Color{0, 0, 255, 255}));
  EXPECT_FALSE(space.movable(c));
  EXPECT_EQ(space.color(c), (Color{178, 178, 178, 255}));
}

TEST(Box, SizeErrors) {
  ExpectMentions(Error(Box("b", "")),
                 {"<box id=\"b\">", "attribute 'size'", "required attribute is missing"});
  ExpectMentions(Error(Box("b", "size=\"0.5,-0.1,0.2\"")),
                 {"attribute 'size'", "'0.5,-0.1,0.2' is out of range", "accepted: a number > 0"});
  ExpectMentions(Error(Box("b", "size=\"0.5,0,0.2\"")), {"attribute 'size'", "out of range"});
  ExpectMentions(Error(Box("b", "size=\"0.5,0.2\"")),
                 {"attribute 'size'", "is not three finite numbers"});
  ExpectMentions(Error(Box("b", "size=\"a,b,c\"")),
                 {"attribute 'size'", "is not three finite numbers"});
  ExpectMentions(Error(Box("b", "size=\"1,1,nan\"")),
                 {"attribute 'size'", "is not three finite numbers"});
}

TEST(Box, MassAndMovableErrors) {
  ExpectMentions(Error(Box("b", "size=\"0.2,0.2,0.2\" movable=\"true\" mass=\"0\"")),
                 {"attribute 'mass'", "a movable object needs a mass > 0"});
  ExpectMentions(Error(Box("b", "size=\"0.2,0.2,0.2\" mass=\"-1\"")),
                 {"attribute 'mass'", "'-1' is out of range", ">= 0"});
  ExpectMentions(Error(Box("b", "size=\"0.2,0.2,0.2\" movable=\"yes\"")),
                 {"attribute 'movable'", "'yes' is not a boolean; accepted: true, false"});
  ExpectMentions(Error(Box("b", "size=\"0.2,0.2,0.2\" color=\"pink\"")),
                 {"attribute 'color'", "is not a colour"});
}

TEST(Box, UnknownAttributeAndChildAreReported) {
  ExpectMentions(Error(Box("b", "size=\"0.2,0.2,0.2\" moveable=\"true\"")),
                 {"attribute 'moveable'", "unknown attribute", "did you mean 'movable'"});
  ExpectMentions(Error("<box id=\"b\" size=\"0.2,0.2,0.2\"><body position=\"0,0,0\"/><controller "
                       "config=\"op\"/></box>"),
                 {"unknown element inside <box>"});
  ExpectMentions(Error("<box id=\"b\" size=\"0.2,0.2,0.2\"/>"),
                 {"<box id=\"b\">", "missing <body"});
}

TEST(Box, PlacementErrors) {
  ExpectMentions(Error(Box("b", "size=\"1,1,0.2\"", "1.8,0,0")),
                 {"entity 'b' is outside the arena"});
  ExpectMentions(Error(Box("b", "size=\"0.2,0.2,2\"")),
                 {"entity 'b' is outside the arena"});  // taller than the arena
  // Fixed boxes may touch and cross each other (walls meet at corners)...
  EXPECT_EQ(Error(Box("a", "size=\"1,0.1,0.2\"") + Box("b", "size=\"0.1,1,0.2\"")), "");
  // ...movable ones must start clear.
  ExpectMentions(
      Error(Box("a", "size=\"1,0.1,0.2\"") + Box("b", "size=\"0.1,1,0.2\" movable=\"true\"")),
      {"entity 'b' overlaps 'a'"});
}

TEST(Box, CannotBePlacedOnARobotWhateverTheOrder) {
  // A robot inside a box is rejected when the box comes first...
  ExpectMentions(Error(Box("b", "size=\"0.4,0.4,0.2\"") + Robot("r", "0,0,0")),
                 {"entity 'r' overlaps 'b'"});
  // ...and should be when the robot comes first. Exposes the loader checking
  // overlaps only for movable entities (core/loader.cpp, CheckPlacement).
  const std::string message = Error(Robot("r", "0,0,0") + Box("b", "size=\"0.4,0.4,0.2\""));
  EXPECT_NE(message.find("overlaps"), std::string::npos)
      << "a robot was placed inside a box: '" << message << "'";
}

TEST(Box, RotatedFootprintIsUsedForPlacement) {
  // A 1 m x 0.1 m bar turned 90 degrees lies along y: a robot at (0.3, 0)
  // is clear of it, one at (0, 0.3) is not.
  const std::string bar = Box("bar", "size=\"1,0.1,0.2\"", "0,0,0", "90,0,0");
  EXPECT_EQ(Error(bar + Robot("r", "0.3,0,0")), "");
  ExpectMentions(Error(bar + Robot("r", "0,0.3,0")), {"entity 'r' overlaps 'bar'"});
}

// --- cylinder

TEST(Cylinder, RadiusHeightAndDefaults) {
  auto sim =
      LoadXml(Experiment(Cylinder("c", "radius=\"0.15\" height=\"0.4\"", "-1,1,0"), kController));
  const Space& space = sim->space();
  const uint32_t i = space.Find("c").index;
  EXPECT_EQ(space.geometry(i).shape, ShapeKind::kCylinder);
  EXPECT_DOUBLE_EQ(space.geometry(i).radius, 0.15);
  EXPECT_DOUBLE_EQ(space.geometry(i).height(), 0.4);
  EXPECT_EQ(space.pose(i).position, Vec3(-1, 1, 0));
  EXPECT_EQ(space.flags(i) & (kSolid | kMovable), kSolid);
  EXPECT_EQ(space.color(i), (Color{179, 179, 179, 255}));
}

TEST(Cylinder, MovableWithDefaultMass) {
  auto sim = LoadXml(
      Experiment(Cylinder("c", "radius=\"0.1\" height=\"0.2\" movable=\"true\""), kController));
  EXPECT_TRUE(sim->space().movable(sim->space().Find("c").index));
}

TEST(Cylinder, Errors) {
  ExpectMentions(Error(Cylinder("c", "height=\"0.2\"")),
                 {"attribute 'radius'", "required attribute is missing"});
  ExpectMentions(Error(Cylinder("c", "radius=\"0.1\"")),
                 {"attribute 'height'", "required attribute is missing"});
  ExpectMentions(Error(Cylinder("c", "radius=\"-0.1\" height=\"0.2\"")),
                 {"attribute 'radius'", "'-0.1' is out of range", "accepted: a number > 0"});
  ExpectMentions(Error(Cylinder("c", "radius=\"0.1\" height=\"0\"")),
                 {"attribute 'height'", "out of range"});
  ExpectMentions(Error(Cylinder("c", "radius=\"big\" height=\"0.2\"")),
                 {"attribute 'radius'", "is not a finite number"});
  ExpectMentions(Error(Cylinder("c", "radius=\"0.1\" height=\"0.2\" movable=\"true\" mass=\"0\"")),
                 {"attribute 'mass'", "mass > 0"});
  ExpectMentions(Error(Cylinder("c", "radius=\"0.1\" height=\"0.2\" size=\"1,1,1\"")),
                 {"attribute 'size'", "unknown attribute"});
  // Both missing: both reported at once.
  ExpectMentions(Error(Cylinder("c", "")), {"attribute 'radius'", "attribute 'height'"});
}

// --- light

TEST(Light, PositionColourIntensity) {
  auto sim = LoadXml(
      Experiment("<light id=\"l\" position=\"0.5,0.5,0.8\" color=\"orange\" intensity=\"2.5\"/>",
                 kController));
  const Space& space = sim->space();
  const uint32_t i = space.Find("l").index;
  EXPECT_EQ(space.pose(i).position, Vec3(0.5, 0.5, 0.8));
  ASSERT_NE(space.light(i), nullptr);
  EXPECT_DOUBLE_EQ(space.light(i)->intensity, 2.5);
  EXPECT_EQ(space.color(i), (Color{255, 140, 0, 255}));
  // It shines in its own colour, for cameras and renderers.
  ASSERT_EQ(space.leds(i).size(), 1u);
  EXPECT_EQ(space.leds(i)[0], (Color{255, 140, 0, 255}));
  // Not solid: nothing collides with it.
  EXPECT_EQ(space.flags(i) & (kSolid | kMovable), 0);
  EXPECT_EQ(space.geometry(i).shape, ShapeKind::kNone);
}

TEST(Light, Defaults) {
  auto sim = LoadXml(Experiment("<light id=\"l\" position=\"0,0,0.5\"/>", kController));
  const uint32_t i = sim->space().Find("l").index;
  EXPECT_DOUBLE_EQ(sim->space().light(i)->intensity, 1.0);
  EXPECT_EQ(sim->space().color(i), (Color{255, 255, 0, 255}));  // yellow
}

TEST(Light, MayShareItsPlaceWithARobot) {
  EXPECT_EQ(Error("<light id=\"l\" position=\"0,0,0.06\"/>" + Robot("r", "0,0,0")), "");
  EXPECT_EQ(Error(Robot("r", "0,0,0") + "<light id=\"l\" position=\"0,0,0.06\"/>"), "");
}

TEST(Light, ArgosMediumAttributeIsAccepted) {
  EXPECT_EQ(Error("<light id=\"l\" position=\"0,0,0.5\" medium=\"leds\"/>"), "");
}

TEST(Light, Errors) {
  ExpectMentions(Error("<light id=\"l\"/>"),
                 {"<light id=\"l\">", "attribute 'position'", "required attribute is missing"});
  ExpectMentions(Error("<light id=\"l\" position=\"0,0,0.5\" intensity=\"0\"/>"),
                 {"attribute 'intensity'", "'0' is out of range", "> 0"});
  ExpectMentions(Error("<light id=\"l\" position=\"0,0,0.5\" intensity=\"-3\"/>"),
                 {"attribute 'intensity'"});
  ExpectMentions(Error("<light id=\"l\" position=\"0,0,0.5\" color=\"bright\"/>"),
                 {"attribute 'color'", "is not a colour"});
  // A light takes its position as an attribute, not a <body>.
  ExpectMentions(Error("<light id=\"l\" position=\"0,0,0.5\"><body position=\"0,0,0\"/></light>"),
                 {"unknown element inside <light>"});
  ExpectMentions(Error("<light id=\"l\" position=\"0,0,0.5\" size=\"1,1,1\"/>"),
                 {"attribute 'size'", "unknown attribute"});
}

// --- registered attributes (what `colony query` and the README list)

std::vector<std::string> AttributesOf(const std::string& label) {
  const auto* entry = Registry<EntityType>::Get().Find(label);
  return entry ? entry->info.AttributeNames() : std::vector<std::string>{"<not registered>"};
}

TEST(Objects, RegisteredAttributesMatchTheReadme) {
  EXPECT_EQ(AttributesOf("box"), (std::vector<std::string>{"size", "movable", "mass", "color"}));
  EXPECT_EQ(AttributesOf("cylinder"),
            (std::vector<std::string>{"radius", "height", "movable", "mass", "color"}));
  EXPECT_EQ(AttributesOf("cube"), (std::vector<std::string>{"size", "mass", "color"}));
  EXPECT_EQ(AttributesOf("light"),
            (std::vector<std::string>{"position", "orientation", "color", "intensity", "medium"}));
}

}  // namespace
}  // namespace colony
