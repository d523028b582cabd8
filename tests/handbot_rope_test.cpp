// The hand-bot benchmark scene does what its comment says: each of its 10
// hand-bots launches its rope, climbs about a metre and comes back down
// (up 10 s, 2 s at the top, down 10 s), among 50 marXbots on the floor
// (controllers/handbot_rope).
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "actuators/rope_launcher/rope_state.h"
#include "core/simulation.h"

namespace colony {
namespace {

TEST(handbot_rope, TheBenchmarksHandBotsClimbAMetreAndComeBackDown) {
  ExperimentOptions options;
  options.file = COLONY_SOURCE_DIR "/experiments/benchmarks/handbots_10_marxbots_50.xml";
  options.overrides = {"framework.experiment.length=30"};
  auto sim = Simulation::Load(options);
  Space& space = sim->space();
  std::vector<uint32_t> handbots;
  for (uint32_t s = 0; s < space.slots(); ++s) {
    if (space.alive(s) && space.Get<RopeState>(s)) handbots.push_back(s);
  }
  ASSERT_EQ(handbots.size(), 10u);
  std::vector<double> highest(handbots.size(), 0.0);
  std::vector<bool> back_down(handbots.size(), false);
  while (!sim->Done()) {
    sim->Step();
    for (size_t k = 0; k < handbots.size(); ++k) {
      const double z = space.pose(handbots[k]).position.z();
      highest[k] = std::max(highest[k], z);
      if (highest[k] > 0.9 && z < 0.02) back_down[k] = true;
    }
  }
  for (size_t k = 0; k < handbots.size(); ++k) {
    EXPECT_NEAR(highest[k], 1.0, 0.03) << space.id(handbots[k]);
    EXPECT_TRUE(back_down[k]) << space.id(handbots[k]) << " came back to the floor";
    EXPECT_TRUE(space.Get<RopeState>(handbots[k])->attached()) << space.id(handbots[k]);
  }
}

}  // namespace
}  // namespace colony
