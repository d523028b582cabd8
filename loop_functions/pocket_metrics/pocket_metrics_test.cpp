// The criteria of seed 004 on hand-made pocket layouts, against values
// computed by hand (metrics.h), and the pocket_metrics loop functions in
// small arenas: the reservoir refill, the end of the run with the final
// criteria, and bad parameters refused with messages naming them.
#include <cmath>
#include <string>
#include <vector>

#include "core/loop_functions.h"
#include "core/plugin_loader.h"
#include "core/registry.h"
#include "entities/objects/pocket.h"
#include "loop_functions/pocket_metrics/metrics.h"
#include "tests/test_util.h"

namespace colony::testing {
namespace {

using namespace colony::pockets;

// n pocket centres spread evenly over [a, b], each in the middle of its share.
std::vector<double> Even(int n, double a, double b) {
  std::vector<double> x;
  for (int k = 0; k < n; ++k) x.push_back(a + (b - a) * (k + 0.5) / n);
  return x;
}

TEST(pocket_metrics, TheFrameFollowsTheTemplateLandmarks) {
  // Four landmarks on a 1 m line at 30 degrees, listed in order.
  const Vec2 dir(std::cos(M_PI / 6), std::sin(M_PI / 6));
  const Vec2 start(0.5, -0.2);
  const std::vector<Vec2> points = {start, start + 0.3 * dir, start + 0.7 * dir, start + dir};
  const auto frame = FrameThrough(points);
  ASSERT_TRUE(frame);
  EXPECT_NEAR(frame->length, 1.0, 1e-12);
  EXPECT_NEAR((frame->origin - start).norm(), 0, 1e-12);
  const Vec2 normal(-dir.y(), dir.x());
  const Vec2 f = frame->ToFrame(start + 0.4 * dir + 0.05 * normal);
  EXPECT_NEAR(f.x(), 0.4, 1e-12);
  EXPECT_NEAR(f.y(), 0.05, 1e-12);
  EXPECT_NEAR(frame->DistanceToSegment(start + 0.4 * dir - 0.05 * normal), 0.05, 1e-12);
  EXPECT_NEAR(frame->DistanceToSegment(start - 0.3 * dir + 0.4 * normal), 0.5, 1e-12);

  EXPECT_FALSE(FrameThrough(std::vector<Vec2>{start}));
  EXPECT_FALSE(FrameThrough(std::vector<Vec2>{start, start + Vec2(0.0001, 0)}));
}

TEST(pocket_metrics, AnEvenRowIsUniformAndAHalfRowDeviatesByHalf) {
  // 30 pockets evenly along 1 m (3.3 cm apart) with the default bandwidth:
  // only the kernels' tails past the ends are lost.
  EXPECT_LT(UniformityDeviation(Even(30, 0, 1), 0, 1, DefaultBandwidth()), 0.03);
  EXPECT_LT(UniformityDeviation(Even(112, 0, 3.5), 0, 3.5, DefaultBandwidth()), 0.02);
  // All the pockets on the first half: f_h is 2 / L there and 0 beyond, f_u
  // is 1 / L, so the integral of |f_h - f_u| is 1 and u_d = 1 / 2.
  EXPECT_NEAR(UniformityDeviation(Even(60, 0, 0.5), 0, 1, 0.01), 0.5, 0.01);
  // All in one heap, h = 1 cm: f_h exceeds f_u = 1 within 2.716 h of the
  // heap (where phi(z) / h = 1), so the common area of f_h and f_u is
  // 2 x 0.02716 + 2 (1 - Phi(2.716)) = 0.0609 and u_d = 1 - 0.0609.
  EXPECT_NEAR(UniformityDeviation(std::vector<double>(10, 0.5), 0, 1, 0.01), 0.9391, 0.001);
  // A 30 cm void in an otherwise even row: f_h is 1 / 0.7 per metre where the
  // pockets are and ~0 in the void, f_u is 1: 0.7 (1 / 0.7 - 1) + 0.3 = 0.6,
  // so u_d is about 0.3.
  // (h = 5 mm, the pockets 5 mm apart: the smoothing of the edges is small.)
  std::vector<double> with_void = Even(70, 0, 0.35);
  for (double x : Even(70, 0.65, 1)) with_void.push_back(x);
  EXPECT_NEAR(UniformityDeviation(with_void, 0, 1, 0.005), 0.3, 0.01);
  EXPECT_GT(UniformityDeviation(with_void, 0, 1, DefaultBandwidth()), 0.25);
}

TEST(pocket_metrics, IntegrityDeviationIsTheSampleStandardDeviationAcross) {
  // Mean 1 cm; deviations -3, -1, 1, 3 cm; sum of squares 20 cm^2 over n - 1 = 3.
  const std::vector<double> across = {-0.02, 0.0, 0.02, 0.04};
  EXPECT_NEAR(IntegrityDeviation(across), std::sqrt(0.002 / 3), 1e-12);
  EXPECT_EQ(IntegrityDeviation(std::vector<double>{0.3}), 0);
}

TEST(pocket_metrics, MaximumGapIsTheLargestCentreToCentreGapBetweenPockets) {
  // Pockets 10 cm apart but for a 30 cm gap, given in any order.
  EXPECT_NEAR(MaximumGap(std::vector<double>{0.6, 0.1, 0.5, 0.0, 0.2}), 0.3, 1e-12);
  // The ends of the structure are not pockets: two pockets in the middle of
  // a 1 m structure are 10 cm apart, whatever lies between them and the ends.
  EXPECT_NEAR(MaximumGap(std::vector<double>{0.4, 0.5}), 0.1, 1e-12);
  EXPECT_EQ(MaximumGap(std::vector<double>{0.4}), 0);
}

TEST(pocket_metrics, SwarmFiguresFollowEquationsFiveOneToFiveFour) {
  // The seed's median single-robot run: 30 pockets in 2486 s, about 83 s each.
  EXPECT_NEAR(AverageIterationTime(2486, 30), 82.8667, 1e-4);
  // xi_d(4) = xi_c(1) / 4.
  EXPECT_DOUBLE_EQ(IdealIterationTime(83, 4), 20.75);
  // 8 marXbots (R = 8.5 cm) in the 4 m x 6 m arena: pi 0.085^2 8 / 24.
  EXPECT_NEAR(SwarmDensity(0.085, 8, 24), 0.0075661, 1e-7);
  // 4 robots taking 25 s per pocket where one took 83 s:
  // 1 - (25 / 83 - 1 / 4) = 0.948795...
  EXPECT_NEAR(Efficiency(25, 83, 4), 1 - (25.0 / 83 - 0.25), 1e-12);
  EXPECT_NEAR(Efficiency(83.0 / 4, 83, 4), 1, 1e-12);
  EXPECT_NEAR(Efficiency(83, 83, 1), 1, 1e-12);
}

// The loop functions, in a 3 m x 2 m arena: four template landmarks along
// y = 0.5 from x = -0.5 to 0.5, a reservoir between two landmarks 0.2 m
// apart at (0, -0.6); `pockets` and `params` added.
std::string Arena(const std::string& pockets, const std::string& params) {
  std::string body;
  for (int k = 0; k < 4; ++k) {
    body += "<landmark id=\"template_" + std::to_string(k) + "\"><body position=\"" +
            std::to_string(-0.5 + k / 3.0) + ",0.5,0\"/></landmark>";
  }
  body +=
      "<landmark id=\"res_a\"><body position=\"-0.1,-0.6,0\"/></landmark>"
      "<landmark id=\"res_b\"><body position=\"0.1,-0.6,0\"/></landmark>";
  return Experiment(body + pockets, "", "3,2,1",
                    "<loop_functions library=\"pocket_metrics\" label=\"pocket_metrics\"><params " +
                        params + "/></loop_functions>");
}

PocketState& StateOf(Simulation& sim, const std::string& id) {
  return *sim.space().Get<PocketState>(sim.space().Find(id).index);
}

TEST(pocket_metrics, ANewPocketAppearsAtTheReservoirOnceTheLastIsPickedUpAndCarriedOff) {
  auto sim =
      LoadXml(Arena("", "reservoirs=\"res_a,res_b\" quota=\"3\" occlusion_threshold=\"50\""));
  Space& space = sim->space();
  // The first pocket lies midway between the reservoir's landmarks, its long
  // axis along the line joining them.
  const uint32_t first = space.Find("supplied_pocket_0").index;
  EXPECT_NEAR((space.pose(first).position.head<2>() - Vec2(0, -0.6)).norm(), 0, 1e-9);
  EXPECT_NEAR(YawOf(space.pose(first).orientation), 0, 1e-9);
  EXPECT_EQ(Metric(*sim, "supplied"), 1);
  EXPECT_DOUBLE_EQ(StateOf(*sim, "supplied_pocket_0").threshold, 0.5);

  // Picked up: no new pocket while the held one is still over the place.
  StateOf(*sim, "supplied_pocket_0").holder = 0;
  sim->Step();
  EXPECT_FALSE(space.Find("supplied_pocket_1").valid());
  // Carried off: a new one appears there.
  space.pose(first).position += Vec3(0, 0.5, 0.05);
  sim->Step();
  const EntityHandle second = space.Find("supplied_pocket_1");
  ASSERT_TRUE(second.valid());
  EXPECT_NEAR((space.pose(second.index).position.head<2>() - Vec2(0, -0.6)).norm(), 0, 1e-9);
  EXPECT_EQ(Metric(*sim, "supplied"), 2);

  // The first pocket dropped in the structure: one deposited.
  StateOf(*sim, "supplied_pocket_0").holder = PocketState::kNobody;
  space.pose(first).position = Vec3(0, 0.45, 0);
  sim->Step();
  EXPECT_EQ(Metric(*sim, "deposited"), 1);
  EXPECT_EQ(Metric(*sim, "uniformity_deviation"), -1);

  // The quota of three: after the third pick-up no fourth pocket comes.
  for (const char* id : {"supplied_pocket_1", "supplied_pocket_2"}) {
    const EntityHandle h = space.Find(id);
    ASSERT_TRUE(h.valid()) << id;
    StateOf(*sim, id).holder = 0;
    space.pose(h.index).position += Vec3(0, 0.5, 0.05);
    sim->Step();
  }
  EXPECT_FALSE(space.Find("supplied_pocket_3").valid());
  EXPECT_EQ(Metric(*sim, "supplied"), 3);
}

TEST(pocket_metrics, NoPocketAppearsUnderARobotAndTheSwarmDensityCountsIt) {
  // A robot standing still just behind the reservoir's pocket.
  const std::string robot =
      "<marxbot id=\"mb\"><body position=\"0,-0.75,0\" orientation=\"90,0,0\"/>"
      "<controller config=\"still\"/></marxbot>";
  const std::string controllers =
      "<diffusion id=\"still\" library=\"diffusion\"><actuators><differential_steering/>"
      "</actuators><sensors><proximity/></sensors><params velocity=\"0\"/></diffusion>";
  std::string xml = Arena(robot, "reservoirs=\"res_a,res_b\" quota=\"2\"");
  xml.replace(xml.find("<controllers>"), 13, "<controllers>" + controllers);
  auto sim = LoadXml(xml);
  Space& space = sim->space();
  const uint32_t mb = space.Find("mb").index;
  // R^2 pi m / A_a with the robot's own radius and the 3 m x 2 m arena.
  const double r = space.geometry(mb).radius;
  EXPECT_NEAR(Metric(*sim, "swarm_density"), M_PI * r * r / 6, 1e-12);

  const uint32_t first = space.Find("supplied_pocket_0").index;
  StateOf(*sim, "supplied_pocket_0").holder = mb;
  space.pose(first).position += Vec3(0, 0.5, 0.05);
  sim->Step();
  EXPECT_FALSE(space.Find("supplied_pocket_1").valid()) << "a pocket appeared under the robot";
  space.pose(mb).position = Vec3(1, -0.75, 0);
  sim->Step();
  EXPECT_TRUE(space.Find("supplied_pocket_1").valid());
}

TEST(pocket_metrics, TheRunEndsWhenTheQuotaIsDepositedWithTheFinalCriteria) {
  // Three pockets already in the structure, 20 then 30 cm apart.
  std::string pockets;
  const double xs[] = {-0.4, -0.2, 0.1};
  const double ys[] = {0.38, 0.40, 0.42};
  for (int k = 0; k < 3; ++k) {
    pockets += "<pocket id=\"p" + std::to_string(k) + "\"><body position=\"" +
               std::to_string(xs[k]) + "," + std::to_string(ys[k]) + ",0\"/></pocket>";
  }
  const auto dir = FreshTempDir("pocket_metrics", "csv");
  const std::string csv = (dir / "pockets.csv").string();
  EXPECT_TRUE(Mentions(LoadError(Arena(pockets, "csv=\"" + csv + "\"")), {"csv", "no folder"}));
  std::filesystem::create_directories(dir);
  auto sim = LoadXml(Arena(pockets, "csv=\"" + csv + "\""));
  sim->Step();
  EXPECT_TRUE(sim->Done());
  EXPECT_EQ(Metric(*sim, "deposited"), 3);
  EXPECT_EQ(Metric(*sim, "supplied"), 0);
  EXPECT_NEAR(Metric(*sim, "maximum_gap"), 0.3, 1e-6);
  EXPECT_NEAR(Metric(*sim, "integrity_deviation"), 0.02, 1e-6);
  EXPECT_GT(Metric(*sim, "uniformity_deviation"), 0.3);
  // All deposited from the start, counted at the end of the first tick; no
  // robots, so no efficiency.
  EXPECT_NEAR(Metric(*sim, "construction_time"), 0.1, 1e-9);
  EXPECT_EQ(Metric(*sim, "efficiency"), -1);
  const std::string text = ReadFile(csv);
  EXPECT_EQ(text.substr(0, text.find('\n')), "id,x,y,z,along,across,occlusion,held,deposited");
  EXPECT_NE(text.find("p2,0.100000,0.420000,0.000000,0.600000,-0.080000"), std::string::npos)
      << text;
}

TEST(pocket_metrics, BadParametersAreRefusedNamingThem) {
  const std::string one = "<pocket id=\"p\"><body position=\"0,0.4,0\"/></pocket>";
  EXPECT_TRUE(Mentions(LoadError(Arena(one, "quota=\"5\"")), {"quota", "no reservoirs"}));
  EXPECT_TRUE(Mentions(LoadError(Arena("", "reservoirs=\"res_a,res_b\"")), {"quota", "required"}));
  EXPECT_TRUE(Mentions(LoadError(Arena(one, "template=\"template_0\"")),
                       {"template", "two landmarks or more"}));
  EXPECT_TRUE(Mentions(LoadError(Arena(one, "template=\"template_0,nowhere\"")),
                       {"template", "nowhere", "no entity"}));
  EXPECT_TRUE(
      Mentions(LoadError(Arena(one, "template=\"template_0,p\"")), {"template", "not a landmark"}));
  EXPECT_TRUE(
      Mentions(LoadError(Arena(one, "template_prefix=\"fence\"")), {"template_prefix", "found 0"}));
  EXPECT_TRUE(Mentions(LoadError(Arena("", "reservoirs=\"res_a\" quota=\"2\"")),
                       {"reservoirs", "not a pair"}));
  EXPECT_TRUE(Mentions(LoadError(Arena("", "reservoirs=\"res_a,res_b\" quota=\"-2\"")), {"quota"}));
  EXPECT_TRUE(Mentions(LoadError(Arena(one, "structure_width=\"-1\"")), {"structure_width"}));
  EXPECT_TRUE(Mentions(LoadError(Arena(one, "robot_radius=\"-0.1\"")), {"robot_radius"}));
  EXPECT_TRUE(Mentions(LoadError(Arena("",
                                       "reservoirs=\"res_a,res_b\" quota=\"2\" "
                                       "structure_width=\"1.2\"")),
                       {"structure_width", "reservoir at (0,-0.6)"}));
  EXPECT_TRUE(
      Mentions(LoadError(Arena(one, "occlusion_threshold=\"120\"")), {"occlusion_threshold"}));
  EXPECT_TRUE(Mentions(LoadError(Arena("", "")), {"reservoirs", "no pockets"}));
  // An L of landmarks is no straight boundary.
  EXPECT_TRUE(Mentions(LoadError(Arena(one, "template=\"template_0,template_3,res_b\"")),
                       {"template", "do not form a straight boundary", "off the line"}));
}

TEST(pocket_metrics, RegisteredParametersMatchTheReadme) {
  ASSERT_EQ(LoadPluginLibrary("pocket_metrics", ""), "");
  const auto* entry = Registry<LoopFunctions>::Get().Find("pocket_metrics");
  ASSERT_NE(entry, nullptr);
  EXPECT_EQ(ReadmeAttributes("loop_functions/pocket_metrics"), entry->info.AttributeNames());
}

}  // namespace
}  // namespace colony::testing
