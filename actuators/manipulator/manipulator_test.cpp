// The manipulator actuator as a controller uses it: commands reach the
// robot's manipulator state clamped to its limits, XML overrides the limits,
// bad values and robots or engines that cannot carry it are rejected at load
// time with a message naming element, robot and engine.
#include "actuators/manipulator/manipulator.h"

#include <cmath>
#include <limits>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "actuators/manipulator/manipulator_state.h"
#include "core/registry.h"
#include "tests/test_util.h"

namespace colony {
namespace {

using testing::Experiment;
using testing::LoadError;
using testing::LoadXml;

// Test double for the device logic, not physics: an engine that declares it
// simulates the manipulator and, every step, puts each head where its
// commands ask (elevation and rotation jump to their targets, the magnet to
// fully engaged or disengaged). Nothing moves, nothing is held.
class ManipulatorDoubleEngine : public PhysicsEngine {
 public:
  void AddEntity(EntityHandle, PhysicsModel&) override {}
  void RemoveEntity(EntityHandle) override {}
  void Step(double) override {
    Space& space = sim().space();
    for (uint32_t s = 0; s < space.slots(); ++s) {
      ManipulatorState* m = space.alive(s) && Owns(s) ? space.Get<ManipulatorState>(s) : nullptr;
      if (!m) continue;
      m->elevation = m->target_elevation;
      m->rotation = m->target_rotation;
      m->magnet = m->want_magnet ? 1 : 0;
    }
  }
};
class DoubleModel : public PhysicsModel {};
COLONY_REGISTER_ENGINE(ManipulatorDoubleEngine, "manipulator_actuator_double",
                       "test double: heads jump to their commands; nothing moves", {});
COLONY_REGISTER_PHYSICS_MODEL(DoubleModel, "manipulator_actuator_double:marxbot", "test double",
                              (std::vector<std::string>{"drive", "manipulator"}));
// An engine whose marXbot model does not simulate the manipulator.
COLONY_REGISTER_ENGINE(ManipulatorDoubleEngine, "manipulator_actuator_none",
                       "test double: simulates no manipulator", {});
COLONY_REGISTER_PHYSICS_MODEL(DoubleModel, "manipulator_actuator_none:marxbot", "test double",
                              (std::vector<std::string>{"drive"}));

// Sends what the test puts in its public fields every control step.
class ManipulatorDriver : public Controller {
 public:
  void Init(const Params&) override {
    manipulator = &GetActuator<ManipulatorActuator>("manipulator");
  }
  void ControlStep() override {
    if (elevation) manipulator->SetElevation(*elevation);
    if (rotation) manipulator->SetRotation(*rotation);
    if (magnet) {
      if (*magnet) {
        manipulator->EngageMagnet();
      } else {
        manipulator->DisengageMagnet();
      }
    }
  }
  std::optional<double> elevation, rotation;
  std::optional<bool> magnet;
  ManipulatorActuator* manipulator = nullptr;
};
COLONY_REGISTER_CONTROLLER(ManipulatorDriver, "manipulator_driver",
                           "test: scripted manipulator commands");

const std::string kDouble = "<manipulator_actuator_double id=\"dbl\"/>";

std::string Controllers(const std::string& attributes = "") {
  return "<manipulator_driver id=\"md\"><actuators><manipulator " + attributes +
         "/></actuators></manipulator_driver>";
}

std::string Robot(const std::string& id, bool manipulator = true) {
  return "<marxbot id=\"" + id + "\"" + (manipulator ? " manipulator=\"true\"" : "") +
         "><body position=\"0,0,0\"/><controller config=\"md\"/></marxbot>";
}

std::unique_ptr<Simulation> Load(const std::string& attributes = "") {
  return LoadXml(Experiment(Robot("r"), Controllers(attributes), "4,4,1", "", kDouble));
}

ManipulatorDriver& Driver(Simulation& sim) {
  return dynamic_cast<ManipulatorDriver&>(*sim.ControllerOf(sim.space().Find("r")));
}
const ManipulatorState& State(Simulation& sim) {
  return *sim.space().Get<ManipulatorState>(sim.space().Find("r").index);
}

// Steps until a command given now has reached the state (it is sent at the
// end of the next tick and written at the start of the one after).
void Settle(Simulation& sim) {
  sim.Step();
  sim.Step();
}

TEST(ManipulatorActuator, CommandsReachTheManipulator) {
  auto sim = Load();
  ManipulatorDriver& d = Driver(*sim);
  d.elevation = 0.12;
  d.rotation = 1.0;
  d.magnet = true;
  Settle(*sim);
  const ManipulatorState& m = State(*sim);
  EXPECT_DOUBLE_EQ(m.target_elevation, 0.12);
  EXPECT_DOUBLE_EQ(m.target_rotation, 1.0);
  EXPECT_TRUE(m.want_magnet);
  EXPECT_DOUBLE_EQ(m.elevation, 0.12) << "the engine double moved the head there";
  d.magnet = false;
  Settle(*sim);
  EXPECT_FALSE(State(*sim).want_magnet);
  EXPECT_EQ(State(*sim).magnet, 0.0);
}

TEST(ManipulatorActuator, WithoutCommandsTheHeadStaysWhereItIs) {
  auto sim = Load();
  for (int t = 0; t < 3; ++t) sim->Step();
  const ManipulatorState& m = State(*sim);
  EXPECT_DOUBLE_EQ(m.target_elevation, ManipulatorState().elevation);
  EXPECT_DOUBLE_EQ(m.elevation, ManipulatorState().elevation);
  EXPECT_DOUBLE_EQ(m.target_rotation, 0.0);
  EXPECT_FALSE(m.want_magnet);
}

TEST(ManipulatorActuator, ElevationIsClampedToTheRobotsRange) {
  auto sim = Load();
  ManipulatorDriver& d = Driver(*sim);
  EXPECT_DOUBLE_EQ(d.manipulator->min_elevation(), 0.03);
  EXPECT_DOUBLE_EQ(d.manipulator->max_elevation(), 0.20);
  d.elevation = 1.0;
  Settle(*sim);
  EXPECT_DOUBLE_EQ(State(*sim).target_elevation, 0.20);
  d.elevation = -1.0;
  Settle(*sim);
  EXPECT_DOUBLE_EQ(State(*sim).target_elevation, 0.03);
}

TEST(ManipulatorActuator, RotationIsWrappedAndTheSidesAreHalfATurnApart) {
  auto sim = Load();
  ManipulatorDriver& d = Driver(*sim);
  d.rotation = 1.5 * M_PI;
  Settle(*sim);
  EXPECT_NEAR(State(*sim).target_rotation, -0.5 * M_PI, 1e-12);
  d.rotation.reset();
  d.manipulator->SetIrSide();
  Settle(*sim);
  EXPECT_NEAR(State(*sim).target_rotation, M_PI, 1e-12);
  d.manipulator->SetMagnetSide();
  Settle(*sim);
  EXPECT_NEAR(State(*sim).target_rotation, 0.0, 1e-12);
}

TEST(ManipulatorActuator, NonFiniteCommandsHoldTheHead) {
  auto sim = Load();
  ManipulatorDriver& d = Driver(*sim);
  d.elevation = 0.1;
  d.rotation = 0.5;
  Settle(*sim);
  d.elevation = std::numeric_limits<double>::quiet_NaN();
  d.rotation = std::numeric_limits<double>::infinity();
  Settle(*sim);
  EXPECT_DOUBLE_EQ(State(*sim).target_elevation, 0.1);
  EXPECT_DOUBLE_EQ(State(*sim).target_rotation, 0.5);
}

TEST(ManipulatorActuator, XmlOverridesTheLimits) {
  auto sim = Load(
      "min_elevation=\"0.05\" max_elevation=\"0.15\" elevation_speed=\"0.1\" rotation_speed=\"2\" "
      "switch_time=\"0.5\"");
  const ManipulatorState& m = State(*sim);
  EXPECT_DOUBLE_EQ(m.min_elevation, 0.05);
  EXPECT_DOUBLE_EQ(m.max_elevation, 0.15);
  EXPECT_DOUBLE_EQ(m.elevation_speed, 0.1);
  EXPECT_DOUBLE_EQ(m.rotation_speed, 2.0);
  EXPECT_DOUBLE_EQ(m.switch_time, 0.5);
  ManipulatorDriver& d = Driver(*sim);
  EXPECT_DOUBLE_EQ(d.manipulator->max_elevation(), 0.15);
  d.elevation = 0.19;
  Settle(*sim);
  EXPECT_DOUBLE_EQ(State(*sim).target_elevation, 0.15);
  // Attributes not given keep the robot's values.
  auto plain = Load("switch_time=\"2\"");
  EXPECT_DOUBLE_EQ(State(*plain).elevation_speed, ManipulatorState().elevation_speed);
  EXPECT_DOUBLE_EQ(State(*plain).max_elevation, ManipulatorState().max_elevation);
}

void ExpectMentions(const std::string& message, const std::vector<std::string>& parts) {
  for (const auto& p : parts)
    EXPECT_NE(message.find(p), std::string::npos) << "'" << p << "' in: " << message;
}

TEST(ManipulatorActuator, BadAttributesAreReportedWithElementAndLine) {
  // On its own line, so the line number is checked too.
  auto error = [](const std::string& attributes) {
    return LoadError(Experiment(Robot("r"), "\n" + Controllers(attributes), "4,4,1", "", kDouble));
  };
  ExpectMentions(error("elevation_speed=\"0\""),
                 {":2:", "<manipulator>", "attribute 'elevation_speed'", "> 0"});
  ExpectMentions(error("rotation_speed=\"-1\""), {":2:", "attribute 'rotation_speed'", "> 0"});
  ExpectMentions(error("switch_time=\"soon\""), {"attribute 'switch_time'", "not a finite number"});
  ExpectMentions(error("min_elevation=\"-0.01\""), {"attribute 'min_elevation'", ">= 0"});
  ExpectMentions(error("min_elevation=\"0.1\" max_elevation=\"0.1\""),
                 {":2:", "attribute 'max_elevation'", "must be below max_elevation",
                  "min_elevation < max_elevation"});
  // Only one bound given: checked against the robot's other bound (0.2).
  ExpectMentions(error("min_elevation=\"0.25\""),
                 {"attribute 'min_elevation'", "(0.25) must be below max_elevation (0.2)"});
  ExpectMentions(error("max_elevation=\"0.02\""),
                 {"attribute 'max_elevation'", "(0.03) must be below max_elevation (0.02)"});
  ExpectMentions(error("elevation=\"0.1\""), {"attribute 'elevation'", "unknown attribute"});
  // A malformed bound is reported once, not also as an empty range.
  const std::string malformed = error("max_elevation=\"high\"");
  ExpectMentions(malformed, {"attribute 'max_elevation'", "not a finite number"});
  EXPECT_EQ(malformed.find("must be below"), std::string::npos) << malformed;
}

TEST(ManipulatorActuator, RobotWithoutManipulatorIsRejected) {
  const std::string m =
      LoadError(Experiment(Robot("r", false), Controllers(), "4,4,1", "", kDouble));
  ExpectMentions(m, {"<manipulator>: robot 'r' (a marxbot", "cannot carry this actuator",
                     "declare the marxbot with manipulator=\"true\""});
}

TEST(ManipulatorActuator, EnginesThatDoNotSimulateItRejectItAtLoadTime) {
  const std::string m = LoadError(
      Experiment(Robot("r"), Controllers(), "4,4,1", "", "<manipulator_actuator_none id=\"n\"/>"));
  ExpectMentions(m, {"<manipulator>: robot 'r' (a marxbot",
                     "its physics engine (manipulator_actuator_none 'n') does not simulate the "
                     "manipulator of a marxbot; use ",
                     "manipulator_actuator_double"});
  if (testing::HaveEngine("kinematics2d")) ExpectMentions(m, {"kinematics2d"});
}

TEST(ManipulatorActuator, RegisteredAttributesMatchTheReadme) {
  const auto* entry = Registry<ActuatorSystem>::Get().Find("manipulator");
  ASSERT_NE(entry, nullptr);
  const std::vector<std::string> registered = entry->info.AttributeNames();
  EXPECT_EQ(registered,
            (std::vector<std::string>{"min_elevation", "max_elevation", "elevation_speed",
                                      "rotation_speed", "tilt_speed", "switch_time"}));
  EXPECT_EQ(testing::ReadmeAttributes("actuators/manipulator"), registered);
}

}  // namespace
}  // namespace colony
