// Seed 004's barrier construction with one robot (experiments/pockets_single.xml,
// controllers/pocket_builder): the robot builds the whole barrier along the
// boundary within the run's time, the same way at any thread count; and the
// deposition rules of eq. 3.3 and 3.5 on controlled scenes.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "controllers/pocket_builder/deposition.h"
#include "entities/objects/pocket.h"
#include "tests/test_util.h"

namespace colony {
namespace {

using pocket_builder::Point;

bool HaveEngine() { return testing::HaveEngine("kinematics2d"); }

class SingleRobotSeed : public ::testing::TestWithParam<int> {};

TEST_P(SingleRobotSeed, DepositsAllThirtyPocketsAlongTheBoundary) {
  if (!HaveEngine()) GTEST_SKIP() << "kinematics2d not in this build";
  auto sim = testing::LoadExperiment("pockets_single.xml", GetParam());
  while (!sim->Done()) sim->Step();
  EXPECT_EQ(testing::Metric(*sim, "deposited"), 30);
  const double t_c = testing::Metric(*sim, "construction_time");
  EXPECT_GT(t_c, 0) << "the 30th pocket was not deposited within the run (5400 s)";
  // The structure lies along the boundary: pockets within a few centimetres
  // of the line (the seed's median i_d: 2.44 cm), no stretch of the barrier
  // without pockets much longer than two pockets (12 cm each), and spread
  // over its length (u_d 0 = uniform, 0.5 = all on one half).
  EXPECT_GT(testing::Metric(*sim, "integrity_deviation"), 0.0);
  EXPECT_LT(testing::Metric(*sim, "integrity_deviation"), 0.05);
  EXPECT_LT(testing::Metric(*sim, "maximum_gap"), 0.25);
  EXPECT_LT(testing::Metric(*sim, "uniformity_deviation"), 0.3);
  // Every deposited pocket lies on the safe side, near the segment.
  const Space& space = sim->space();
  for (uint32_t s = 0; s < space.slots(); ++s) {
    const auto* pocket = space.alive(s) ? space.Get<PocketState>(s) : nullptr;
    if (pocket == nullptr || pocket->holder != PocketState::kNobody) continue;
    const Vec3 p = space.pose(s).position;
    if (p.x() < 0) continue;  // the reservoir's
    EXPECT_LT(p.x(), 0.85) << space.id(s) << " beyond the boundary";
    EXPECT_GT(p.x(), 0.65) << space.id(s);
    EXPECT_LT(std::abs(p.y()), 0.6) << space.id(s);
  }
}

INSTANTIATE_TEST_SUITE_P(Seeds, SingleRobotSeed, ::testing::Values(1, 2));

TEST(PocketsSingle, SameResultAtAnyThreadCount) {
  if (!HaveEngine()) GTEST_SKIP() << "kinematics2d not in this build";
  std::vector<uint64_t> hashes;
  for (int threads : {0, 1, 2}) {
    auto sim = testing::LoadExperiment("pockets_single.xml", 1, {"loop_functions.params.quota=6"},
                                       threads);
    while (!sim->Done()) sim->Step();
    EXPECT_EQ(testing::Metric(*sim, "deposited"), 6) << threads << " threads";
    hashes.push_back(sim->StateHash());
  }
  EXPECT_EQ(hashes[0], hashes[1]);
  EXPECT_EQ(hashes[0], hashes[2]);
}

// Seed 004's swarm (experiments/pockets_swarm.xml, section 3.4.4), shortened:
// 3 robots and a quota of 15 pockets. The robots share the double path and
// the reservoirs; while the reservoirs still supply pockets, none of them
// ever stands still for two minutes (robots waiting on each other would; once
// the 15th is supplied, robots without one wait at empty reservoirs, as they
// should), and all 15 pockets land along the boundary.
TEST(PocketsSwarm, ThreeRobotsDepositTheirQuotaWithoutDeadlock) {
  if (!HaveEngine()) GTEST_SKIP() << "kinematics2d not in this build";
  for (int seed : {1, 2}) {
    auto sim = testing::LoadExperiment(
        "pockets_swarm.xml", seed,
        {"arena.distribute.entity.quantity=3", "loop_functions.params.quota=15"});
    const Space& space = sim->space();
    std::vector<uint32_t> robots;
    for (uint32_t s = 0; s < space.slots(); ++s) {
      if (space.alive(s) && (space.flags(s) & kRobot)) robots.push_back(s);
    }
    ASSERT_EQ(robots.size(), 3u);
    const int still_limit = 1200;  // ticks: 120 s
    std::vector<Vec3> last(robots.size());
    std::vector<int> still(robots.size(), 0);
    for (size_t i = 0; i < robots.size(); ++i) last[i] = space.pose(robots[i]).position;
    while (!sim->Done()) {
      sim->Step();
      if (sim->tick() % 10 != 0) continue;
      if (testing::Metric(*sim, "supplied") >= 15) break;
      for (size_t i = 0; i < robots.size(); ++i) {
        const Vec3 p = space.pose(robots[i]).position;
        still[i] = (p - last[i]).norm() < 0.01 ? still[i] + 10 : 0;
        last[i] = p;
        ASSERT_LT(still[i], still_limit)
            << "seed " << seed << ": " << space.id(robots[i])
            << " stood still for 120 s at t = " << sim->tick() / 10.0 << " s";
      }
    }
    while (!sim->Done()) sim->Step();
    EXPECT_EQ(testing::Metric(*sim, "deposited"), 15) << "seed " << seed;
    EXPECT_GT(testing::Metric(*sim, "construction_time"), 0) << "seed " << seed;
    EXPECT_LT(testing::Metric(*sim, "integrity_deviation"), 0.05) << "seed " << seed;
  }
}

TEST(PocketsSwarm, SameResultAtAnyThreadCount) {
  if (!HaveEngine()) GTEST_SKIP() << "kinematics2d not in this build";
  std::vector<uint64_t> hashes;
  for (int threads : {0, 1, 2}) {
    auto sim = testing::LoadExperiment(
        "pockets_swarm.xml", 1,
        {"arena.distribute.entity.quantity=3", "loop_functions.params.quota=8"}, threads);
    while (!sim->Done()) sim->Step();
    EXPECT_EQ(testing::Metric(*sim, "deposited"), 8) << threads << " threads";
    hashes.push_back(sim->StateHash());
  }
  EXPECT_EQ(hashes[0], hashes[1]);
  EXPECT_EQ(hashes[0], hashes[2]);
}

// The boundary 35 cm ahead of the robot, across its heading, and pockets
// piling up on it in front of the robot: the more influential pockets in
// view, the less likely eq. 3.3 picks this place along the boundary.
TEST(DepositionRules, YProbabilityFallsAsInfluentialPocketsGrow) {
  const auto frame = pocket_builder::FrameOfLine({0.35, -0.5}, {0.35, 0.5});
  EXPECT_NEAR(frame.psi_p, 0.0, 1e-12);
  EXPECT_NEAR(frame.distance, 0.35, 1e-12);
  const double k1 = 0.02, alpha = 0.5, delta1 = 0.08;
  std::vector<Point> seen = {{0.3, 0.4}, {0.3, -0.3}};  // far along the boundary: not influential
  std::vector<double> p;
  for (int added = 0; added <= 6; ++added) {
    std::vector<Point> in_frame;
    for (const Point& q : seen) in_frame.push_back(frame.ToInstant(q));
    const int n_f = pocket_builder::CountInfluential(in_frame, delta1);
    EXPECT_EQ(n_f, added);
    p.push_back(pocket_builder::YDepositionProbability(n_f, k1, alpha));
    seen.push_back({0.3, -0.07 + 0.025 * added});  // one more within 8 cm of the robot's y
  }
  EXPECT_DOUBLE_EQ(p[0], k1) << "nothing around: k1";
  for (size_t i = 1; i < p.size(); ++i) {
    EXPECT_LT(p[i], p[i - 1]) << i << " influential pockets";
    EXPECT_NEAR(p[i], k1 / (1 + alpha * alpha * i * i), 1e-15);
  }
  EXPECT_LT(p[6], p[0] / 9) << "six pockets in view: a tenth of k1";
}

// Seen from a robot turned 90 degrees (the boundary on its left), the same
// pockets are influential: the rule works in the instantaneous frame.
TEST(DepositionRules, InfluentialPocketsDoNotDependOnTheRobotsHeading) {
  const auto frame = pocket_builder::FrameOfLine({-0.5, 0.35}, {0.5, 0.35});
  EXPECT_NEAR(frame.psi_p, M_PI / 2, 1e-12);
  const Point q = frame.ToInstant({0.05, 0.3});  // 30 cm towards the boundary, 5 cm to the right
  EXPECT_NEAR(q.x, 0.3, 1e-12);
  EXPECT_NEAR(q.y, -0.05, 1e-12);
  EXPECT_EQ(pocket_builder::CountInfluential({q}, 0.08), 1);
  EXPECT_EQ(pocket_builder::CountInfluential({q}, 0.04), 0);
}

// Eq. 3.4-3.5: the x-deposition probability is k2 where the influential
// pockets lie under the manipulator, and falls off with sigma either side.
TEST(DepositionRules, XProbabilityPeaksOverThePockets) {
  const double k2 = 0.2, sigma = 0.03, d_m = 0.12;
  int n_f = 0;
  const std::vector<Point> pockets = {{0.11, 0.02}, {0.13, -0.03}, {0.4, 0.2}};
  const double mu = pocket_builder::MeanInfluentialX(pockets, 0.06, d_m, n_f);
  EXPECT_EQ(n_f, 2);
  EXPECT_NEAR(mu, 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(pocket_builder::XDepositionProbability(mu, k2, sigma), k2);
  EXPECT_NEAR(pocket_builder::XDepositionProbability(sigma, k2, sigma), k2 / M_E, 1e-12);
  EXPECT_LT(pocket_builder::XDepositionProbability(0.2, k2, sigma), 1e-10);
  EXPECT_EQ(pocket_builder::MeanInfluentialX({{0.3, 0.3}}, 0.06, d_m, n_f), 0.0);
  EXPECT_EQ(n_f, 0);
}

// `colony run --out DIR` leaves pockets.csv beside metrics.csv: one row per
// pocket, the 30 the file declares and the one the reservoir supplies.
TEST(PocketsRunFolder, FinalPositionsGoToTheRunFolder) {
  const auto out = testing::FreshTempDir("colony_pockets_test", "csv");
  const std::string command = std::string(COLONY_EXE) +
                              " run " COLONY_SOURCE_DIR
                              "/experiments/pockets_single.xml --quiet "
                              "--set framework.experiment.length=3 --out " +
                              out.string() + " 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  const std::string csv = testing::ReadFile(out / "pockets.csv");
  ASSERT_EQ(csv.rfind("id,x,y,z,along,across,occlusion,held,deposited\n", 0), 0u) << csv;
  size_t rows = 0;
  for (char c : csv) rows += c == '\n' ? 1 : 0;
  EXPECT_GE(rows, 2u) << csv;  // the header and at least the reservoir's pocket
  std::filesystem::remove_all(out);
}

}  // namespace
}  // namespace colony
