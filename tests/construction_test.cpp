// The construction experiments (EXPERIMENTS.md E3) run to the end: the
// marXbot builds the bridge and crosses it, and stacks the tower, as a user
// running experiments/construction_*.xml sees in metrics.csv; and the
// controller is never told where the cubes are.
#include <cmath>
#include <fstream>
#include <regex>
#include <string>

#include "tests/test_util.h"

namespace colony::testing {
namespace {

struct Outcome {
  bool success = false, failed = false;
  double time = -1;
  std::unique_ptr<Simulation> sim;
};

Outcome RunExperiment(const std::string& file, uint64_t seed,
                      std::vector<std::string> overrides = {}) {
  Outcome o;
  o.sim = LoadExperiment(file, seed, std::move(overrides));
  while (!o.sim->Done()) o.sim->Step();
  o.success = Metric(*o.sim, "success") == 1;
  o.failed = Metric(*o.sim, "failed") == 1;
  o.time = Metric(*o.sim, "outcome_time");
  return o;
}

TEST(construction, BridgeIsBuiltAndCrossed) {
  for (uint64_t seed : {1, 2}) {
    const Outcome o = RunExperiment("construction_bridge.xml", seed);
    EXPECT_TRUE(o.success) << "seed " << seed;
    EXPECT_FALSE(o.failed) << "seed " << seed;
    EXPECT_GT(o.time, 30) << "seed " << seed;
    EXPECT_EQ(Metric(*o.sim, "cubes_in_ditch"), 2) << "seed " << seed;
    // The robot stands on the far side of the ditch, on the floor.
    const Vec3 robot = o.sim->space().pose(o.sim->space().Find("builder").index).position;
    EXPECT_GT(robot.x(), 0.12) << "seed " << seed;
    EXPECT_GT(robot.z(), -0.01) << "seed " << seed;
  }
}

TEST(construction, TowerOfThreeCubesIsStacked) {
  for (uint64_t seed : {1, 2}) {
    const Outcome o = RunExperiment("construction_tower.xml", seed);
    EXPECT_TRUE(o.success) << "seed " << seed;
    EXPECT_EQ(Metric(*o.sim, "tower_height"), 3) << "seed " << seed;
    // The top cube stands two cube heights up.
    double highest = 0;
    const Space& space = o.sim->space();
    for (uint32_t c : space.OfType(const_cast<Space&>(space).TypeId("cube"))) {
      highest = std::max(highest, space.pose(c).position.z());
    }
    EXPECT_NEAR(highest, 0.12, 0.01) << "seed " << seed;
  }
}

std::string ReadExperiment(const std::string& name);

TEST(construction, TheTowerIsFoundWhereItStandsNotWhereTheMapSays) {
  // The tower's first cube already stands 4 cm beyond and 3.5 cm aside of
  // the map's site (tower_built="1": the map knows the tower has one cube,
  // not exactly where). The robot finds its top with the camera and lines
  // up on it, and stops on the proximity ring: the two cubes it brings go on
  // top, level. Stacked by the robot's own pose over the site, as before,
  // the second cube lands half off the first and slides down (the run ends
  // unfinished with a tower of 1).
  std::string xml = ReadExperiment("construction_tower.xml");
  const std::string params = "site=\"0.5,0\" speed=\"0.1\"";
  const std::string first_cube = "    <cube id=\"cube_0\">";
  ASSERT_NE(xml.find(params), std::string::npos);
  ASSERT_NE(xml.find(first_cube), std::string::npos);
  xml.replace(xml.find(params), params.size(), params + " tower_built=\"1\"");
  xml.insert(xml.find(first_cube),
             "    <cube id=\"base\"><body position=\"0.54,0.035,0\"/></cube>\n");
  auto sim = LoadXml(xml);
  while (!sim->Done()) sim->Step();
  EXPECT_EQ(Metric(*sim, "success"), 1);
  EXPECT_EQ(Metric(*sim, "tower_height"), 3);
  EXPECT_EQ(Metric(*sim, "cubes_tilted"), 0);
  // The top cube stands two cube heights up, over the first one.
  const Space& space = sim->space();
  Vec3 top(0, 0, 0);
  for (uint32_t c : space.OfType(const_cast<Space&>(space).TypeId("cube"))) {
    if (space.pose(c).position.z() > top.z()) top = space.pose(c).position;
  }
  EXPECT_NEAR(top.z(), 0.12, 0.01);
  EXPECT_NEAR(top.x(), 0.54, 0.015);
  EXPECT_NEAR(top.y(), 0.035, 0.015);
}

TEST(construction, AJammedBridgeCubeIsSeenAndMended) {
  // Told the ditch is 10 cm wide (it is 7), the robot lets the first cube go
  // 1.5 cm beyond the ditch's middle: it catches the far edge and stays
  // across it, tilted, sticking up out of the ditch. The robot sees it with
  // the manipulator's IR sensors and goes for it again with the magnet; the
  // cube, pushed off the edge, drops into the ditch (on its side, as level
  // as upright), and the bridge is finished and crossed. Without the check
  // and the mending the robot stops before the jammed cube (it does not
  // cross a bridge that is not whole) and the run ends unfinished.
  const Outcome o = RunExperiment("construction_bridge.xml", 1,
                                  {"controllers.construction.params.ditch_width=0.1"});
  EXPECT_TRUE(o.success);
  EXPECT_FALSE(o.failed);
  EXPECT_EQ(Metric(*o.sim, "cubes_in_ditch"), 2);
  EXPECT_EQ(Metric(*o.sim, "cubes_tilted"), 0);
  EXPECT_GT(PositionOf(*o.sim, "builder").x(), 0.12);
}

TEST(construction, WithoutTimeTheRunEndsUnfinished) {
  const Outcome o = RunExperiment("construction_tower.xml", 1, {"framework.experiment.length=30"});
  EXPECT_FALSE(o.success);
  EXPECT_EQ(o.time, -1);
}

std::string ReadExperiment(const std::string& name) {
  std::ifstream in(std::string(COLONY_SOURCE_DIR) + "/experiments/" + name);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(construction, NoExperimentTellsTheControllerWhereTheCubesAre) {
  // The map only (regions, the ditch, the sites): no <params> of any
  // construction experiment names a cube's place, in any form.
  for (const std::string name :
       {"construction_bridge.xml", "construction_tower.xml", "construction_remote.xml"}) {
    const std::string xml = ReadExperiment(name);
    ASSERT_FALSE(xml.empty()) << name;
    std::vector<std::string> params;
    const std::regex params_element("<params[^>]*>");
    for (std::sregex_iterator it(xml.begin(), xml.end(), params_element), end; it != end; ++it) {
      params.push_back(it->str());
    }
    ASSERT_EQ(params.size(), 2u) << name;  // the controller's and the loop functions'
    const std::regex cube("<cube id=\"[^\"]*\"><body position=\"([^,]+),([^,]+),[^\"]*\"");
    int cubes = 0;
    for (std::sregex_iterator it(xml.begin(), xml.end(), cube), end; it != end; ++it, ++cubes) {
      const double x = std::stod((*it)[1]), y = std::stod((*it)[2]);
      const std::regex pair("(-?[0-9.]+),(-?[0-9.]+)");
      for (const std::string& p : params) {
        for (std::sregex_iterator n(p.begin(), p.end(), pair), e; n != e; ++n) {
          const double px = std::stod((*n)[1]), py = std::stod((*n)[2]);
          EXPECT_FALSE(std::abs(px - x) < 0.03 && std::abs(py - y) < 0.03)
              << name << ": " << p << " names the place of the cube at " << x << "," << y;
        }
      }
    }
    EXPECT_GE(cubes, 2) << name;
    for (const std::string& p : params) {
      EXPECT_EQ(p.find("cubes="), std::string::npos) << name << ": " << p;
    }
  }
  // And the controller does not take them: a cubes parameter is refused.
  std::string xml = ReadExperiment("construction_bridge.xml");
  xml.replace(xml.find("<params task=\"bridge\""), 21,
              "<params task=\"bridge\" cubes=\"-0.45,0.25;-0.45,-0.25\"");
  EXPECT_TRUE(Mentions(LoadError(xml), {"<params> attribute 'cubes'", "not read by controller"}));
}

TEST(construction, RemoteCubesBridgeIsBuiltFirst) {
  // Shortened: the first 300 s of the remote-cubes task (the whole runs are
  // in docs/construction.md): the two local cubes fill the ditch, flat, and
  // the robot has crossed into the region of the remote cubes. Seed 2: the
  // magnet holds the second cube 1.7 cm off its middle; unless the robot
  // sees that in its image and drives that much aside, the cube lands on
  // the first one's edge and jams, tilted.
  for (uint64_t seed : {2}) {
    const Outcome o =
        RunExperiment("construction_remote.xml", seed, {"framework.experiment.length=300"});
    EXPECT_FALSE(o.failed) << "seed " << seed;
    EXPECT_EQ(Metric(*o.sim, "cubes_in_ditch"), 2) << "seed " << seed;
    EXPECT_EQ(Metric(*o.sim, "cubes_tilted"), 0) << "seed " << seed;
    EXPECT_GT(PositionOf(*o.sim, "builder").x(), 0.12) << "seed " << seed;
  }
}

TEST(construction, BadParametersAreNamed) {
  const std::string xml = ReadExperiment("construction_tower.xml");
  auto with = [&](const std::string& from, const std::string& to) {
    std::string x = xml;
    const size_t at = x.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) x.replace(at, from.size(), to);
    return LoadError(x);
  };
  const std::string bad_region =
      with("cube_region=\"0.06,-0.55,0.95,0.55\"", "cube_region=\"0.95,-0.55,0.06,0.55\"");
  EXPECT_NE(bad_region.find("parameter 'cube_region': '0.95,-0.55,0.06,0.55' is not "
                            "\"x0,y0,x1,y1\" with x0 < x1 and y0 < y1"),
            std::string::npos)
      << bad_region;
  const std::string bad_point = with("site=\"0.5,0\"", "site=\"0.5\"");
  EXPECT_NE(bad_point.find("parameter 'site': '0.5' is not \"x,y\""), std::string::npos)
      << bad_point;
  const std::string bad_task = with("<params task=\"tower\"/>", "<params task=\"roof\"/>");
  EXPECT_NE(bad_task.find("'roof' is not accepted; accepted: bridge, tower, remote"),
            std::string::npos)
      << bad_task;
  const std::string bad_built = with("site=\"0.5,0\"", "site=\"0.5,0\" tower_built=\"3\"");
  EXPECT_NE(bad_built.find("parameter 'tower_built': 3 is out of range; accepted: [0, 2]"),
            std::string::npos)
      << bad_built;
  const std::string no_camera = with("<camera preset=\"marxbot_front_camera\"/>", "");
  EXPECT_NE(no_camera.find("camera"), std::string::npos) << no_camera;
}

}  // namespace
}  // namespace colony::testing
