// The same file and seed give the same final state hash with 0, 1, 2 and 4
// threads: on the demo, and on a scene dense enough that robots collide.
#include "tests/test_util.h"

namespace colony {
namespace {

uint64_t FinalHash(const ExperimentOptions& base, int threads) {
  ExperimentOptions options = base;
  options.threads = threads;
  auto sim = Simulation::Load(options);
  while (!sim->Done()) sim->Step();
  return sim->StateHash();
}

void ExpectSameHashForAllThreadCounts(const ExperimentOptions& options) {
  const uint64_t reference = FinalHash(options, 0);
  for (int threads : {1, 2, 4}) {
    EXPECT_EQ(FinalHash(options, threads), reference) << "with " << threads << " threads";
  }
}

TEST(Determinism, DemoSameHashWhateverTheThreadCount) {
  ExperimentOptions options;
  options.file = COLONY_SOURCE_DIR "/experiments/diffusion.xml";
  options.overrides = {"framework.experiment.length=20"};
  ExpectSameHashForAllThreadCounts(options);
}

TEST(Determinism, DenseCollidingSceneSameHashWhateverTheThreadCount) {
  ExperimentOptions options;
  options.text = testing::Experiment(
      "<walls thickness=\"0.1\" height=\"0.5\"/>"
      "<distribute><position method=\"uniform\" min=\"-1.4,-1.4,0\" max=\"1.4,1.4,0\"/>"
      "<orientation method=\"uniform\" min=\"0,0,0\" max=\"360,0,0\"/>"
      "<entity quantity=\"150\" max_trials=\"1000\"><marxbot id=\"mb\"><controller "
      "config=\"dc\"/></marxbot></entity>"
      "</distribute>",
      "<diffusion id=\"dc\" library=\"diffusion\"><actuators><differential_steering/><leds "
      "color=\"red\"/></actuators>"
      "<sensors><proximity noise=\"gaussian\" noise_std_dev=\"0.05\"/><wheel_encoders "
      "slip=\"0.1\"/>"
      "<positioning noise=\"uniform\" noise_range=\"-0.01,0.01\"/><ground/></sensors>"
      "<params velocity=\"0.3\"/></diffusion>",
      "3.2,3.2,1");
  // Different seeds give different runs; each is reproducible.
  options.seed = 3;
  ExpectSameHashForAllThreadCounts(options);
  const uint64_t a = FinalHash(options, 2);
  options.seed = 4;
  EXPECT_NE(FinalHash(options, 2), a);
}

TEST(Determinism, SwarmNumberedByPlaceSameHashWhateverTheThreadCount) {
  ExperimentOptions options;
  options.file = COLONY_SOURCE_DIR "/experiments/benchmarks/diffusion_1000.xml";
  options.overrides = {"framework.experiment.length=5"};
  ExpectSameHashForAllThreadCounts(options);
}

}  // namespace
}  // namespace colony
