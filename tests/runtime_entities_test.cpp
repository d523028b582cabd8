// Entities added and removed while running, as loop functions do.
#include "actuators/differential_steering/differential_steering.h"
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

const char* kWatcher =
    "<runtime_watcher id=\"w\"><sensors><proximity/></sensors></runtime_watcher>";

TEST(RuntimeEntities, AddedBoxIsSeenAndRemovedBoxIsGone) {
  auto sim = testing::LoadXml(testing::Experiment(
      "<marxbot id=\"mb\"><body position=\"0,0,0\"/><controller config=\"w\"/></marxbot>",
      kWatcher));
  auto& watcher = dynamic_cast<Watcher&>(*sim->ControllerOf(sim->space().Find("mb")));
  sim->Step();
  EXPECT_EQ(watcher.front, 0.0);
  const EntityHandle box = sim->AddEntity(
      "<box id=\"new_box\" size=\"0.1,0.4,0.3\"><body position=\"0.15,0,0\"/></box>");
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
      "<marxbot id=\"mb\"><body position=\"0,0,0\"/><controller config=\"w\"/></marxbot>",
      kWatcher));
  EXPECT_EQ(sim->robot_count(), 1u);
  const EntityHandle added = sim->AddEntity(
      "<marxbot id=\"mb2\"><body position=\"1,0,0\"/><controller config=\"w\"/></marxbot>");
  EXPECT_EQ(sim->robot_count(), 2u);
  ASSERT_NE(sim->ControllerOf(added), nullptr);
  sim->Step();
  sim->RemoveEntity(sim->space().Find("mb"));
  EXPECT_EQ(sim->robot_count(), 1u);
  sim->Step();
  // A removed slot is reused with a new generation: old handles stay dead.
  const EntityHandle again =
      sim->AddEntity("<box id=\"b\" size=\"0.1,0.1,0.1\"><body position=\"-1,-1,0\"/></box>");
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

// Drives straight ahead at 0.1 m/s.
class Driver : public Controller {
 public:
  void Init(const Params&) override {
    wheels_ = &GetActuator<DifferentialSteering>("differential_steering");
  }
  void ControlStep() override { wheels_->SetLinearVelocity(0.1, 0.1); }

 private:
  DifferentialSteering* wheels_ = nullptr;
};
COLONY_REGISTER_CONTROLLER(Driver, "runtime_driver", "test: drives straight ahead");

const char kDriver[] =
    "<runtime_driver id=\"d\"><actuators><differential_steering/></actuators></runtime_driver>";

// One marXbot, on line 2.
const char kOneRobot[] =
    "\n<marxbot id=\"mb\"><body position=\"0,0,0\"/><controller config=\"d\"/></marxbot>";

// A marXbot description read once, as a loop function would keep it.
EntityDesc Marxbot(const std::string& id, double x, double y) {
  static const EntityDesc kProto = ReadEntityDesc(
      "<marxbot id=\"proto\"><body position=\"0,0,0\"/><controller config=\"d\"/></marxbot>",
      "<test>");
  EntityDesc desc = kProto;
  desc.init.id = id;
  desc.init.pose.position = Vec3(x, y, 0);
  return desc;
}

// The message of the ConfigError AddEntity raises for `desc` ("" if added).
std::string AddError(Simulation& sim, const EntityDesc& desc,
                     PlacementCheck check = PlacementCheck::kNone) {
  try {
    sim.AddEntity(desc, check);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(RuntimeEntities, RobotsAddedFromADescriptionGetAControllerAndMove) {
  auto sim = testing::LoadXml(testing::Experiment("", kDriver));
  ASSERT_EQ(sim->robot_count(), 0u);
  // One description, copied for each robot.
  std::vector<EntityHandle> added;
  for (int i = 0; i < 3; ++i)
    added.push_back(sim->AddEntity(Marxbot("spawned" + std::to_string(i), -1, i - 1.0)));
  EXPECT_EQ(sim->robot_count(), 3u);
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(sim->space().IsAlive(added[i]));
    EXPECT_EQ(sim->space().Find("spawned" + std::to_string(i)), added[i]);
    EXPECT_NE(dynamic_cast<Driver*>(sim->ControllerOf(added[i])), nullptr);
    EXPECT_NE(sim->EngineOf(added[i]), nullptr);
  }
  for (int t = 0; t < 20; ++t) sim->Step();
  for (int i = 0; i < 3; ++i) {
    const Vec3& p = sim->space().pose(added[i].index).position;
    EXPECT_NEAR(p.x(), -1 + 0.1 * 2.0, 0.03) << "robot " << i << " drove 2 s at 0.1 m/s along x";
    EXPECT_NEAR(p.y(), i - 1.0, 1e-9);
  }
}

TEST(RuntimeEntities, BoxesNeedNoXml) {
  auto sim = testing::LoadXml(testing::Experiment("", kDriver));
  EntityDesc box;
  box.type = "box";
  box.init.id = "crate";
  box.init.geometry.shape = ShapeKind::kBox;
  box.init.geometry.size = Vec3(0.2, 0.2, 0.2);
  box.init.geometry.radius = box.init.geometry.BoundingRadius();
  box.init.pose.position = Vec3(0.5, 0, 0);
  const EntityHandle h = sim->AddEntity(box, PlacementCheck::kClear);
  ASSERT_TRUE(sim->space().IsAlive(h));
  EXPECT_EQ(sim->space().geometry(h.index).size, Vec3(0.2, 0.2, 0.2));
  // A robot driving into it stops there.
  sim->AddEntity(Marxbot("r", 0, 0));
  for (int t = 0; t < 100; ++t) sim->Step();
  EXPECT_LT(sim->space().pose(sim->space().Find("r").index).position.x(), 0.4 - 0.085 + 1e-6);
}

TEST(RuntimeEntities, DuplicateIdIsRefused) {
  auto sim = testing::LoadXml(testing::Experiment(kOneRobot, kDriver));
  EXPECT_TRUE(testing::Mentions(AddError(*sim, Marxbot("mb", 1, 1)),
                                {"<marxbot id=\"mb\">", "attribute 'id'",
                                 "duplicate entity id 'mb'", "first defined at line 2"}));
  EXPECT_EQ(sim->robot_count(), 1u);
  EXPECT_EQ(sim->space().alive_count(), 1u);
  EXPECT_EQ(sim->space().pose(sim->space().Find("mb").index).position, Vec3(0, 0, 0))
      << "the first one is untouched";
  sim->Step();
}

TEST(RuntimeEntities, UnknownTypeIsRefused) {
  auto sim = testing::LoadXml(testing::Experiment("", kDriver));
  EntityDesc desc = Marxbot("m", 0, 0);
  desc.type = "marxbott";
  EXPECT_TRUE(testing::Mentions(
      AddError(*sim, desc),
      {"unknown entity type 'marxbott'", "did you mean 'marxbot'?", "accepted:", "box"}));
  EXPECT_EQ(sim->space().alive_count(), 0u);
}

TEST(RuntimeEntities, UnknownOrMissingControllerIsRefused) {
  auto sim = testing::LoadXml(testing::Experiment("", kDriver));
  EntityDesc desc = Marxbot("m", 0, 0);
  desc.controller = "e";
  EXPECT_TRUE(testing::Mentions(AddError(*sim, desc), {"no controller with id 'e'", "defined: d"}));
  desc.controller = "";
  EXPECT_TRUE(testing::Mentions(AddError(*sim, desc), {"a marxbot needs a controller"}));
  EXPECT_EQ(sim->space().alive_count(), 0u);
}

TEST(RuntimeEntities, EntityOutsideEveryEngineIsRefused) {
  const std::string engines =
      "<kinematics2d id=\"west\"><boundaries><sides><vertex point=\"-2,-2\"/><vertex "
      "point=\"0,-2\"/>"
      "<vertex point=\"0,2\"/><vertex point=\"-2,2\"/></sides></boundaries></kinematics2d>";
  auto sim = testing::LoadXml(testing::Experiment("", kDriver, "4,4,1", "", engines));
  EXPECT_TRUE(testing::Mentions(
      AddError(*sim, Marxbot("east", 1, 0)),
      {"<marxbot id=\"east\">", "entity 'east' at (1, 0, 0) is inside no engine's <boundaries>",
       "kinematics2d 'west'"}));
  EXPECT_EQ(sim->space().alive_count(), 0u);
  EXPECT_EQ(sim->robot_count(), 0u);
  // Inside it is fine.
  EXPECT_TRUE(sim->space().IsAlive(sim->AddEntity(Marxbot("west", -1, 0))));
  sim->Step();
}

TEST(RuntimeEntities, PlacementIsCheckedWhenAsked) {
  auto sim = testing::LoadXml(testing::Experiment(kOneRobot, kDriver));
  EXPECT_TRUE(testing::Mentions(
      AddError(*sim, Marxbot("near", 0.1, 0), PlacementCheck::kClear),
      {"entity 'near' overlaps 'mb' (line 2)", "not overlapping solid entities"}));
  EXPECT_TRUE(
      testing::Mentions(AddError(*sim, Marxbot("far", 5, 0), PlacementCheck::kClear),
                        {"entity 'far' is outside the arena", "the arena spans x [-2, 2]"}));
  EXPECT_EQ(sim->space().alive_count(), 1u);
  // Unchecked, the caller decides.
  EXPECT_TRUE(sim->space().IsAlive(sim->AddEntity(Marxbot("near", 0.1, 0))));
  EXPECT_TRUE(sim->space().IsAlive(sim->AddEntity(Marxbot("clear", 1, 1), PlacementCheck::kClear)));
}

TEST(RuntimeEntities, RobotWhoseDevicesCannotStartIsTakenOutAgain) {
  // kinematics2d simulates no manipulator, and this marXbot has none.
  const std::string controllers =
      std::string(kDriver) +
      "<runtime_driver id=\"m\"><actuators><differential_steering/><manipulator/>"
      "</actuators></runtime_driver>";
  auto sim = testing::LoadXml(testing::Experiment("", controllers));
  EntityDesc desc = Marxbot("lifter", 0, 0);
  desc.controller = "m";
  EXPECT_FALSE(AddError(*sim, desc).empty());
  EXPECT_FALSE(sim->space().Find("lifter").valid());
  EXPECT_EQ(sim->robot_count(), 0u);
  // The run goes on, and the id can be used again.
  sim->Step();
  const EntityHandle h = sim->AddEntity(Marxbot("lifter", 0, 0));
  for (int t = 0; t < 10; ++t) sim->Step();
  EXPECT_GT(sim->space().pose(h.index).position.x(), 0.05);
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
