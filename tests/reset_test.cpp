// Simulation::Reset (docs/embedding.md): a reset simulation runs exactly as
// a fresh load with the same seed (the same state hash and metrics, at any
// thread count), for experiments of every engine; controllers' and loop
// functions' Reset hooks are called; failures leave a simulation that says
// why and can be reset again; the evolution example runs.
#include "tests/test_util.h"

namespace colony {
namespace {

using testing::LoadExperiment;
using testing::Mentions;

// Runs `sim` for `ticks` ticks, or to its end.
void RunTicks(Simulation& sim, int ticks) {
  for (int t = 0; t < ticks && !sim.Done(); ++t) sim.Step();
}

// The final hash of `file` loaded fresh with `seed` and run `ticks` ticks.
uint64_t FreshRunHash(const std::string& file, uint64_t seed, int ticks,
                      std::optional<int> threads = std::nullopt) {
  auto sim = LoadExperiment(file, seed, {}, threads);
  RunTicks(*sim, ticks);
  return sim->StateHash();
}

// An experiment of experiments/, the engine it needs, and how many ticks the
// test runs it.
struct Case {
  const char* file;
  const char* engine;
  int ticks;
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.file; }

class ResetEqualsFreshLoad : public ::testing::TestWithParam<Case> {};

// After a run with seed 1, Reset(2) gives what a fresh load with seed 2
// gives: the same state at tick 0, the same state and metrics after the
// run; and Reset(1) gives the first run again.
TEST_P(ResetEqualsFreshLoad, SameStateAndMetricsAsAFreshLoad) {
  const Case& c = GetParam();
  if (!testing::HaveEngine(c.engine)) GTEST_SKIP() << c.engine << " is not in this build";
  auto fresh = LoadExperiment(c.file, 2);
  const uint64_t fresh_start = fresh->StateHash();
  RunTicks(*fresh, c.ticks);

  auto sim = LoadExperiment(c.file, 1);
  RunTicks(*sim, c.ticks);
  const uint64_t first_run = sim->StateHash();
  const std::vector<double> first_metrics = sim->metrics().values();
  EXPECT_NE(first_run, fresh->StateHash()) << "seeds 1 and 2 should give different runs";

  sim->Reset(2);
  EXPECT_EQ(sim->tick(), 0u);
  EXPECT_FALSE(sim->Done());
  EXPECT_EQ(sim->seed(), 2u);
  EXPECT_EQ(sim->StateHash(), fresh_start);
  RunTicks(*sim, c.ticks);
  EXPECT_EQ(sim->tick(), fresh->tick());
  EXPECT_EQ(sim->StateHash(), fresh->StateHash());
  EXPECT_EQ(sim->metrics().columns(), fresh->metrics().columns());
  EXPECT_EQ(sim->metrics().values(), fresh->metrics().values());

  sim->Reset(1);
  RunTicks(*sim, c.ticks);
  EXPECT_EQ(sim->StateHash(), first_run);
  EXPECT_EQ(sim->metrics().values(), first_metrics);
}

INSTANTIATE_TEST_SUITE_P(
    Experiments, ResetEqualsFreshLoad,
    ::testing::Values(Case{"diffusion.xml", "kinematics2d", 40},
                      Case{"flocking.xml", "kinematics2d", 40},
                      // loop functions drawing from their random stream
                      Case{"foraging.xml", "kinematics2d", 40},
                      // loop functions adding entities while running
                      Case{"pockets_swarm.xml", "kinematics2d", 40},
                      // Box2D, two engines and robots migrating between them
                      Case{"multiple_engines.xml", "dynamics2d", 40},
                      // eye-bots in pointmass3d above foot-bots in kinematics2d
                      Case{"eyebot_guidance.xml", "pointmass3d", 40},
                      // ODE: foot-bots, hand-bots, joints
                      Case{"pushpull.xml", "dynamics3d", 20}),
    [](const ::testing::TestParamInfo<Case>& info) {
      std::string name = info.param.file;
      return name.substr(0, name.find('.'));
    });

#ifdef COLONY_TEST_LUA
TEST(Reset, LuaControllersRunAsAfterAFreshLoad) {
  const std::string file = "lua/diffusion.argos";
  auto sim = LoadExperiment(file, 1);
  RunTicks(*sim, 30);
  sim->Reset(2);
  RunTicks(*sim, 30);
  EXPECT_EQ(sim->StateHash(), FreshRunHash(file, 2, 30));
}
#endif

// The same hash after a Reset whatever the thread count: the kinematics2d
// demo and two Box2D engines stepping in parallel.
TEST(Reset, SameHashWhateverTheThreadCount) {
  for (const char* file : {"diffusion.xml", "multiple_engines.xml"}) {
    if (std::string(file) == "multiple_engines.xml" && !testing::HaveEngine("dynamics2d")) continue;
    const uint64_t reference = FreshRunHash(file, 5, 30, 1);
    for (int threads : {0, 1, 2, 4}) {
      auto sim = LoadExperiment(file, 1, {}, threads);
      RunTicks(*sim, 30);
      sim->Reset(5);
      RunTicks(*sim, 30);
      EXPECT_EQ(sim->StateHash(), reference) << file << " with " << threads << " threads";
    }
  }
}

TEST(Reset, WithoutSeedKeepsTheSeedAndRepeatsTheRun) {
  auto sim = LoadExperiment("diffusion.xml", 9);
  RunTicks(*sim, 30);
  const uint64_t first = sim->StateHash();
  while (!sim->Done()) sim->Step();
  sim->Reset();
  EXPECT_EQ(sim->seed(), 9u);
  EXPECT_EQ(sim->tick(), 0u);
  EXPECT_FALSE(sim->Done());
  RunTicks(*sim, 30);
  EXPECT_EQ(sim->StateHash(), first);
}

// Entities added and removed while running are as the file built them
// after a Reset.
TEST(Reset, PutsBackRemovedEntitiesAndRemovesAddedOnes) {
  auto sim = LoadExperiment("diffusion.xml", 3);
  const uint64_t start = sim->StateHash();
  const size_t robots = sim->robot_count();
  sim->Step();
  sim->AddEntity("<box id=\"extra\" size=\"0.2,0.2,0.2\"><body position=\"3.9,3.9,0\"/></box>");
  sim->RemoveEntity(sim->space().Find("mb0"));
  sim->RemoveEntity(sim->space().Find("box1"));
  sim->Step();
  ASSERT_EQ(sim->robot_count(), robots - 1);
  sim->Reset();
  EXPECT_FALSE(sim->space().Find("extra").valid());
  EXPECT_TRUE(sim->space().Find("mb0").valid());
  EXPECT_TRUE(sim->space().Find("box1").valid());
  EXPECT_NE(sim->ControllerOf(sim->space().Find("mb0")), nullptr);
  EXPECT_EQ(sim->robot_count(), robots);
  EXPECT_EQ(sim->StateHash(), start);
}

// A controller that counts its hooks (and can fail in each, by parameter).
struct Counts {
  int constructed = 0, inits = 0, resets = 0, destroys = 0;
  int resets_after_init = 0;  // Reset calls on an object whose Init ran
  int lf_inits = 0, lf_resets = 0, lf_destroys = 0;
  int controller_resets_seen_by_lf = -1;  // Counts::resets when the loop functions' Reset ran
};
Counts counts;

class Counter : public Controller {
 public:
  Counter() { ++counts.constructed; }
  void Init(const Params& params) override {
    ++counts.inits;
    initialised_ = true;
    throw_at_tick_ = params.GetInt("throw_at_tick", 0, 0);
    throw_in_reset_ = params.GetBool("throw_in_reset", false);
    throw_in_destroy_ = params.GetBool("throw_in_destroy", false);
  }
  void ControlStep() override {
    if (++ticks_ == throw_at_tick_) throw std::runtime_error("told to throw at this tick");
  }
  void Reset() override {
    ++counts.resets;
    counts.resets_after_init += initialised_ && ticks_ == 0;
    if (throw_in_reset_) throw std::runtime_error("told to throw in Reset");
  }
  void Destroy() override {
    ++counts.destroys;
    if (throw_in_destroy_) throw std::runtime_error("told to throw in Destroy");
  }

 private:
  bool initialised_ = false, throw_in_reset_ = false, throw_in_destroy_ = false;
  int64_t throw_at_tick_ = 0, ticks_ = 0;
};
COLONY_REGISTER_CONTROLLER(Counter, "reset_test_counter", "test: counts its hooks");

// Loop functions that count their hooks, and reset the simulation from
// PostStep when told to.
class CounterLoop : public LoopFunctions {
 public:
  void Init(const Params& params) override {
    ++counts.lf_inits;
    reset_in_post_step_ = params.GetBool("reset_in_post_step", false);
    sim().metrics().Set("ticks_seen", 0);
  }
  void PostStep() override {
    sim().metrics().Set("ticks_seen", static_cast<double>(++ticks_));
    if (reset_in_post_step_) sim().Reset();
  }
  void Reset() override {
    ++counts.lf_resets;
    counts.controller_resets_seen_by_lf = counts.resets;
  }
  void Destroy() override { ++counts.lf_destroys; }

 private:
  bool reset_in_post_step_ = false;
  int ticks_ = 0;
};
COLONY_REGISTER_LOOP_FUNCTIONS(CounterLoop, "reset_test_loop", "test: counts its hooks",
                               {{"reset_in_post_step", "true or false", "false",
                                 "calls Simulation::Reset from PostStep"}});

std::string CounterExperiment(const std::string& params = "", const std::string& loop_params = "") {
  std::string robots;
  for (int i = 0; i < 3; ++i) {
    robots += "<marxbot id=\"r" + std::to_string(i) + "\"><body position=\"" +
              std::to_string(i - 1) + ",0,0\"/><controller config=\"cc\"/></marxbot>";
  }
  return testing::Experiment(
      robots, "<reset_test_counter id=\"cc\"><params " + params + "/></reset_test_counter>",
      "4,4,1",
      "<loop_functions label=\"reset_test_loop\"><params " + loop_params + "/></loop_functions>");
}

TEST(Reset, CallsControllersThenLoopFunctionsResetOnNewObjects) {
  counts = {};
  auto sim = testing::LoadXml(CounterExperiment());
  EXPECT_EQ(counts.inits, 3);
  EXPECT_EQ(counts.resets, 0);  // a load calls no Reset
  EXPECT_EQ(counts.lf_inits, 1);
  EXPECT_EQ(counts.lf_resets, 0);
  RunTicks(*sim, 5);
  EXPECT_EQ(sim->metrics().Value("ticks_seen"), 5);

  sim->Reset(11);
  // The old objects were destroyed, new ones built and Init'ed, then reset:
  // the controllers first, then the loop functions.
  EXPECT_EQ(counts.destroys, 3);
  EXPECT_EQ(counts.lf_destroys, 1);
  EXPECT_EQ(counts.constructed, 6);
  EXPECT_EQ(counts.inits, 6);
  EXPECT_EQ(counts.resets, 3);
  EXPECT_EQ(counts.resets_after_init, 3);
  EXPECT_EQ(counts.lf_inits, 2);
  EXPECT_EQ(counts.lf_resets, 1);
  EXPECT_EQ(counts.controller_resets_seen_by_lf, 3);
  EXPECT_EQ(sim->metrics().Value("ticks_seen"), 0);  // the new loop functions' metrics
  RunTicks(*sim, 2);
  EXPECT_EQ(sim->metrics().Value("ticks_seen"), 2);
  sim.reset();
  EXPECT_EQ(counts.destroys, 6);
  EXPECT_EQ(counts.lf_destroys, 2);
}

TEST(Reset, RecoversAfterAControllerThrew) {
  auto sim = testing::LoadXml(CounterExperiment("throw_at_tick=\"3\""));
  sim->Step();
  sim->Step();
  try {
    sim->Step();
    FAIL() << "the controller should have failed the tick";
  } catch (const RuntimeFailure& e) {
    EXPECT_TRUE(Mentions(e.what(), {"told to throw at this tick", "r0"}));
  }
  sim->SetControllerParam("cc", "throw_at_tick", "0");
  sim->Reset();
  while (!sim->Done()) sim->Step();
  EXPECT_EQ(sim->tick(), 100u);
}

// A Reset that fails leaves an empty simulation that says why, until a
// Reset succeeds.
TEST(Reset, AFailedResetSaysWhyUntilAResetSucceeds) {
  auto sim = testing::LoadXml(CounterExperiment());
  sim->SetControllerParam("cc", "throw_in_reset", "true");
  try {
    sim->Reset();
    FAIL() << "Reset should have failed";
  } catch (const RuntimeFailure& e) {
    EXPECT_TRUE(Mentions(e.what(), {"controller 'reset_test_counter' of robot 'r0' failed in "
                                    "Reset: told to throw in Reset"}));
  }
  EXPECT_EQ(sim->robot_count(), 0u);
  try {
    sim->Step();
    FAIL() << "Step should have refused";
  } catch (const RuntimeFailure& e) {
    EXPECT_TRUE(Mentions(e.what(),
                         {"its last Reset failed", "told to throw in Reset", "call Reset again"}));
  }
  sim->SetControllerParam("cc", "throw_in_reset", "false");
  sim->Reset();
  EXPECT_EQ(sim->robot_count(), 3u);
  while (!sim->Done()) sim->Step();
  EXPECT_EQ(sim->tick(), 100u);
}

TEST(Reset, ADestroyThatThrowsIsReported) {
  auto sim = testing::LoadXml(CounterExperiment("throw_in_destroy=\"true\""));
  sim->Step();
  sim->SetControllerParam("cc", "throw_in_destroy", "false");
  try {
    sim->Reset();
    FAIL() << "Reset should have failed";
  } catch (const RuntimeFailure& e) {
    EXPECT_TRUE(Mentions(e.what(), {"robot 'r0' failed in Destroy: told to throw in Destroy"}));
  }
  EXPECT_THROW(sim->Step(), RuntimeFailure);
  sim->Reset();  // the new controllers do not throw
  while (!sim->Done()) sim->Step();
  EXPECT_EQ(sim->tick(), 100u);
}

TEST(Reset, BadParametersAreReportedAsAtLoad) {
  auto sim = LoadExperiment("diffusion.xml", 1);
  sim->SetControllerParam("dc", "velocity", "fast");
  try {
    sim->Reset();
    FAIL() << "Reset should have failed";
  } catch (const ConfigError& e) {
    EXPECT_TRUE(Mentions(e.what(), {"diffusion.xml", "velocity", "fast"}));
  }
  EXPECT_THROW(sim->Step(), RuntimeFailure);
  sim->SetControllerParam("dc", "velocity", "0.2");
  sim->Reset();
  RunTicks(*sim, 20);
  EXPECT_TRUE(sim->Done() || sim->tick() == 20);

  sim->SetControllerParam("dc", "velocty", "0.1");
  try {
    sim->Reset();
    FAIL() << "Reset should have failed";
  } catch (const ConfigError& e) {
    EXPECT_TRUE(Mentions(e.what(), {"velocty", "did you mean 'velocity'"}));
  }
  try {
    sim->SetControllerParam("nope", "velocity", "0.1");
    FAIL() << "SetControllerParam should have refused";
  } catch (const std::invalid_argument& e) {
    EXPECT_TRUE(Mentions(e.what(), {"no controller configuration with id 'nope'", "dc"}));
  }
}

// SetControllerParam changes the controllers the next Reset builds, as
// --set would have changed the file.
TEST(Reset, NewParametersRunAsTheFileWithThemWould) {
  auto sim = LoadExperiment("diffusion.xml", 4);
  sim->SetControllerParam("dc", "velocity", "0.2");
  sim->SetControllerParam("dc", "alpha", "20");
  RunTicks(*sim, 20);
  auto as_before = LoadExperiment("diffusion.xml", 4);
  RunTicks(*as_before, 20);
  EXPECT_EQ(sim->StateHash(), as_before->StateHash()) << "the running controllers keep theirs";

  sim->Reset();
  RunTicks(*sim, 20);
  auto changed = LoadExperiment("diffusion.xml", 4,
                                {"controllers.diffusion[dc].params.velocity=0.2",
                                 "controllers.diffusion[dc].params.alpha=20"});
  RunTicks(*changed, 20);
  EXPECT_EQ(sim->StateHash(), changed->StateHash());
  EXPECT_NE(sim->StateHash(), as_before->StateHash());
}

TEST(Reset, RefusedDuringATick) {
  auto sim = testing::LoadXml(CounterExperiment("", "reset_in_post_step=\"true\""));
  try {
    sim->Step();
    FAIL() << "the loop functions' Reset call should have failed the tick";
  } catch (const RuntimeFailure& e) {
    EXPECT_TRUE(Mentions(e.what(), {"PostStep", "Reset was called during a tick"}));
  }
}

TEST(Metrics, ValueNamesTheMissingMetric) {
  auto sim = LoadExperiment("diffusion.xml", 1);
  EXPECT_EQ(sim->metrics().Value("robots"), 120);
  try {
    sim->metrics().Value("fitness");
    FAIL() << "Value should have thrown";
  } catch (const std::out_of_range& e) {
    EXPECT_TRUE(Mentions(e.what(), {"no metric 'fitness'", "mean_displacement"}));
  }
}

// The example: 20 parameter sets evaluated in one process, shortened.
TEST(EvolutionExample, EvaluatesTwentySetsInOneProcess) {
  const std::string exe = COLONY_EVOLUTION_EXE;
  const auto result = testing::RunCommand(
      exe + " " COLONY_SOURCE_DIR "/experiments/diffusion.xml --seconds 2 --trials 1");
  ASSERT_EQ(result.status, 0) << result.output;
  // One row per set: number, velocity, alpha, delta, fitness.
  const std::regex row(R"(\n +([0-9]+) +[0-9.]+ +[0-9.]+ +[0-9.]+ +(-?[0-9.]+))");
  int rows = 0;
  for (auto it = std::sregex_iterator(result.output.begin(), result.output.end(), row);
       it != std::sregex_iterator(); ++it) {
    EXPECT_EQ(std::stoi((*it)[1]), ++rows);
  }
  EXPECT_EQ(rows, 20) << result.output;
  EXPECT_TRUE(Mentions(result.output, {"best: set ", "20 runs in one process"}));
}

TEST(EvolutionExample, BadInputExitsWithStatus2) {
  const std::string exe = COLONY_EVOLUTION_EXE;
  const std::string diffusion = COLONY_SOURCE_DIR "/experiments/diffusion.xml";
  auto r = testing::RunCommand(exe + " " + diffusion + " --controller nope --seconds 1");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(Mentions(r.output, {"no controller configuration with id 'nope'", "dc"}));
  // An experiment without the diffusion_metrics loop functions.
  r = testing::RunCommand(exe + " " COLONY_SOURCE_DIR "/experiments/rendering.xml --seconds 1");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(Mentions(r.output, {"no metric 'robots'", "diffusion_metrics"}));
  r = testing::RunCommand(exe + " " + diffusion + " --sets 0");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(Mentions(r.output, {"--sets"}));
}

}  // namespace
}  // namespace colony
