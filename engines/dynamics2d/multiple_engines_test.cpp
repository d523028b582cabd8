// Several engines in one experiment: regions, migration across boundaries,
// determinism with engines stepping in parallel, and load-time errors.
#include "actuators/differential_steering/differential_steering.h"
#include "tests/test_util.h"

namespace colony {
namespace {

class Cruiser : public Controller {
 public:
  void Init(const Params& params) override {
    speed_ = params.GetDouble("speed", 0.1);
    wheels_ = &GetActuator<DifferentialSteering>("differential_steering");
  }
  void ControlStep() override { wheels_->SetLinearVelocity(speed_, speed_); }

 private:
  double speed_ = 0;
  DifferentialSteering* wheels_ = nullptr;
};
COLONY_REGISTER_CONTROLLER(Cruiser, "multi_engine_cruiser", "test: drives straight");

const char* kCruiser =
    "<multi_engine_cruiser id=\"c\"><actuators><differential_steering/></actuators>"
    "<params speed=\"0.1\"/></multi_engine_cruiser>";

// A region as <boundaries> over the rectangle [x0, x1] x [y0, y1].
std::string Boundaries(double x0, double y0, double x1, double y1) {
  auto v = [](double x, double y) {
    return "<vertex point=\"" + std::to_string(x) + "," + std::to_string(y) + "\"/>";
  };
  return "<boundaries><top height=\"1\"/><bottom height=\"0\"/><sides size=\"4\">" + v(x0, y0) +
         v(x1, y0) + v(x1, y1) + v(x0, y1) + "</sides></boundaries>";
}

// Left half and right half of a 4 x 2 arena, with engine kinds `left`, `right`.
std::string HalvesScene(const std::string& left, const std::string& right,
                        const std::string& robot) {
  const std::string engines = "<" + left + " id=\"west\">" + Boundaries(-2, -1, 0, 1) + "</" +
                              left + ">" + "<" + right + " id=\"east\">" + Boundaries(0, -1, 2, 1) +
                              "</" + right + ">";
  return testing::Experiment(robot + "<walls/>", kCruiser, "4,2,1", "", engines);
}

void ExpectSmoothCrossing(const std::string& left, const std::string& right, double start_x,
                          double heading) {
  const std::string robot = "<marxbot id=\"r\"><body position=\"" + std::to_string(start_x) +
                            ",0,0\" orientation=\"" + std::to_string(heading) +
                            ",0,0\"/><controller config=\"c\"/></marxbot>";
  auto sim = testing::LoadXml(HalvesScene(left, right, robot));
  const EntityHandle r = sim->space().Find("r");
  const std::string start_engine = sim->EngineOf(r)->id();
  std::vector<double> xs;
  for (int t = 0; t < 60; ++t) {
    sim->Step();
    xs.push_back(sim->space().pose(r.index).position.x());
  }
  // Crossed x = 0 and ended under the other engine.
  EXPECT_NE(sim->EngineOf(r)->id(), start_engine);
  EXPECT_LT(xs.front() * xs.back(), 0.0);
  // Once up to speed (0.01 m per tick), every tick moves it the same amount:
  // no jump in position or speed at the boundary.
  for (size_t t = 10; t < xs.size(); ++t) {
    EXPECT_NEAR(std::abs(xs[t] - xs[t - 1]), 0.01, 1e-3) << "tick " << t + 1 << " x " << xs[t];
  }
  EXPECT_NEAR(sim->space().pose(r.index).position.y(), 0.0, 1e-3);
}

TEST(MultipleEngines, RobotCrossesFromKinematicsToDynamicsSmoothly) {
  ExpectSmoothCrossing("kinematics2d", "dynamics2d", -0.3, 0);
}

TEST(MultipleEngines, RobotCrossesFromDynamicsToKinematicsSmoothly) {
  ExpectSmoothCrossing("kinematics2d", "dynamics2d", 0.3, 180);
}

TEST(MultipleEngines, RobotCrossesBetweenTwoDynamicsEngines) {
  ExpectSmoothCrossing("dynamics2d", "dynamics2d", -0.3, 0);
}

TEST(MultipleEngines, FixedEntitiesAreInEveryEngineTheyTouch) {
  auto sim = testing::LoadXml(HalvesScene("dynamics2d", "dynamics2d", ""));
  const uint32_t north = sim->space().Find("wall_north").index;  // spans both halves
  const uint32_t east = sim->space().Find("wall_east").index;    // east half only
  EXPECT_TRUE(sim->engines()[0]->Owns(north));
  EXPECT_TRUE(sim->engines()[1]->Owns(north));
  EXPECT_FALSE(sim->engines()[0]->Owns(east));
  EXPECT_TRUE(sim->engines()[1]->Owns(east));
}

std::string QuadrantsScene(int robots) {
  std::string engines;
  const double q[4][4] = {{-2, -2, 0, 0}, {0, -2, 2, 0}, {0, 0, 2, 2}, {-2, 0, 0, 2}};
  for (int i = 0; i < 4; ++i) {
    engines += "<dynamics2d id=\"q" + std::to_string(i) + "\">" +
               Boundaries(q[i][0], q[i][1], q[i][2], q[i][3]) + "</dynamics2d>";
  }
  return testing::Experiment(
      "<walls/><distribute><position method=\"uniform\" min=\"-1.8,-1.8,0\" max=\"1.8,1.8,0\"/>"
      "<orientation method=\"uniform\" min=\"0,0,0\" max=\"360,0,0\"/>"
      "<entity quantity=\"" +
          std::to_string(robots) +
          "\" max_trials=\"1000\">"
          "<marxbot id=\"mb\"><controller config=\"dc\"/></marxbot></entity></distribute>",
      "<diffusion id=\"dc\" library=\"diffusion\"><actuators><differential_steering/></actuators>"
      "<sensors><proximity/></sensors><params velocity=\"0.2\"/></diffusion>",
      "4,4,1", "", engines);
}

TEST(MultipleEngines, FourQuadrantsSameHashWhateverTheThreadCountAndRobotsMigrate) {
  const std::string xml = QuadrantsScene(120);
  uint64_t reference = 0;
  for (int threads : {0, 1, 2, 4}) {
    auto sim = testing::LoadXml(xml, {}, threads);
    std::vector<std::string> start;
    for (const auto& id : {"mb0", "mb1", "mb2"})
      start.push_back(sim->EngineOf(sim->space().Find(id))->id());
    size_t migrated = 0;
    std::vector<const PhysicsEngine*> before(sim->space().slots());
    for (uint32_t s = 0; s < sim->space().slots(); ++s)
      before[s] = sim->EngineOf(sim->space().HandleOf(s));
    for (int t = 0; t < 100; ++t) sim->Step();
    for (uint32_t s = 0; s < sim->space().slots(); ++s) {
      if (sim->space().flags(s) & kRobot)
        migrated += sim->EngineOf(sim->space().HandleOf(s)) != before[s];
    }
    EXPECT_GT(migrated, 5u) << "robots should wander across quadrants";
    // Every robot is owned by exactly the engine whose region holds it.
    for (uint32_t s = 0; s < sim->space().slots(); ++s) {
      if (!(sim->space().flags(s) & kRobot)) continue;
      const PhysicsEngine* engine = sim->EngineOf(sim->space().HandleOf(s));
      EXPECT_TRUE(engine->Holds(sim->space().pose(s).position)) << sim->space().id(s);
    }
    const uint64_t hash = sim->StateHash();
    if (threads == 0) reference = hash;
    EXPECT_EQ(hash, reference) << "with " << threads << " threads";
  }
}

// The message loading `engines` (inside <physics_engines>) with one robot at `robot_at`.
std::string EngineError(const std::string& engines, const std::string& robot_at = "-1,0,0") {
  return testing::LoadError(testing::Experiment(
      "<marxbot id=\"r\"><body position=\"" + robot_at + "\"/><controller config=\"c\"/></marxbot>",
      kCruiser, "4,2,1", "", engines));
}

TEST(MultipleEngines, EntityOutsideEveryEngineIsRejected) {
  const std::string m =
      EngineError("<dynamics2d id=\"west\">" + Boundaries(-2, -1, 0, 1) + "</dynamics2d>", "1,0,0");
  EXPECT_NE(
      m.find("<marxbot id=\"r\">: entity 'r' at (1, 0, 0) is inside no engine's <boundaries>"),
      std::string::npos)
      << m;
}

TEST(MultipleEngines, OverlappingEnginesOfOneKindAreRejected) {
  const std::string m =
      EngineError("<dynamics2d id=\"a\">" + Boundaries(-2, -1, 0.5, 1) + "</dynamics2d>" +
                  "<dynamics2d id=\"b\">" + Boundaries(0, -1, 2, 1) + "</dynamics2d>");
  EXPECT_NE(m.find("<dynamics2d id=\"b\">: the region of dynamics2d 'b' overlaps that of "
                   "dynamics2d 'a' (line 1)"),
            std::string::npos)
      << m;
  // Different kinds may overlap; sharing a side is not overlapping.
  EXPECT_EQ(EngineError("<dynamics2d id=\"a\">" + Boundaries(-2, -1, 0.5, 1) + "</dynamics2d>" +
                        "<kinematics2d id=\"b\">" + Boundaries(0, -1, 2, 1) + "</kinematics2d>"),
            "");
  EXPECT_EQ(EngineError("<dynamics2d id=\"a\">" + Boundaries(-2, -1, 0, 1) + "</dynamics2d>" +
                        "<dynamics2d id=\"b\">" + Boundaries(0, -1, 2, 1) + "</dynamics2d>"),
            "");
  // Two engines of one kind without boundaries both claim the whole arena.
  EXPECT_NE(EngineError("<dynamics2d id=\"a\"/><dynamics2d id=\"b\"/>").find("overlaps"),
            std::string::npos);
}

TEST(MultipleEngines, ClockwiseOrSelfCrossingPolygonsAreRejected) {
  const std::string clockwise =
      "<dynamics2d id=\"a\"><boundaries><sides><vertex point=\"-2,-1\"/><vertex point=\"-2,1\"/>"
      "<vertex point=\"2,1\"/><vertex point=\"2,-1\"/></sides></boundaries></dynamics2d>";
  std::string m = EngineError(clockwise);
  EXPECT_NE(m.find("<sides>: the vertices are listed clockwise; list them counter-clockwise"),
            std::string::npos)
      << m;
  const std::string bow_tie =
      "<dynamics2d id=\"a\"><boundaries><sides><vertex point=\"-2,-1\"/><vertex point=\"2,1\"/>"
      "<vertex point=\"2,-1\"/><vertex point=\"-2,1\"/></sides></boundaries></dynamics2d>";
  m = EngineError(bow_tie);
  EXPECT_NE(m.find("<sides>: the polygon is not simple"), std::string::npos) << m;
  const std::string two_points =
      "<dynamics2d id=\"a\"><boundaries><sides><vertex point=\"-2,-1\"/><vertex "
      "point=\"2,1\"/></sides>"
      "</boundaries></dynamics2d>";
  m = EngineError(two_points);
  EXPECT_NE(m.find("at least 3 vertices"), std::string::npos) << m;
  const std::string bad_point =
      "<dynamics2d id=\"a\"><boundaries><sides><vertex "
      "point=\"-2\"/></sides></boundaries></dynamics2d>";
  m = EngineError(bad_point);
  EXPECT_NE(m.find("<vertex> attribute 'point': '-2' is not two finite numbers"), std::string::npos)
      << m;
  const std::string upside_down =
      "<dynamics2d id=\"a\"><boundaries><top height=\"0\"/><bottom height=\"1\"/><sides><vertex "
      "point=\"-2,-1\"/>"
      "<vertex point=\"2,-1\"/><vertex point=\"2,1\"/></sides></boundaries></dynamics2d>";
  m = EngineError(upside_down);
  EXPECT_NE(m.find("bottom height must be below the top height"), std::string::npos) << m;
}

}  // namespace
}  // namespace colony
