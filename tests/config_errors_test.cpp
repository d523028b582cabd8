// Bad experiment files and command-line overrides. Each must be refused with
// a ConfigError whose message names what a user needs to fix it: the file and
// line, the element, the attribute, the bad value and what is accepted.
// Suites are named config_errors* so `ctest -R config_errors` selects them.
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/registry.h"
#include "tests/test_util.h"

namespace colony::testing {
namespace {

namespace fs = std::filesystem;

// A minimal controller, so controller cases need no shared library.
class ProbeController : public Controller {
 public:
  void Init(const Params& params) override { speed_ = params.GetDouble("speed", 0.1, 0, 1); }
  void ControlStep() override {}

 private:
  double speed_ = 0;
};

COLONY_REGISTER_CONTROLLER(ProbeController, "config_errors_probe",
                           "test controller of config_errors_test; params: speed");

const char kProbe[] = "<config_errors_probe id=\"probe\"/>";

std::string Robot(const std::string& id, const std::string& position,
                  const std::string& config = "probe") {
  return "<marxbot id=\"" + id + "\"><body position=\"" + position + "\"/><controller config=\"" +
         config + "\"/></marxbot>";
}

// Every problem reported for `xml` (empty if it loads).
std::vector<Diagnostic> Diagnose(const std::string& xml, std::vector<std::string> overrides = {}) {
  try {
    LoadXml(xml, std::move(overrides));
  } catch (const ConfigError& e) {
    return e.diagnostics();
  }
  return {};
}

// A file whose <experiment> (line 3) carries `attributes`.
std::string WithExperiment(const std::string& attributes) {
  return "<colony>\n<framework>\n<experiment " + attributes +
         "/>\n</framework>\n<arena size=\"2,2,1\"/>\n</colony>\n";
}

// A folder of its own under the system's temporary folder.
fs::path TempDir() {
  std::string pattern = (fs::temp_directory_path() / "colony_config_errors_XXXXXX").string();
  EXPECT_NE(mkdtemp(pattern.data()), nullptr);
  return pattern;
}

// --- Not an experiment file at all -----------------------------------------

TEST(config_errors, EmptyFile) {
  EXPECT_TRUE(Mentions(LoadError(""), {"<string>", "the file is empty", "<colony>"}));
  EXPECT_TRUE(Mentions(LoadError("  \n\n  "), {"the file is empty"}));
}

TEST(config_errors, PlainTextIsNotXml) {
  const std::string message = LoadError("length = 10\nticks = 5\n");
  EXPECT_TRUE(Mentions(message, {"<string>:1:", "not XML", "root element <colony>"}));
  EXPECT_EQ(message.find("XML_ERROR"), std::string::npos)
      << "raw parser codes mean nothing to a user:\n"
      << message;
}

TEST(config_errors, TruncatedFileNamesTheElementLeftOpen) {
  const std::string message = LoadError(
      "<colony>\n<framework>\n<experiment length=\"1\"/>\n</framework>\n<arena size=\"2,2,1\">\n");
  EXPECT_TRUE(Mentions(message, {"<string>:5:", "not well-formed XML", "<arena> (line 5)",
                                 "never closed", "</arena>", "truncated"}));
  EXPECT_EQ(message.find("XML_ERROR"), std::string::npos) << message;
}

TEST(config_errors, FileCutInsideATag) {
  const std::string message = LoadError("<colony>\n<framework>\n<experiment length=\"1");
  EXPECT_TRUE(Mentions(message, {"<string>:3:", "<experiment>", "truncated"}));
}

TEST(config_errors, MismatchedClosingTag) {
  const std::string message =
      LoadError("<colony>\n<framework>\n<experiment length=\"1\"/>\n</frame>\n</colony>");
  EXPECT_TRUE(
      Mentions(message, {"<string>:2:", "<framework>", "not closed by a matching </framework>"}));
}

TEST(config_errors, UnquotedAttribute) {
  EXPECT_TRUE(Mentions(LoadError(WithExperiment("length=10")),
                       {"<string>:3:", "<experiment>", "malformed", "accepted: name=\"value\""}));
}

TEST(config_errors, WrongRootElement) {
  const std::string message = LoadError("<?xml version=\"1.0\"?>\n<argos>\n</argos>\n");
  EXPECT_TRUE(
      Mentions(message, {"<string>:2:", "<argos>", "accepted: <colony> or <argos-configuration>"}));
}

// --- Bad values --------------------------------------------------------------

TEST(config_errors, NumberThatIsNotANumber) {
  const auto diagnostics = Diagnose(WithExperiment("length=\"abc\""));
  ASSERT_EQ(diagnostics.size(), 1u);
  EXPECT_TRUE(Mentions(diagnostics[0].ToString(),
                       {"<string>:3:", "<experiment>", "attribute 'length'", "'abc'",
                        "not a finite number", "accepted: a number >= 0"}));
  EXPECT_EQ(diagnostics[0].value, "abc");
}

TEST(config_errors, NegativeTicksPerSecond) {
  EXPECT_TRUE(Mentions(LoadError(WithExperiment("length=\"10\" ticks_per_second=\"-1\"")),
                       {"<string>:3:", "<experiment>", "attribute 'ticks_per_second'", "'-1'",
                        "out of range", "accepted: a number in (0, 1e+06]"}));
}

TEST(config_errors, ZeroTicksPerSecondIsOutsideTheAcceptedRange) {
  // The accepted range must not claim to include 0.
  EXPECT_TRUE(Mentions(LoadError(WithExperiment("length=\"10\" ticks_per_second=\"0\"")),
                       {"'0' is out of range", "(0, 1e+06]"}));
}

TEST(config_errors, NonFiniteNumbers) {
  for (const std::string bad : {"inf", "-inf", "nan", "1e999"}) {
    EXPECT_TRUE(Mentions(LoadError(WithExperiment("length=\"" + bad + "\"")),
                         {"<string>:3:", "attribute 'length'", "'" + bad + "'",
                          "not a finite number", "accepted: a number >= 0"}));
  }
}

TEST(config_errors, ExperimentTooLongToCount) {
  EXPECT_TRUE(Mentions(
      LoadError(WithExperiment("length=\"1e300\"")),
      {"<string>:3:", "attribute 'length'", "accepted: length * ticks_per_second < 9e18"}));
}

TEST(config_errors, ThreadsOutOfRange) {
  const std::string xml =
      "<colony>\n<framework>\n<system threads=\"1000\"/>\n<experiment "
      "length=\"1\"/>\n</framework>\n"
      "<arena size=\"2,2,1\"/>\n</colony>";
  EXPECT_TRUE(Mentions(LoadError(xml), {"<string>:3:", "<system>", "attribute 'threads'", "'1000'",
                                        "out of range", "accepted: a whole number in [0, 256]"}));
}

TEST(config_errors, WholeNumberWithAFraction) {
  EXPECT_TRUE(Mentions(LoadError(WithExperiment("length=\"1\" random_seed=\"1.5\"")),
                       {"<string>:3:", "attribute 'random_seed'", "'1.5'", "not a whole number",
                        "accepted: a whole number >= 0"}));
}

TEST(config_errors, BadTriple) {
  EXPECT_TRUE(
      Mentions(LoadError("<colony>\n<framework><experiment length=\"1\"/></framework>\n"
                         "<arena size=\"2,2\"/>\n</colony>"),
               {"<string>:3:", "<arena>", "attribute 'size'", "'2,2'", "accepted: \"x,y,z\""}));
}

// --- Unknown names -------------------------------------------------------------

TEST(config_errors, UnknownTopLevelElement) {
  const auto diagnostics = Diagnose(
      "<colony>\n<framwork>\n<experiment length=\"1\"/>\n</framwork>\n<arena "
      "size=\"2,2,1\"/>\n</colony>");
  // One message: the typo, not also "missing <framework>".
  ASSERT_EQ(diagnostics.size(), 1u);
  EXPECT_TRUE(Mentions(diagnostics[0].ToString(),
                       {"<string>:2:", "<framwork>", "unknown element inside <colony>",
                        "did you mean <framework>?", "accepted: framework, controllers"}));
}

TEST(config_errors, UnknownAttribute) {
  const auto diagnostics = Diagnose(WithExperiment("lenght=\"10\""));
  ASSERT_EQ(diagnostics.size(), 1u);
  EXPECT_TRUE(
      Mentions(diagnostics[0].ToString(),
               {"<string>:3:", "<experiment>", "attribute 'lenght'", "unknown attribute",
                "did you mean 'length'?", "accepted: length, ticks_per_second, random_seed"}));
}

TEST(config_errors, UnknownRobotTypeInArena) {
  const std::string message =
      LoadError(Experiment("\n<marxbott id=\"m\"><body position=\"0,0,0\"/></marxbott>"));
  EXPECT_TRUE(
      Mentions(message, {"<string>:2:", "<marxbott id=\"m\">", "unknown element inside <arena>",
                         "did you mean <marxbot>?", "accepted:", "marxbot", "box", "cylinder"}));
}

TEST(config_errors, UnknownSensorAndActuatorInController) {
  const std::string controllers =
      "\n<config_errors_probe id=\"probe\">\n<sensors><proximty/></sensors>\n"
      "<actuators><differential_stearing/></actuators>\n</config_errors_probe>";
  const auto diagnostics = Diagnose(Experiment("", controllers));
  ASSERT_EQ(diagnostics.size(), 2u);
  EXPECT_TRUE(
      Mentions(diagnostics[0].ToString(), {"<string>:3:", "<proximty>", "unknown sensor 'proximty'",
                                           "did you mean 'proximity'?", "accepted:", "proximity"}));
  EXPECT_TRUE(Mentions(
      diagnostics[1].ToString(),
      {"<string>:4:", "<differential_stearing>", "unknown actuator 'differential_stearing'",
       "did you mean 'differential_steering'?", "accepted:", "leds"}));
}

TEST(config_errors, UnknownPhysicsEngine) {
  const std::string message =
      LoadError(Experiment("", "", "4,4,1", "", "\n<kinematic2d id=\"k\"/>"));
  EXPECT_TRUE(Mentions(
      message, {"<string>:2:", "<kinematic2d id=\"k\">", "unknown physics engine 'kinematic2d'",
                "did you mean 'kinematics2d'?", "accepted: kinematics2d"}));
}

TEST(config_errors, RobotNamesAnUndefinedController) {
  const std::string message = LoadError(Experiment("\n" + Robot("m", "0,0,0", "x"), kProbe));
  EXPECT_TRUE(Mentions(
      message, {"<string>:2:", "<controller>", "attribute 'config'",
                "no controller with id 'x' is defined in <controllers>", "defined: probe"}));
}

TEST(config_errors, RobotWithoutController) {
  EXPECT_TRUE(Mentions(
      LoadError(Experiment("\n<marxbot id=\"m\"><body position=\"0,0,0\"/></marxbot>", kProbe)),
      {"<string>:2:", "<marxbot id=\"m\">", "missing <controller config=\"ID\"/>"}));
}

TEST(config_errors, DuplicateEntityIds) {
  const std::string arena =
      "\n<box id=\"b\" size=\"0.2,0.2,0.2\"><body position=\"1,1,0\"/></box>"
      "\n<box id=\"b\" size=\"0.2,0.2,0.2\"><body position=\"-1,-1,0\"/></box>";
  EXPECT_TRUE(Mentions(LoadError(Experiment(arena)),
                       {"<string>:3:", "<box id=\"b\">", "attribute 'id'",
                        "duplicate entity id 'b'", "first defined at line 2"}));
}

TEST(config_errors, DuplicateControllerIds) {
  EXPECT_TRUE(Mentions(
      LoadError(Experiment("", std::string("\n") + kProbe + "\n" + kProbe)),
      {"<string>:3:", "attribute 'id'", "controller id 'probe' already defined at line 2"}));
}

// --- Libraries -------------------------------------------------------------------

TEST(config_errors, MissingLibrary) {
  const auto diagnostics =
      Diagnose(Experiment("", "\n<diffusion id=\"c\" library=\"no_such_lib\"/>"));
  ASSERT_FALSE(diagnostics.empty());
  const std::string message = diagnostics[0].ToString();
  EXPECT_TRUE(Mentions(message, {"<string>:2:", "<diffusion id=\"c\">", "attribute 'library'",
                                 "cannot load library 'no_such_lib'", "tried:",
                                 "libno_such_lib.so (no such file)", "COLONY_PLUGIN_PATH"}));
  if (const char* path = std::getenv("COLONY_PLUGIN_PATH")) {
    EXPECT_TRUE(Mentions(message, {std::string(path) + "/libno_such_lib.so"}));
  }
}

TEST(config_errors, UnloadableLibrary) {
  const fs::path dir = TempDir();
  const fs::path library = dir / "libbroken.so";
  {
    std::ofstream out(library);
    for (int i = 0; i < 64; ++i) out << "this is not a shared library\n";
  }
  const std::string message =
      LoadError(Experiment("", "\n<diffusion id=\"c\" library=\"" + library.string() + "\"/>"));
  EXPECT_TRUE(Mentions(message, {"<string>:2:", "attribute 'library'", "cannot load library",
                                 "tried:", library.string() + " ("}));
  // It exists: the reason is the loader's, not "no such file".
  EXPECT_EQ(message.find("no such file"), std::string::npos) << message;
  fs::remove_all(dir);
}

// --- Placement -----------------------------------------------------------------

TEST(config_errors, RobotInsideABox) {
  const std::string box = "\n<box id=\"b\" size=\"1,1,0.5\"><body position=\"0,0,0\"/></box>";
  EXPECT_TRUE(Mentions(LoadError(Experiment(box + "\n" + Robot("m", "0.3,0,0"), kProbe)),
                       {"<string>:3:", "<marxbot id=\"m\">", "entity 'm' overlaps 'b' (line 2)"}));
}

TEST(config_errors, BoxPlacedOnARobotDeclaredBeforeIt) {
  // The same overlap, whichever of the two is declared first.
  const std::string box = "\n<box id=\"b\" size=\"1,1,0.5\"><body position=\"0,0,0\"/></box>";
  EXPECT_TRUE(Mentions(LoadError(Experiment("\n" + Robot("m", "0.3,0,0") + box, kProbe)),
                       {"<string>:3:", "<box id=\"b\">", "entity 'b' overlaps 'm' (line 2)"}));
}

TEST(config_errors, RobotInsideTheWalls) {
  const std::string arena = "\n<walls thickness=\"0.1\" height=\"0.5\"/>\n" + Robot("m", "0,1.9,0");
  EXPECT_TRUE(Mentions(LoadError(Experiment(arena, kProbe)),
                       {"<string>:3:", "<marxbot id=\"m\">", "overlaps 'wall_north' (line 2)"}));
}

TEST(config_errors, WallsFitAnArenaWhoseSizeHasManyDecimals) {
  std::string xml =
      Experiment("<walls thickness=\"0.1\" height=\"0.5\"/>", "", "70.9106791,70.9106791,1");
  EXPECT_EQ(LoadError(xml), "");
}

TEST(config_errors, FixedObjectsMayTouch) {
  // Walls meet at corners and boxes may lean on them: only movable things must be clear.
  const std::string arena =
      "<walls thickness=\"0.1\" height=\"0.5\"/><box id=\"b\" size=\"1,0.5,0.5\"><body "
      "position=\"1.4,0,0\"/></box>";
  EXPECT_EQ(LoadError(Experiment(arena)), "");
}

TEST(config_errors, EntityOutsideTheArena) {
  const std::string box = "\n<box id=\"b\" size=\"1,1,0.5\"><body position=\"5,0,0\"/></box>";
  EXPECT_TRUE(Mentions(LoadError(Experiment(box)),
                       {"<string>:2:", "<box id=\"b\">", "entity 'b' is outside the arena",
                        "x [4.5, 5.5]", "the arena spans x [-2, 2]"}));
}

// Marxbots distributed over 1 m x 1 m; `entity` is the attributes of the
// block's <entity> (line 5 of the file; the marxbot is on line 6).
std::string DistributeOverOneSquareMetre(const std::string& entity) {
  return "\n<distribute>\n<position method=\"uniform\" min=\"-0.5,-0.5,0\" max=\"0.5,0.5,0\"/>\n"
         "<orientation method=\"constant\" values=\"0,0,0\"/>\n<entity " +
         entity +
         ">\n<marxbot id=\"mb\"><controller config=\"probe\"/></marxbot>\n</entity>\n"
         "</distribute>";
}

TEST(config_errors, DistributeCannotPlaceEveryRobot) {
  const auto diagnostics = Diagnose(
      Experiment(DistributeOverOneSquareMetre("quantity=\"500\" max_trials=\"20\""), kProbe));
  ASSERT_EQ(diagnostics.size(), 1u);
  const std::string message = diagnostics[0].ToString();
  EXPECT_TRUE(
      Mentions(message, {"<string>:5:", "<entity>", "attribute 'max_trials'", "could place only ",
                         " of 500 entities", "no free place in 20 trials", "raise max_trials"}));
  // Some fit in 1 m x 1 m, far from all.
  const size_t at = message.find("could place only ") + std::string("could place only ").size();
  const int placed = std::stoi(message.substr(at));
  EXPECT_GT(placed, 0);
  EXPECT_LT(placed, 500);
}

TEST(config_errors, DistributeNumberedByPlaceCannotPlaceEveryRobot) {
  // Drawn whole before any is added: the message names the draw that failed,
  // not an id (ids follow the places), and what it overlapped.
  const auto diagnostics = Diagnose(Experiment(
      DistributeOverOneSquareMetre("quantity=\"500\" max_trials=\"20\" order=\"place\""), kProbe));
  ASSERT_EQ(diagnostics.size(), 1u);
  EXPECT_TRUE(Mentions(diagnostics[0].ToString(), {"<string>:5:", "could place only ",
                                                   " of 500 entities: the next found no "
                                                   "free place in 20 trials",
                                                   "overlaps an entity of the same <distribute> "
                                                   "block drawn before it (line 6)"}));
}

TEST(config_errors, DistributeOrderMustBeDrawnOrPlace) {
  EXPECT_TRUE(Mentions(
      LoadError(
          Experiment(DistributeOverOneSquareMetre("quantity=\"2\" order=\"spatial\""), kProbe)),
      {"<string>:5:", "<entity>", "attribute 'order'", "'spatial'", "accepted: drawn, place"}));
}

TEST(config_errors, DistributeGridTooLargeIsRefusedNotAllocated) {
  const std::string arena =
      "\n<distribute>\n<position method=\"grid\" center=\"0,0,0\" distances=\"0.3,0.3,0\" "
      "layout=\"5000,5000,5000\"/>\n<orientation method=\"constant\" values=\"0,0,0\"/>\n"
      "<entity quantity=\"4\"><marxbot id=\"mb\"><controller "
      "config=\"probe\"/></marxbot></entity>\n</distribute>";
  EXPECT_TRUE(Mentions(LoadError(Experiment(arena, kProbe)),
                       {"<string>:3:", "<position>", "attribute 'layout'", "'5000,5000,5000'",
                        "product is at most 10000000"}));
}

// --- Structure -------------------------------------------------------------------

TEST(config_errors, PathologicalNesting) {
  std::string nested;
  for (int i = 0; i < 200; ++i) nested += "<a>";
  for (int i = 0; i < 200; ++i) nested += "</a>";
  EXPECT_TRUE(Mentions(LoadError("<colony>\n" + nested + "\n</colony>"),
                       {"<string>:2:", "nested too deeply", "over 100 levels"}));
  // Deep, but within the parser's limit: still one clear error, no crash.
  std::string deep;
  for (int i = 0; i < 90; ++i) deep += "<a>";
  for (int i = 0; i < 90; ++i) deep += "</a>";
  EXPECT_TRUE(Mentions(LoadError(Experiment("", "", "4,4,1", deep)),
                       {"<a>", "unknown element inside <colony>"}));
}

// --- Command-line overrides ------------------------------------------------------

TEST(config_errors, OverrideWithBadPath) {
  const std::string message = LoadError(Experiment(""), {"framework.nope.length=3"});
  EXPECT_TRUE(Mentions(message, {"--set 'framework.nope.length=3'",
                                 "no element <nope> inside <framework>", "it holds: experiment"}));
}

TEST(config_errors, OverrideWithMisspeltElement) {
  EXPECT_TRUE(Mentions(LoadError(Experiment(""), {"framework.experimnt.length=3"}),
                       {"no element <experimnt>", "did you mean 'experiment'?"}));
}

TEST(config_errors, MalformedOverride) {
  EXPECT_TRUE(
      Mentions(LoadError(Experiment(""), {"noequals"}),
               {"--set 'noequals'", "expected PATH=VALUE", "framework.experiment.length=10"}));
  EXPECT_TRUE(
      Mentions(LoadError(Experiment(""), {"framework..length=3"}), {"empty name in the path"}));
  EXPECT_TRUE(
      Mentions(LoadError(Experiment(""), {"length=3"}), {"at least an element and an attribute"}));
}

TEST(config_errors, OverrideWithBadValueIsCheckedLikeTheFile) {
  EXPECT_TRUE(Mentions(
      LoadError(Experiment(""), {"framework.experiment.length=-3"}),
      {"<experiment>", "attribute 'length'", "'-3' is out of range", "accepted: a number >= 0"}));
}

// --- Several errors ---------------------------------------------------------------

TEST(config_errors, SeveralErrorsAreReportedTogether) {
  const auto diagnostics = Diagnose(
      "<colony>\n<framework>\n<experiment length=\"abc\"\n  "
      "ticks_per_second=\"fast\"/>\n</framework>\n"
      "<arena size=\"2,2,1\"/>\n</colony>");
  ASSERT_EQ(diagnostics.size(), 2u);
  EXPECT_TRUE(Mentions(diagnostics[0].ToString(), {"attribute 'length'", "'abc'"}));
  EXPECT_TRUE(Mentions(diagnostics[1].ToString(), {"attribute 'ticks_per_second'", "'fast'"}));
  // And the exception's message carries both, one per line.
  const std::string message = LoadError(
      "<colony>\n<framework>\n<experiment length=\"abc\"\n  "
      "ticks_per_second=\"fast\"/>\n</framework>\n"
      "<arena size=\"2,2,1\"/>\n</colony>");
  EXPECT_TRUE(Mentions(message, {"'abc'", "\n", "'fast'"}));
}

TEST(config_errors, ErrorsInDifferentEntitiesAreReportedTogether) {
  const std::string arena =
      "\n<box id=\"b1\" size=\"0.2,0.2,-1\"><body position=\"1,1,0\"/></box>"
      "\n<cylinder id=\"c1\" radius=\"0.1\" height=\"0.2\" colour=\"red\"><body "
      "position=\"-1,1,0\"/></cylinder>"
      "\n<lamp id=\"l\"/>";
  const std::string message = LoadError(Experiment(arena));
  EXPECT_TRUE(Mentions(
      message, {"<string>:2:", "'0.2,0.2,-1' is out of range", "<string>:3:", "attribute 'colour'",
                "did you mean 'color'?", "<string>:4:", "<lamp id=\"l\">"}));
}

TEST(config_errors, BadWallsDoNotHideOtherErrors) {
  const std::string arena =
      "\n<walls thickness=\"3\" height=\"0.5\"/>"
      "\n<box id=\"b\" size=\"0.2,0.2,0\"><body position=\"1,1,0\"/></box>";
  const std::string message = LoadError(Experiment(arena));
  EXPECT_TRUE(Mentions(message, {"<string>:2:", "<walls>", "attribute 'thickness'",
                                 "walls 3 m thick", "accepted: a number > 0 and < 2",
                                 "<string>:3:", "<box id=\"b\">", "'0.2,0.2,0' is out of range"}));
}

// --- Controller parameters -----------------------------------------------------------

TEST(config_errors, ControllerParameterNotRead) {
  const std::string controllers =
      "\n<diffusion id=\"dc\" library=\"diffusion\">"
      "<actuators><differential_steering/></actuators><sensors><proximity/></sensors>"
      "\n<params alpha=\"7.5\" velocty=\"0.05\"/>\n</diffusion>";
  const std::string message = LoadError(Experiment(Robot("m", "0,0,0", "dc"), controllers));
  EXPECT_TRUE(Mentions(message, {"<string>:3:", "<params>", "attribute 'velocty'",
                                 "parameter not read by controller 'diffusion'",
                                 "did you mean 'velocity'?", "it reads: alpha, delta, velocity"}));
}

TEST(config_errors, ControllerParameterWithBadValue) {
  const std::string controllers =
      "\n<config_errors_probe id=\"probe\">\n<params speed=\"quick\"/>\n</config_errors_probe>";
  EXPECT_TRUE(
      Mentions(LoadError(Experiment(Robot("m", "0,0,0"), controllers)),
               {"<string>:3:", "<params>", "attribute 'speed'", "'quick' is not a finite number"}));
}

// --- Files -------------------------------------------------------------------------

TEST(config_errors, MessagesNameTheFile) {
  const fs::path dir = TempDir();
  const fs::path file = dir / "bad.xml";
  std::ofstream(file) << WithExperiment("length=\"abc\"");
  ExperimentOptions options;
  options.file = file.string();
  try {
    Simulation::Load(options);
    ADD_FAILURE() << "the experiment loaded";
  } catch (const ConfigError& e) {
    EXPECT_TRUE(Mentions(e.what(), {file.string() + ":3:", "attribute 'length'", "'abc'"}));
  }
  fs::remove_all(dir);
}

TEST(config_errors, MissingFile) {
  ExperimentOptions options;
  options.file = "/no/such/experiment.xml";
  try {
    Simulation::Load(options);
    ADD_FAILURE() << "the experiment loaded";
  } catch (const ConfigError& e) {
    EXPECT_TRUE(Mentions(e.what(), {"/no/such/experiment.xml", "no such file"}));
  }
}

TEST(config_errors, AGoodExperimentStillLoads) {
  // The cases above fail for the reason they test, not because the base is broken.
  const auto sim = LoadXml(Experiment(Robot("m", "0,0,0"), kProbe));
  EXPECT_EQ(sim->robot_count(), 1u);
  EXPECT_EQ(sim->length_ticks(), 100u);
}

// --- Ceilings -------------------------------------------------------------------

TEST(config_errors, CeilingIsReadAndCheckedAgainstTheArenaAndWhatStandsUnderIt) {
  // The test arena is 4 x 4 x 1 m, its floor at z = 0.
  const auto sim = LoadXml(Experiment("<ceiling height=\"0.8\" ferromagnetic=\"false\"/>"));
  ASSERT_TRUE(sim->space().ceiling().has_value());
  EXPECT_DOUBLE_EQ(sim->space().ceiling()->z, 0.8);
  EXPECT_FALSE(sim->space().ceiling()->ferromagnetic);
  EXPECT_FALSE(LoadXml(Experiment(""))->space().ceiling().has_value())
      << "no <ceiling>: open above";
  EXPECT_TRUE(Mentions(LoadError(Experiment("\n<ceiling height=\"1.5\"/>")),
                       {"<string>:2:", "<ceiling>", "height", "'1.5'", "above the arena's top",
                        "<= the arena's height (1 m)"}));
  EXPECT_TRUE(Mentions(LoadError(Experiment("\n<ceiling height=\"-1\" ferromagnetic=\"maybe\"/>")),
                       {"<string>:2:", "height", "'-1'"}));
  EXPECT_TRUE(Mentions(LoadError(Experiment("\n<ceiling ferromagnetic=\"maybe\"/>")),
                       {"<string>:2:", "ferromagnetic", "'maybe'"}));
  EXPECT_TRUE(Mentions(LoadError(Experiment("<ceiling height=\"0.5\"/><ceiling height=\"0.6\"/>")),
                       {"<ceiling>"}));
  // A box 0.6 m tall under a ceiling 0.5 m up.
  EXPECT_TRUE(Mentions(
      LoadError(Experiment("<ceiling height=\"0.5\"/>\n<box id=\"tall\" size=\"0.2,0.2,0.6\">"
                           "<body position=\"1,1,0\"/></box>")),
      {"<string>:2:", "'tall'", "reaches above the ceiling", "z = 0.6", "z = 0.5"}));
}

// --- Floors with ditches ------------------------------------------------------

TEST(config_errors, DitchOutsideTheArena) {
  const std::string floor =
      "\n<floor><ditch center=\"1.9,0\" size=\"0.5,1\" depth=\"0.06\"/></floor>";
  EXPECT_TRUE(Mentions(LoadError(Experiment(floor)),
                       {"<string>:2:", "<ditch>", "center", "reaches outside the arena"}));
}

TEST(config_errors, DitchWithBadSizeAndDepth) {
  const std::string floor =
      "\n<floor><ditch center=\"0,0\" size=\"-0.1,1\"/>\n<ditch center=\"0,0\" size=\"0.1,1\" "
      "depth=\"0\"/>"
      "\n<ditch size=\"0.1,1\"/>\n<ditch center=\"0,0,0\" size=\"0.1,1\"/></floor>";
  const std::string message = LoadError(Experiment(floor));
  EXPECT_TRUE(Mentions(message, {"<string>:2:", "size", "'-0.1,1'"}));
  EXPECT_TRUE(Mentions(message, {"<string>:3:", "depth", "'0'"}));
  EXPECT_TRUE(Mentions(message, {"<string>:4:", "center", "required attribute is missing"}));
  EXPECT_TRUE(Mentions(message, {"<string>:5:", "center", "is not two finite numbers", "\"x,y\""}));
}

TEST(config_errors, DitchesAreReadIntoTheFloor) {
  const auto sim = LoadXml(
      Experiment("<floor><ditch center=\"0.5,0\" size=\"0.06,2\" depth=\"0.07\"/></floor>"));
  const Floor& floor = sim->space().floor();
  ASSERT_EQ(floor.ditches().size(), 1u);
  EXPECT_DOUBLE_EQ(floor.ditches()[0].min_x, 0.47);
  EXPECT_DOUBLE_EQ(floor.ditches()[0].max_y, 1.0);
  EXPECT_DOUBLE_EQ(floor.ditches()[0].depth, 0.07);
  EXPECT_FALSE(floor.HasGroundAt(0.5, 0.3));
  EXPECT_TRUE(floor.HasGroundAt(0.4, 0.3));
}

TEST(config_errors, EntitiesMayStartDownInADitchButNotBelowIt) {
  const std::string floor =
      "<floor><ditch center=\"0.5,0\" size=\"0.07,2\" depth=\"0.06\"/></floor>";
  const std::string in =
      "<box id=\"b\" size=\"0.06,0.06,0.06\" movable=\"true\"><body "
      "position=\"0.5,0,-0.06\"/></box>";
  EXPECT_EQ(LoadError(Experiment(floor + in)), "");
  const std::string below =
      "<box id=\"b\" size=\"0.06,0.06,0.06\" movable=\"true\"><body "
      "position=\"0.5,0,-0.07\"/></box>";
  EXPECT_TRUE(Mentions(LoadError(Experiment(floor + below)), {"entity 'b' is outside the arena"}));
  const std::string astride =
      "<box id=\"b\" size=\"0.06,0.06,0.06\" movable=\"true\"><body "
      "position=\"0.45,0,-0.06\"/></box>";
  EXPECT_TRUE(
      Mentions(LoadError(Experiment(floor + astride)), {"entity 'b' is outside the arena"}));
}

// --- Media ------------------------------------------------------------------

TEST(config_errors, UnknownMedium) {
  const std::string extra = "<media>\n<radio id=\"r\"/></media>";
  EXPECT_TRUE(Mentions(LoadError(Experiment("", "", "4,4,1", extra)),
                       {"<string>:2:", "unknown medium 'radio'"}));
}

// --- Renderers ----------------------------------------------------------------

TEST(config_errors, RenderersInABuildWithoutAnImageRendererNameTheOption) {
  const WithoutImageRenderer no_image_renderer;
  const std::string need =
      " needs an image renderer, and this build has none: configure with -DCOLONY_WITH_OSMESA=ON "
      "(needs libosmesa6-dev and libassimp-dev)";
  const std::string extra = "<visualization>\n<osmesa width=\"640\"/></visualization>";
  EXPECT_TRUE(Mentions(LoadError(Experiment("", "", "4,4,1", extra)),
                       {"<string>:2: <osmesa>", "the renderer <osmesa>" + need}));
  // As `colony run --frames` adds one.
  auto sim = LoadXml(Experiment(""));
  std::string message;
  try {
    sim->AddRenderer("<osmesa/>");
  } catch (const ConfigError& e) {
    message = e.what();
  }
  EXPECT_TRUE(Mentions(message, {"the renderer <osmesa>" + need}));
}

// Sampling periods, controller rates and bus accounting (docs/events.md):
// each bad value named with the file, line, attribute and what is accepted.
std::string Timed(const std::string& controller_attributes, const std::string& sensors) {
  return "<colony>\n<framework><experiment length=\"1\" ticks_per_second=\"200\"/></framework>\n"
         "<controllers>\n<config_errors_probe id=\"probe\" " +
         controller_attributes + ">\n<sensors>\n" + sensors +
         "\n</sensors>\n</config_errors_probe>\n</controllers>\n"
         "<arena size=\"2,2,1\">" +
         Robot("r", "0,0,0") +
         "</arena>\n<physics_engines><kinematics2d id=\"k\"/></physics_engines>\n</colony>\n";
}

TEST(config_errors, SensorPeriodsMustBePositiveAndNoShorterThanATick) {
  for (const std::string bad : {"0", "-0.01"}) {
    const std::string message = LoadError(Timed("", "<proximity period=\"" + bad + "\"/>"));
    EXPECT_TRUE(Mentions(
        message, {"<string>:6:", "<proximity>", "attribute 'period'", "'" + bad + "'", "> 0"}))
        << message;
  }
  const std::string message = LoadError(Timed("", "<proximity period=\"0.001\"/>"));
  EXPECT_TRUE(Mentions(message, {"<string>:6:", "attribute 'period'", "'0.001'",
                                 "shorter than one tick", "0.005 s at 200 ticks per second"}))
      << message;
  EXPECT_EQ(LoadError(Timed("", "<proximity period=\"0.005\"/>")), "");
}

TEST(config_errors, ControllerRatesMustBePositiveAndNoFasterThanTheTicks) {
  const std::string fast = LoadError(Timed("rate=\"300\"", "<proximity/>"));
  EXPECT_TRUE(Mentions(fast, {"<string>:4:", "attribute 'rate'", "'300'",
                              "above the simulation's 200 ticks per second"}))
      << fast;
  const std::string zero = LoadError(Timed("rate=\"0\"", "<proximity/>"));
  EXPECT_TRUE(Mentions(zero, {"<string>:4:", "attribute 'rate'", "'0'", "> 0"})) << zero;
  const std::string phase = LoadError(Timed("rate=\"10\" phase=\"0.1\"", "<proximity/>"));
  EXPECT_TRUE(Mentions(phase, {"<string>:4:", "attribute 'phase'", "'0.1'", "[0, 0.1)"})) << phase;
  const std::string alone = LoadError(Timed("phase=\"random\"", "<proximity/>"));
  EXPECT_TRUE(Mentions(alone, {"<string>:4:", "attribute 'phase'", "give rate"})) << alone;
  EXPECT_EQ(LoadError(Timed("rate=\"200\" phase=\"random\"", "<proximity/>")), "");
}

TEST(config_errors, BusAccountingOnASensorWithoutABusModel) {
  const std::string message = LoadError(Timed("", "<positioning bus=\"true\"/>"));
  EXPECT_TRUE(Mentions(
      message, {"<string>:6:", "attribute 'bus'", "'positioning' has no bus model", "proximity"}))
      << message;
  const std::string actuator = LoadError(
      "<colony>\n<framework><experiment length=\"1\"/></framework>\n<controllers>\n"
      "<config_errors_probe id=\"probe\"><actuators><leds period=\"0.1\"/></actuators>"
      "</config_errors_probe></controllers><arena size=\"2,2,1\"/></colony>");
  EXPECT_TRUE(Mentions(actuator, {"attribute 'period'"})) << actuator;
}

}  // namespace
}  // namespace colony::testing

namespace colony {
namespace {

TEST(config_errors, ZeroLengthWithoutLoopFunctionsWouldNeverEnd) {
  std::string xml = testing::Experiment("");
  xml.replace(xml.find("length=\"10\""), 11, "length=\"0\"");
  const std::string message = testing::LoadError(xml);
  EXPECT_NE(message.find("attribute 'length'"), std::string::npos) << message;
  EXPECT_NE(message.find("none are declared"), std::string::npos) << message;
}

}  // namespace
}  // namespace colony
