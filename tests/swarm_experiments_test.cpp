// The swarm experiments (experiments/flocking.xml, aggregation.xml,
// foraging.xml) do what a user runs them for: a flock orders itself, robots
// gather into clusters, items come back to the nest and keep coming. Runs are
// shortened or shrunk to keep CI time to seconds.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "core/loop_functions.h"
#include "tests/test_util.h"

namespace colony {
namespace {

using testing::Metric;

const std::string kFlocking = COLONY_SOURCE_DIR "/experiments/flocking.xml";
const std::string kAggregation = COLONY_SOURCE_DIR "/experiments/aggregation.xml";
const std::string kForaging = COLONY_SOURCE_DIR "/experiments/foraging.xml";

std::unique_ptr<Simulation> Load(const std::string& file, std::vector<std::string> overrides,
                                 std::optional<int> threads = std::nullopt) {
  ExperimentOptions options;
  options.file = file;
  options.overrides = std::move(overrides);
  options.threads = threads;
  return Simulation::Load(options);
}

void RunUntil(Simulation& sim, double seconds) {
  while (!sim.Done() && sim.time() < seconds - 1e-9) sim.Step();
}

// The message of the ConfigError loading `file` with `overrides` raises.
std::string LoadError(const std::string& file, std::vector<std::string> overrides) {
  try {
    Load(file, std::move(overrides));
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

bool Mentions(const std::string& text, std::initializer_list<const char*> parts) {
  for (const char* p : parts) {
    if (text.find(p) == std::string::npos) {
      ADD_FAILURE() << "'" << p << "' not in:\n" << text;
      return false;
    }
  }
  return true;
}

// The first-column names (`name`) of the table that follows the line
// "`label` parameters:" in docs/swarm-experiments.md.
std::vector<std::string> DocumentedParameters(const std::string& label) {
  std::istringstream doc(testing::ReadFile(COLONY_SOURCE_DIR "/docs/swarm-experiments.md"));
  std::vector<std::string> names;
  std::string line;
  bool in_table = false;
  while (std::getline(doc, line)) {
    if (line.rfind("`" + label + "` ", 0) == 0 && line.find("parameters:") != std::string::npos) {
      in_table = true;
      continue;
    }
    if (!in_table) continue;
    if (line.empty() && !names.empty()) break;
    if (line.rfind("| `", 0) != 0) continue;
    const size_t end = line.find('`', 3);
    names.push_back(line.substr(3, end - 3));
  }
  return names;
}

// What `colony query LABEL` lists for loop functions is what the docs say.
void ExpectDocumented(const std::string& file, const std::string& label) {
  Load(file, {});  // loads the plugin library
  const auto* entry = Registry<LoopFunctions>::Get().Find(label);
  ASSERT_NE(entry, nullptr) << label;
  EXPECT_EQ(entry->info.AttributeNames(), DocumentedParameters(label)) << label;
}

TEST(SwarmExperiments, LoopFunctionParametersMatchTheDocs) {
  ExpectDocumented(kFlocking, "flocking_metrics");
  ExpectDocumented(kAggregation, "aggregation_metrics");
  ExpectDocumented(kForaging, "foraging");
}

// --- Flocking ---------------------------------------------------------------------------------

// A smaller flock than the file's, for a few seconds of CI time.
const std::vector<std::string> kSmallFlock = {
    "arena.distribute.entity.quantity=16", "arena.distribute.position.min=-0.9,-0.9,0",
    "arena.distribute.position.max=0.9,0.9,0", "framework.experiment.length=30"};

TEST(Flocking, PolarisationRisesFromRandomToOrdered) {
  auto sim = Load(kFlocking, kSmallFlock);
  ASSERT_EQ(sim->robot_count(), 16u);
  const double start = Metric(*sim, "polarisation");
  EXPECT_LT(start, 0.5) << "random headings should not start aligned";
  RunUntil(*sim, 30);
  EXPECT_GT(Metric(*sim, "polarisation"), 0.9);
  // Still one flock, not scattered robots.
  EXPECT_EQ(Metric(*sim, "groups"), 1);
  EXPECT_EQ(Metric(*sim, "largest_group_fraction"), 1);
}

TEST(Flocking, TheFlockMovesAsOne) {
  auto sim = Load(kFlocking, kSmallFlock);
  RunUntil(*sim, 30);
  // Every robot's heading is within 30 degrees of the flock's mean heading,
  // and the flock's centre has travelled.
  const Space& space = sim->space();
  double cx = 0, cy = 0, hx = 0, hy = 0;
  int n = 0;
  for (uint32_t i = 0; i < space.slots(); ++i) {
    if (!space.alive(i) || !(space.flags(i) & kRobot)) continue;
    const double yaw = YawOf(space.pose(i).orientation);
    hx += std::cos(yaw);
    hy += std::sin(yaw);
    cx += space.pose(i).position.x();
    cy += space.pose(i).position.y();
    ++n;
  }
  const double mean = std::atan2(hy, hx);
  for (uint32_t i = 0; i < space.slots(); ++i) {
    if (!space.alive(i) || !(space.flags(i) & kRobot)) continue;
    EXPECT_LT(std::abs(WrapAngle(YawOf(space.pose(i).orientation) - mean)), M_PI / 6)
        << space.id(i);
  }
  EXPECT_GT(std::hypot(cx / n, cy / n), 1.0) << "the flock's centre should have moved";
}

TEST(Flocking, NeighboursKeepTheirDistance) {
  auto sim = Load(kFlocking, kSmallFlock);
  RunUntil(*sim, 30);
  // Lennard-Jones-like spacing (target 0.4 m): neither piled up nor drifting apart.
  const double nn = Metric(*sim, "mean_nn_distance");
  EXPECT_GT(nn, 0.25);
  EXPECT_LT(nn, 0.6);
}

// 300 robots, so that 2 threads really share the work (each parallel loop
// hands out chunks of 64 robots), for 10 s.
uint64_t FinalHash(int threads, const std::string& occlusions) {
  auto sim = Load(kFlocking,
                  {"arena.distribute.entity.quantity=300", "arena.distribute.position.min=-4,-4,0",
                   "arena.distribute.position.max=4,4,0", "framework.experiment.length=10",
                   "media.range_and_bearing[rab].check_occlusions=" + occlusions},
                  threads);
  while (!sim->Done()) sim->Step();
  return sim->StateHash();
}

TEST(Flocking, SameFinalHashWith0And1And2Threads) {
  for (const std::string occlusions : {"true", "false"}) {
    const uint64_t reference = FinalHash(0, occlusions);
    EXPECT_EQ(FinalHash(1, occlusions), reference) << "check_occlusions=" << occlusions;
    EXPECT_EQ(FinalHash(2, occlusions), reference) << "check_occlusions=" << occlusions;
  }
}

TEST(Flocking, PayloadTooSmallForTheHeadingIsRejected) {
  const std::string message =
      LoadError(kFlocking, {"controllers.flocking[fc].actuators.range_and_bearing.data_size=1"});
  EXPECT_TRUE(Mentions(message, {"flocking.xml:", "controller 'flocking' failed to start",
                                 "payload holds 1 byte(s)", "data_size"}));
}

TEST(Flocking, BadParameterIsRejectedWithItsLine) {
  const std::string message =
      LoadError(kFlocking, {"controllers.flocking[fc].params.target_distance=-1"});
  EXPECT_TRUE(Mentions(
      message, {"flocking.xml:", "<params>", "attribute 'target_distance'", "-1 is out of range"}));
}

// --- Aggregation ------------------------------------------------------------------------------

TEST(Aggregation, LargestClusterGrows) {
  auto sim = Load(kAggregation, {});
  const double start = Metric(*sim, "largest_cluster_fraction");
  RunUntil(*sim, 60);
  const double minute = Metric(*sim, "largest_cluster_fraction");
  RunUntil(*sim, 600);
  const double end = Metric(*sim, "largest_cluster_fraction");
  EXPECT_LT(start, 0.2) << "robots placed at random should not start aggregated";
  EXPECT_GT(end, start + 0.25);
  EXPECT_GT(end, minute);
  EXPECT_LE(Metric(*sim, "clusters"), 3);
  // Most robots end up in a cluster, and most of them are staying.
  EXPECT_GT(Metric(*sim, "clustered_fraction"), 0.6);
  EXPECT_LT(Metric(*sim, "moving_fraction"), 0.4);
}

TEST(Aggregation, WithoutNeighboursTheyDoNotStay) {
  // With no pull from neighbours (join_slope 0) robots stop only
  // spontaneously and leave soon: no large cluster forms.
  auto sim = Load(kAggregation, {"controllers.aggregation[ac].params.join_slope=0"});
  RunUntil(*sim, 600);
  EXPECT_LT(Metric(*sim, "largest_cluster_fraction"), 0.2);
  EXPECT_GT(Metric(*sim, "moving_fraction"), 0.8);
}

TEST(Aggregation, ImpossibleProbabilityIsRejected) {
  const std::string message =
      LoadError(kAggregation, {"controllers.aggregation[ac].params.join_max=0.9999"});
  EXPECT_TRUE(Mentions(message, {"aggregation.xml:", "attribute 'join_max'", "must be <= 1"}));
}

// --- Foraging ---------------------------------------------------------------------------------

TEST(Foraging, ItemsComeBackAndKeepComing) {
  auto sim = Load(kForaging, {});
  EXPECT_EQ(Metric(*sim, "items_returned"), 0);
  RunUntil(*sim, 100);
  const double early = Metric(*sim, "items_returned");
  RunUntil(*sim, 300);
  const double late = Metric(*sim, "items_returned");
  EXPECT_GT(early, 0);
  EXPECT_GT(late, early * 2);
}

TEST(Foraging, CarryingRobotsShowIt) {
  // LEDs are red exactly on the robots that carry an item. A controller sets
  // them in its control step and they reach the space at the next act step,
  // so after each tick they match the carrying count of the tick before.
  auto sim = Load(kForaging, {});
  double carried_at_some_point = 0;
  for (int tick = 0; tick < 600; ++tick) {
    const double carrying_before = Metric(*sim, "carrying");
    sim->Step();
    const Space& space = sim->space();
    size_t red = 0;
    for (uint32_t i = 0; i < space.slots(); ++i) {
      if (space.alive(i) && (space.flags(i) & kRobot) && space.leds(i)[0] == Color{255, 0, 0, 255})
        ++red;
    }
    ASSERT_EQ(static_cast<double>(red), carrying_before) << "at tick " << sim->tick();
    carried_at_some_point = std::max(carried_at_some_point, carrying_before);
  }
  EXPECT_GT(carried_at_some_point, 0);
}

TEST(Foraging, TheLightLeadsHome) {
  // With the light moved over the source, carrying robots head the wrong
  // way: far fewer items come back.
  auto home = Load(kForaging, {});
  RunUntil(*home, 200);
  auto astray = Load(kForaging, {"arena.light[nest_light].position=2.6,0,0.5"});
  RunUntil(*astray, 200);
  EXPECT_LT(Metric(*astray, "items_returned"), 0.25 * Metric(*home, "items_returned"));
}

TEST(Foraging, BadNestIsRejectedWithItsLine) {
  const std::string message = LoadError(kForaging, {"loop_functions.params.nest=1,1,0,0"});
  EXPECT_TRUE(
      Mentions(message, {"foraging.xml:", "<params>", "attribute 'nest'", "'1,1,0,0'", "x0 < x1"}));
}

}  // namespace
}  // namespace colony
