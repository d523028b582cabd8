// The guidance experiment (experiments/eyebot_guidance.xml): eye-bots in
// pointmass3d find the target from the ceiling and mark it with their
// lasers; foot-bots in kinematics2d see the spot and gather at the target.
// And the mixed-engines scene's determinism across thread counts.
#include "entities/eyebot/eyebot.h"
#include "tests/test_util.h"

namespace colony {
namespace {

bool HaveEngines() {
  return testing::HaveEngine("pointmass3d") && testing::HaveEngine("kinematics2d");
}

class GuidanceSeed : public ::testing::TestWithParam<int> {};

TEST_P(GuidanceSeed, FootbotsReachTheMarkedTarget) {
  if (!HaveEngines()) GTEST_SKIP() << "pointmass3d or kinematics2d not in this build";
  auto sim = testing::LoadExperiment("eyebot_guidance.xml", GetParam());
  const Space& space = sim->space();
  // Every eye-bot is in pointmass3d, every foot-bot in kinematics2d.
  for (uint32_t s = 0; s < space.slots(); ++s) {
    if (!space.alive(s) || !(space.flags(s) & kRobot)) continue;
    const std::string engine = sim->EngineOf(space.HandleOf(s))->label();
    EXPECT_EQ(engine, space.Get<PanTiltState>(s) ? "pointmass3d" : "kinematics2d") << space.id(s);
  }
  while (!sim->Done()) sim->Step();
  const double mark = testing::Metric(*sim, "mark_time");
  const double reach = testing::Metric(*sim, "reach_time");
  EXPECT_GT(mark, 0) << "no eye-bot marked the target";
  EXPECT_GT(reach, mark) << "5 foot-bots did not reach the target after it was marked";
  EXPECT_EQ(testing::Metric(*sim, "success"), 1);
  // The foot-bots there are on the target's side of the arena, and an
  // eye-bot hangs from the ceiling with its laser on the target.
  const Vec3 target = testing::PositionOf(*sim, "target");
  int near = 0;
  bool marking = false;
  for (uint32_t s = 0; s < space.slots(); ++s) {
    if (!space.alive(s) || !(space.flags(s) & kRobot)) continue;
    if (const auto* head = space.Get<PanTiltState>(s)) {
      const auto spot = CastLaser(space, s);
      if (head->laser_on && spot && (spot->point - target).head<2>().norm() < 0.2) {
        marking = true;
        EXPECT_TRUE(space.Get<CeilingAttachmentState>(s)->attached) << space.id(s);
      }
    } else if ((space.pose(s).position - target).head<2>().norm() < 0.6) {
      ++near;
    }
  }
  EXPECT_TRUE(marking);
  EXPECT_GE(near, 5);
}

INSTANTIATE_TEST_SUITE_P(Seeds, GuidanceSeed, ::testing::Values(1, 2, 3));

TEST(EyebotGuidance, BadParametersAreRefused) {
  if (!HaveEngines()) GTEST_SKIP() << "pointmass3d or kinematics2d not in this build";
  auto error = [](const std::string& override) {
    try {
      testing::LoadExperiment("eyebot_guidance.xml", 1, {override});
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_TRUE(testing::Mentions(error("loop_functions.params.k=11"),
                                {"<params>", "'k'", "11 foot-bots", "has 10"}));
  EXPECT_TRUE(testing::Mentions(error("loop_functions.params.k=2.5"), {"not a whole number"}));
  EXPECT_TRUE(testing::Mentions(error("controllers.eyebot_guide[guide].params.tilts=25,x"),
                                {"'tilts'", "'x' is not a finite number"}));
  EXPECT_TRUE(testing::Mentions(error("controllers.eyebot_guide[guide].params.tilts=25,95"),
                                {"'tilts'", "95 is out of range"}));
  EXPECT_TRUE(testing::Mentions(error("controllers.eyebot_guide[guide].params.area=1,2,3"),
                                {"'area'", "4 numbers"}));
  EXPECT_TRUE(testing::Mentions(
      error("controllers.footbot_follow_spot[follower].params.spot_color=reddish"),
      {"'spot_color'", "'reddish' is not a colour"}));
}

// Eye-bots flying in pointmass3d over foot-bots in kinematics2d (the
// mixed-engines benchmark's scene, smaller): the same run whatever the
// thread count, with enough robots that every thread has work.
TEST(MixedEngines, SameHashAtEveryThreadCount) {
  if (!HaveEngines()) GTEST_SKIP() << "pointmass3d or kinematics2d not in this build";
  const std::string xml = R"(<colony>
  <framework><experiment length="20" ticks_per_second="10" random_seed="3"/></framework>
  <controllers>
    <diffusion id="dc" library="diffusion">
      <actuators><differential_steering/></actuators><sensors><proximity/></sensors>
      <params velocity="0.1"/>
    </diffusion>
    <eyebot_waypoints id="wp" library="eyebot_waypoints">
      <actuators><eyebot_propulsion/></actuators><sensors><positioning/></sensors>
      <params area="-6,-6,0.5,6,6,2"/>
    </eyebot_waypoints>
  </controllers>
  <arena size="14,14,3" center="0,0,1.5">
    <ceiling height="2.5"/>
    <walls thickness="0.1" height="0.5"/>
    <distribute>
      <position method="uniform" min="-6.8,-6.8,0" max="6.8,6.8,0"/>
      <orientation method="uniform" min="0,0,0" max="360,0,0"/>
      <entity quantity="400" max_trials="100"><marxbot id="mb"><controller config="dc"/></marxbot></entity>
    </distribute>
    <distribute>
      <position method="uniform" min="-6,-6,0.5" max="6,6,2"/>
      <orientation method="uniform" min="0,0,0" max="360,0,0"/>
      <entity quantity="150" max_trials="100"><eyebot id="eb"><controller config="wp"/></eyebot></entity>
    </distribute>
  </arena>
  <physics_engines>
    <kinematics2d id="ground"/>
    <pointmass3d id="air" entities="eyebot"/>
  </physics_engines>
</colony>)";
  std::vector<uint64_t> hashes;
  for (int threads : {0, 1, 2, 4}) {
    auto sim = testing::LoadXml(xml, {}, threads);
    // An eye-bot flies from waypoint to waypoint meanwhile, at up to 2 m/s.
    double flown = 0;
    while (!sim->Done()) {
      const Vec3 before = testing::PositionOf(*sim, "eb0");
      sim->Step();
      flown += (testing::PositionOf(*sim, "eb0") - before).norm();
    }
    EXPECT_GT(flown, 10.0);
    hashes.push_back(sim->StateHash());
  }
  for (size_t i = 1; i < hashes.size(); ++i) EXPECT_EQ(hashes[i], hashes[0]) << "run " << i;
}

}  // namespace
}  // namespace colony
