// Entities added and removed while running, as loop functions do.
#include "sensors/proximity/proximity.h"
#include "tests/test_util.h"

namespace colony {
namespace {

// Stands still and remembers the strongest front proximity reading.
class Watcher : public Controller {
 public:
  void Init(const Params&) override { proximity_ = &GetSensor<ProximitySensor>("proximity"); }
  void ControlStep() override {
    front = 0;
    for (const auto& r : proximity_->readings())
      if (std::abs(r.angle) < 0.3) front = std::max(front, static_cast<double>(r.value));
  }
  double front = 0;

 private:
  const ProximitySensor* proximity_ = nullptr;
};
COLONY_REGISTER_CONTROLLER(Watcher, "runtime_watcher", "test: records the front proximity reading");

const char* kWatcher = "<runtime_watcher id=\"w\"><sensors><proximity/></sensors></runtime_watcher>";

TEST(RuntimeEntities, AddedBoxIsSeenAndRemovedBoxIsGone) {
  auto sim = testing::LoadXml(testing::Experiment(
      "<marxbot id=\"mb\"><body position=\"0,0,0\"/><controller config=\"w\"/></marxbot>", kWatcher));
  auto& watcher = dynamic_cast<Watcher&>(*sim->ControllerOf(sim->space().Find("mb")));
  sim->Step();
  EXPECT_EQ(watcher.front, 0.0);
  const EntityHandle box = sim->AddEntity("<box id=\"new_box\" size=\"0.1,0.4,0.3\"><body position=\"0.15,0,0\"/></box>");
  ASSERT_TRUE(sim->space().IsAlive(box));
  EXPECT_EQ(sim->space().Find("new_box"), box);
  sim->Step();
  EXPECT_GT(watcher.front, 0.1);  // 1.5 cm ahead
  sim->RemoveEntity(box);
  EXPECT_FALSE(sim->space().IsAlive(box));
  EXPECT_FALSE(sim->space().Find("new_box").valid());
  sim->Step();
  EXPECT_EQ(watcher.front, 0.0);
}

TEST(RuntimeEntities, RobotsCanBeAddedAndRemoved) {
  auto sim = testing::LoadXml(testing::Experiment(
      "<marxbot id=\"mb\"><body position=\"0,0,0\"/><controller config=\"w\"/></marxbot>", kWatcher));
  EXPECT_EQ(sim->robot_count(), 1u);
  const EntityHandle added =
      sim->AddEntity("<marxbot id=\"mb2\"><body position=\"1,0,0\"/><controller config=\"w\"/></marxbot>");
  EXPECT_EQ(sim->robot_count(), 2u);
  ASSERT_NE(sim->ControllerOf(added), nullptr);
  sim->Step();
  sim->RemoveEntity(sim->space().Find("mb"));
  EXPECT_EQ(sim->robot_count(), 1u);
  sim->Step();
  // A removed slot is reused with a new generation: old handles stay dead.
  const EntityHandle again = sim->AddEntity("<box id=\"b\" size=\"0.1,0.1,0.1\"><body position=\"-1,-1,0\"/></box>");
  EXPECT_FALSE(sim->space().IsAlive(EntityHandle{again.index, again.generation - 1}));
}

TEST(RuntimeEntities, BadAddedEntityIsRejectedWithAMessage) {
  auto sim = testing::LoadXml(testing::Experiment("", kWatcher));
  try {
    sim->AddEntity("<box id=\"b\" size=\"0.1,-1,0.1\"><body position=\"0,0,0\"/></box>");
    FAIL() << "a negative size was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("attribute 'size'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(sim->AddEntity("<box"), ConfigError);
}

}  // namespace
}  // namespace colony

namespace {

// The per-phase profile adds up the ticks run and puts time where the work is.
TEST(StepProfile, CountsTicksAndTimesEveryPhase) {
  colony::ExperimentOptions options;
  options.file = COLONY_SOURCE_DIR "/experiments/diffusion.xml";
  auto sim = colony::Simulation::Load(options);
  for (int i = 0; i < 20; ++i) sim->Step();
  const colony::StepProfile& p = sim->profile();
  EXPECT_EQ(p.ticks, 20u);
  EXPECT_GT(p.physics, 0);
  EXPECT_GT(p.sense_control, 0);
  EXPECT_GE(p.act, 0);
  EXPECT_GE(p.media, 0);
  EXPECT_GT(p.loop_functions, 0);  // diffusion_metrics runs every tick
  EXPECT_DOUBLE_EQ(p.total(), p.act + p.physics + p.media + p.loop_functions + p.sense_control);
  sim->ResetProfile();
  EXPECT_EQ(sim->profile().ticks, 0u);
  EXPECT_EQ(sim->profile().total(), 0);
}

}  // namespace
