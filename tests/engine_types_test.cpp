// Engines that take entity types (entities="eyebot"): eye-bots fly in one
// engine while foot-bots drive in another, in the same arena; sensors see
// across engines; load-time errors for claims that cannot work.
#include "actuators/differential_steering/differential_steering.h"
#include "tests/test_util.h"

namespace colony {
namespace {

using testing::LoadError;
using testing::Mentions;

class Idle : public Controller {
 public:
  void ControlStep() override {}
};
COLONY_REGISTER_CONTROLLER(Idle, "engine_types_idle", "test: does nothing");
const char kIdle[] = "<engine_types_idle id=\"idle\"/>";

class Cruise : public Controller {
 public:
  void Init(const Params&) override {
    wheels_ = &GetActuator<DifferentialSteering>("differential_steering");
  }
  void ControlStep() override { wheels_->SetLinearVelocity(0.2, 0.2); }

 private:
  DifferentialSteering* wheels_ = nullptr;
};
COLONY_REGISTER_CONTROLLER(Cruise, "engine_types_cruise", "test: drives straight on");
const char kCruise[] =
    "<engine_types_cruise id=\"cruise\"><actuators><differential_steering/></actuators>"
    "</engine_types_cruise>";

std::string Marxbot(const std::string& id, const std::string& position) {
  return "<marxbot id=\"" + id + "\"><body position=\"" + position +
         "\"/><controller config=\"idle\"/></marxbot>";
}
std::string Eyebot(const std::string& id, const std::string& position,
                   const std::string& attributes = "") {
  return "<eyebot id=\"" + id + "\" " + attributes + "><body position=\"" + position +
         "\"/><controller config=\"idle\"/></eyebot>";
}

TEST(EngineTypes, AnEngineTakesItsTypesAndTheOthersTheRest) {
  if (!testing::HaveEngine("dynamics3d")) GTEST_SKIP() << "no dynamics3d in this build";
  // Foot-bots in dynamics3d wherever they are; boxes in kinematics2d, which
  // takes what its region holds; walls (fixed) in both.
  auto sim = testing::LoadXml(testing::Experiment(
      Marxbot("m", "0,0,0") + "<box id=\"b\" size=\"0.2,0.2,0.2\" movable=\"true\" mass=\"1\">"
                              "<body position=\"1,1,0\"/></box><walls/>",
      kIdle, "4,4,1", "",
      "<kinematics2d id=\"ground\"/><dynamics3d id=\"d3\" entities=\"foot-bot\"/>"));
  const Space& space = sim->space();
  EXPECT_EQ(sim->EngineOf(space.Find("m"))->id(), "d3");
  EXPECT_EQ(sim->EngineOf(space.Find("b"))->id(), "ground");
  EXPECT_EQ(sim->engines()[0]->entity_types().size(), 0u);
  ASSERT_EQ(sim->engines()[1]->entity_types().size(), 1u);
  EXPECT_EQ(sim->engines()[1]->entity_types()[0], "marxbot");  // the alias resolved
}

TEST(EngineTypes, UnknownTypeIsRefusedWithASuggestion) {
  const std::string m = LoadError(testing::Experiment(
      "", "", "4,4,1", "", "<kinematics2d id=\"ground\" entities=\"marxbt\"/>"));
  EXPECT_TRUE(Mentions(m, {"<string>:1:", "<kinematics2d id=\"ground\">", "entities",
                           "unknown entity type "
                           "'marxbt'",
                           "did you mean 'marxbot'"}));
  EXPECT_TRUE(Mentions(LoadError(testing::Experiment("", "", "4,4,1", "",
                                                     "<kinematics2d id=\"g\" entities=\" , \"/>")),
                       {"entities", "names no entity type"}));
}

TEST(EngineTypes, ATypeTakenByTwoEnginesIsRefused) {
  if (!testing::HaveEngine("dynamics3d")) GTEST_SKIP() << "no dynamics3d in this build";
  const std::string m = LoadError(testing::Experiment(
      "", "", "4,4,1", "",
      "<dynamics3d id=\"a\" entities=\"marxbot\"/>\n<dynamics3d id=\"b\" entities=\"box, "
      "foot-bot\"/>"));
  EXPECT_TRUE(Mentions(m, {"<dynamics3d id=\"b\">",
                           "entity type 'marxbot' is already taken by dynamics3d "
                           "'a' (line 1)",
                           "one engine only"}));
}

TEST(EngineTypes, ATypeTheEngineCannotSimulateIsRefused) {
  const std::string m = LoadError(testing::Experiment(
      "", "", "4,4,1", "", "<kinematics2d id=\"ground\" entities=\"handbot\"/>"));
  EXPECT_TRUE(Mentions(m, {"<kinematics2d id=\"ground\">", "entities",
                           "kinematics2d 'ground' cannot simulate "
                           "a 'handbot'",
                           "no model kinematics2d:handbot"}));
  if (testing::HaveEngine("dynamics3d")) {
    EXPECT_TRUE(Mentions(m, {"engines that can: dynamics3d"}));
  }
}

TEST(EngineTypes, AnEyebotNoEngineCanFlyIsRefusedWithTheEnginesThatCan) {
  const std::string m = LoadError(testing::Experiment(Eyebot("e", "0,0,0"), kIdle));
  EXPECT_TRUE(Mentions(m, {"<eyebot id=\"e\">",
                           "no physics engine of this experiment can simulate an "
                           "'eyebot'",
                           "kinematics2d 'k2d'"}));
  if (testing::HaveEngine("pointmass3d")) {
    EXPECT_TRUE(Mentions(m, {"pointmass3d", "entities=\"eyebot\""}));
  }
}

TEST(EngineTypes, TwoAndThreeDimensionalRegionEnginesStillDoNotMix) {
  if (!testing::HaveEngine("dynamics3d")) GTEST_SKIP() << "no dynamics3d in this build";
  const std::string m = LoadError(testing::Experiment(
      "", "", "4,4,1", "", "<kinematics2d id=\"ground\"/><dynamics3d id=\"d3\"/>"));
  EXPECT_TRUE(
      Mentions(m, {"<dynamics3d id=\"d3\">", "cannot share an experiment's regions with 2D engines",
                   "entities=\"eyebot\""}));
}

TEST(EngineTypes, FixedEntitiesOfATakenTypeStayInEveryEngine) {
  if (!testing::HaveEngine("dynamics2d") || !testing::HaveEngine("pointmass3d")) {
    GTEST_SKIP() << "no dynamics2d or pointmass3d in this build";
  }
  // The walls are boxes, and pointmass3d takes boxes: the movable ones are
  // its own, but the walls (fixed) still stop a foot-bot in dynamics2d.
  auto sim = testing::LoadXml(testing::Experiment(
      "<marxbot id=\"m\"><body position=\"1.2,0,0\"/><controller config=\"cruise\"/></marxbot>"
      "<box id=\"b\" size=\"0.2,0.2,0.2\" movable=\"true\" mass=\"1\"><body "
      "position=\"-1,-1,0\"/></box><walls/>",
      kCruise, "4,4,1", "",
      "<dynamics2d id=\"ground\"/><pointmass3d id=\"air\" entities=\"eyebot, box\"/>"));
  EXPECT_EQ(sim->EngineOf(sim->space().Find("b"))->id(), "air");
  testing::RunFor(*sim, 8);
  EXPECT_LT(testing::PositionOf(*sim, "m").x(), 2.0 - 0.08) << "drove through the east wall";
}

TEST(EngineTypes, AnEngineThatTakesTypesHasNoBoundaries) {
  const std::string m = LoadError(testing::Experiment(
      "", "", "4,4,1", "",
      "<kinematics2d id=\"ground\" entities=\"marxbot\"><boundaries><top height=\"1\"/>"
      "<bottom height=\"0\"/><sides><vertex point=\"-1,-1\"/><vertex point=\"1,-1\"/>"
      "<vertex point=\"1,1\"/></sides></boundaries></kinematics2d>"));
  EXPECT_TRUE(Mentions(m, {"<boundaries>", "takes entity types (entities=\"marxbot\")",
                           "cannot have <boundaries>"}));
}

TEST(EngineTypes, AMovableThatOnlyTypeTakingEnginesCouldSimulateIsExplained) {
  if (!testing::HaveEngine("pointmass3d")) GTEST_SKIP() << "no pointmass3d in this build";
  const std::string m = LoadError(testing::Experiment(
      "<box id=\"b\" size=\"0.2,0.2,0.2\" movable=\"true\" mass=\"1\"><body "
      "position=\"1,1,0\"/></box>",
      "", "4,4,1", "",
      "<kinematics2d id=\"ground\" entities=\"marxbot\"/><pointmass3d id=\"air\" "
      "entities=\"eyebot\"/>"));
  EXPECT_TRUE(Mentions(
      m, {"<box id=\"b\"", "entity 'b' is a movable box", "takes only the entity types it lists",
          "kinematics2d 'ground': marxbot; pointmass3d 'air': eyebot",
          "add an engine without entities="}));
}

}  // namespace
}  // namespace colony
