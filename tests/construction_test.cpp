// The construction experiments (EXPERIMENTS.md E3) run to the end: the
// marXbot builds the bridge and crosses it, and stacks the tower, as a user
// running experiments/construction_*.xml sees in metrics.csv.
#include <cmath>
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
    EXPECT_LT(o.time, 200) << "seed " << seed;
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

TEST(construction, WithoutTimeTheRunEndsUnfinished) {
  const Outcome o = RunExperiment("construction_tower.xml", 1, {"framework.experiment.length=30"});
  EXPECT_FALSE(o.success);
  EXPECT_EQ(o.time, -1);
}

TEST(construction, BadParametersAreNamed) {
  std::string xml;
  {
    std::ifstream in(COLONY_SOURCE_DIR "/experiments/construction_tower.xml");
    xml.assign(std::istreambuf_iterator<char>(in), {});
  }
  auto with = [&](const std::string& from, const std::string& to) {
    std::string x = xml;
    const size_t at = x.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) x.replace(at, from.size(), to);
    return LoadError(x);
  };
  const std::string two_cubes =
      with("cubes=\"0.25,0.25;0.75,0.25;0.75,-0.25\"", "cubes=\"0.25,0.25;0.75,0.25\"");
  EXPECT_NE(two_cubes.find("a tower takes 3 cubes, the list has 2"), std::string::npos)
      << two_cubes;
  const std::string bad_point = with("site=\"0.5,0\"", "site=\"0.5\"");
  EXPECT_NE(bad_point.find("parameter 'site': '0.5' is not \"x,y\""), std::string::npos)
      << bad_point;
  const std::string bad_task = with("<params task=\"tower\"/>", "<params task=\"roof\"/>");
  EXPECT_NE(bad_task.find("'roof' is not accepted; accepted: bridge, tower"), std::string::npos)
      << bad_task;
}

}  // namespace
}  // namespace colony::testing
