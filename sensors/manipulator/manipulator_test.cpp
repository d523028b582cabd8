// The manipulator sensor as a controller sees it: the head's elevation and
// rotation, the magnet, whether something is held, and the 6 IR sensors of
// the head's IR side, which see solid things in front of that side at the
// head's height (not the object the magnet holds).
#include "sensors/manipulator/manipulator.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "actuators/manipulator/manipulator.h"
#include "actuators/manipulator/manipulator_state.h"
#include "core/registry.h"
#include "entities/marxbot/marxbot.h"
#include "tests/test_util.h"

namespace colony {
namespace {

using testing::Experiment;
using testing::LoadError;
using testing::LoadXml;

// Test double for the device logic, not physics: an engine that declares it
// simulates the manipulator and, every step, puts each head where its
// commands ask (elevation and rotation jump to their targets) and moves the
// magnet towards its command by dt / switch_time. Nothing moves; holding is
// set by the tests.
class ManipulatorDoubleEngine : public PhysicsEngine {
 public:
  void AddEntity(EntityHandle, PhysicsModel&) override {}
  void RemoveEntity(EntityHandle) override {}
  void Step(double dt) override {
    Space& space = sim().space();
    for (uint32_t s = 0; s < space.slots(); ++s) {
      ManipulatorState* m = space.alive(s) && Owns(s) ? space.Get<ManipulatorState>(s) : nullptr;
      if (!m) continue;
      m->elevation = m->target_elevation;
      m->rotation = m->target_rotation;
      // Exactly 0 or 1 at the ends (ten steps of 0.1 do not add up to 1).
      const double step = dt / m->switch_time + 1e-9;
      m->magnet = std::clamp(m->magnet + (m->want_magnet ? step : -step), 0.0, 1.0);
    }
  }
};
class DoubleModel : public PhysicsModel {};
// The head where the commands put it: its pivot just in front of the body,
// at the base + elevation, turned by the rotation.
class DoubleMarxbotModel : public PhysicsModel {
 public:
  bool Anchor(const Space& space, uint32_t s, std::string_view name, Pose& pose) const override {
    const ManipulatorState* m = space.Get<ManipulatorState>(s);
    if (name != ManipulatorState::kHeadAnchor || !m) return false;
    const Pose& robot = space.pose(s);
    pose.position =
        robot.position +
        robot.orientation * Vec3(marxbot::kBodyRadius + 0.5 * marxbot::kHeadDepth, 0, m->elevation);
    pose.orientation = robot.orientation * FromYaw(m->rotation);
    return true;
  }
};
COLONY_REGISTER_ENGINE(ManipulatorDoubleEngine, "manipulator_sensor_double",
                       "test double: heads jump to their commands; nothing moves", {});
COLONY_REGISTER_PHYSICS_MODEL(DoubleMarxbotModel, "manipulator_sensor_double:marxbot",
                              "test double", (std::vector<std::string>{"drive", "manipulator"}));
COLONY_REGISTER_PHYSICS_MODEL(DoubleModel, "manipulator_sensor_double:cube", "test double", {});
// An engine whose marXbot model does not simulate the manipulator.
COLONY_REGISTER_ENGINE(ManipulatorDoubleEngine, "manipulator_sensor_none",
                       "test double: simulates no manipulator", {});
COLONY_REGISTER_PHYSICS_MODEL(DoubleModel, "manipulator_sensor_none:marxbot", "test double",
                              (std::vector<std::string>{"drive"}));
COLONY_REGISTER_PHYSICS_MODEL(DoubleModel, "manipulator_sensor_double:box", "test double", {});

// Sends the commands in its public fields and copies what the sensor read.
class ManipulatorProbe : public Controller {
 public:
  void Init(const Params&) override {
    arm_ = &GetActuator<ManipulatorActuator>("manipulator");
    sensor = &GetSensor<ManipulatorSensor>("manipulator");
  }
  void ControlStep() override {
    last = sensor->readings();
    arm_->SetElevation(elevation);
    arm_->SetRotation(rotation);
    if (magnet) {
      arm_->EngageMagnet();
    } else {
      arm_->DisengageMagnet();
    }
  }
  double elevation = 0.03, rotation = ManipulatorActuator::kIrSide;
  bool magnet = false;
  const ManipulatorSensor* sensor = nullptr;
  std::vector<ManipulatorSensor::Reading> last;

 private:
  ManipulatorActuator* arm_ = nullptr;
};
COLONY_REGISTER_CONTROLLER(ManipulatorProbe, "manipulator_probe",
                           "test: scripted manipulator, records its sensor");

const std::string kDouble = "<manipulator_sensor_double id=\"dbl\"/>";

std::string Controllers(const std::string& sensor_attributes = "") {
  return "<manipulator_probe "
         "id=\"mp\"><actuators><manipulator/></actuators><sensors><manipulator " +
         sensor_attributes + "/></sensors></manipulator_probe>";
}

std::string Robot(const std::string& id, const std::string& position, double yaw_degrees = 0,
                  bool manipulator = true) {
  return "<marxbot id=\"" + id + "\"" + (manipulator ? " manipulator=\"true\"" : "") +
         "><body position=\"" + position + "\" orientation=\"" + std::to_string(yaw_degrees) +
         ",0,0\"/><controller config=\"mp\"/></marxbot>";
}

std::string Cube(const std::string& id, const std::string& position) {
  return "<cube id=\"" + id + "\"><body position=\"" + position + "\"/></cube>";
}

std::unique_ptr<Simulation> Load(const std::string& arena,
                                 const std::string& sensor_attributes = "",
                                 std::optional<int> threads = std::nullopt) {
  return LoadXml(Experiment(arena, Controllers(sensor_attributes), "4,4,1", "", kDouble), {},
                 threads);
}

ManipulatorProbe& Probe(Simulation& sim, const std::string& robot = "r") {
  return dynamic_cast<ManipulatorProbe&>(*sim.ControllerOf(sim.space().Find(robot)));
}

void Ticks(Simulation& sim, int ticks) {
  for (int t = 0; t < ticks; ++t) sim.Step();
}

std::vector<float> Values(const ManipulatorProbe& p) {
  std::vector<float> v;
  for (const auto& r : p.last) v.push_back(r.value);
  return v;
}

// The IR face of a robot at the origin facing +x with its IR side to the
// front (rotation pi): the head's pivot is 0.1 m ahead of the axis (body
// radius 0.085 + half the head's 3 cm depth), its IR face 1.5 cm further.
constexpr double kIrFaceX = 0.115;

// What sensor i of that robot reads of a face x = face, |y| <= half (the
// near face of a box ahead): sensor i sits (i - 2.5) * 5/6 cm to the left of
// the face's centre and looks (i - 2.5) * 15 degrees to the left.
double ExpectedOnFace(int i, double face, double half, double range = 0.1) {
  const double a = DegToRad((i - 2.5) * 15), oy = (i - 2.5) * 0.05 / 6;
  const double t = (face - kIrFaceX) / std::cos(a);
  if (std::abs(oy + t * std::sin(a)) > half || t > range) return 0;
  return std::min(1.0, 0.01 / t);
}

TEST(ManipulatorSensor, SixSensorsFannedFifteenDegreesApart) {
  auto sim = Load(Robot("r", "0,0,0"));
  Ticks(*sim, 1);
  const auto& r = Probe(*sim).last;
  ASSERT_EQ(r.size(), 6u);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(r[i].angle, DegToRad(-37.5 + 15 * i), 1e-6) << i;
}

TEST(ManipulatorSensor, JointsAndMagnetFollowTheCommands) {
  auto sim = Load(Robot("r", "0,0,0"));
  ManipulatorProbe& p = Probe(*sim);
  Ticks(*sim, 1);
  EXPECT_NEAR(p.sensor->elevation(), 0.03, 1e-12) << "the head starts at its lowest";
  EXPECT_EQ(p.sensor->magnet(), 0.0);
  p.elevation = 0.15;
  p.rotation = -1.0;
  p.magnet = true;
  Ticks(*sim, 2);
  EXPECT_DOUBLE_EQ(p.sensor->elevation(), 0.15);
  EXPECT_DOUBLE_EQ(p.sensor->rotation(), -1.0);
  // The magnet switches over switch_time (1 s, 10 ticks): one tick in.
  EXPECT_NEAR(p.sensor->magnet(), 0.1, 1e-8);
  EXPECT_FALSE(p.sensor->magnet_engaged());
  Ticks(*sim, 8);
  EXPECT_NEAR(p.sensor->magnet(), 0.9, 1e-8);
  EXPECT_FALSE(p.sensor->magnet_engaged());
  Ticks(*sim, 1);
  EXPECT_DOUBLE_EQ(p.sensor->magnet(), 1.0);
  EXPECT_TRUE(p.sensor->magnet_engaged());
  EXPECT_FALSE(p.sensor->holding());
  p.magnet = false;
  Ticks(*sim, 2);
  EXPECT_FALSE(p.sensor->magnet_engaged());
}

TEST(ManipulatorSensor, ReportsWhatTheEngineSaysIsHeld) {
  auto sim = Load(Robot("r", "0,0,0") + Cube("c", "0.5,0,0"));
  ManipulatorProbe& p = Probe(*sim);
  Ticks(*sim, 1);
  EXPECT_FALSE(p.sensor->holding());
  sim->space().Get<ManipulatorState>(sim->space().Find("r").index)->held =
      sim->space().Find("c").index;
  Ticks(*sim, 1);
  EXPECT_TRUE(p.sensor->holding());
}

TEST(ManipulatorSensor, IrSideSeesACubeInFrontAtTheHeadsHeight) {
  // IR side to the front (rotation pi); a 6 cm cube 3 cm in front of the IR face.
  auto sim = Load(Robot("r", "0,0,0") + Cube("c", "0.175,0,0"));
  ManipulatorProbe& p = Probe(*sim);
  Ticks(*sim, 3);
  const auto v = Values(p);
  ASSERT_EQ(v.size(), 6u);
  for (int i = 0; i < 6; ++i)
    EXPECT_NEAR(v[i], ExpectedOnFace(i, 0.145, 0.03), 1e-5) << "sensor " << i;
  EXPECT_GT(v[2], 0.3f) << "the two middle sensors see it about 3 cm away";
  EXPECT_FLOAT_EQ(v[2], v[3]);
  EXPECT_FLOAT_EQ(v[1], v[4]);
  EXPECT_EQ(v[0], 0.0f) << "the outer sensors look past it";
  EXPECT_EQ(v[5], 0.0f);
  // Raised above the cube's top (6 cm), the rays pass over it.
  p.elevation = 0.08;
  Ticks(*sim, 2);
  for (float x : Values(p)) EXPECT_EQ(x, 0.0f);
}

TEST(ManipulatorSensor, OffCentreCubeIsSeenMoreOnItsSide) {
  // The cube 2 cm to the left (+y) of the IR side's axis: the left sensors read more.
  auto sim = Load(Robot("r", "0,0,0") + Cube("c", "0.175,0.02,0"));
  ManipulatorProbe& p = Probe(*sim);
  Ticks(*sim, 3);
  const auto v = Values(p);
  EXPECT_GT(v[3] + v[4] + v[5], v[0] + v[1] + v[2]);
  EXPECT_GT(v[4], 0.0f);
}

TEST(ManipulatorSensor, IrSideTurnsWithTheHeadAndTheRobot) {
  // The robot faces +y (yaw 90 degrees): its head's pivot is at (0, 0.1).
  // One cube ahead of the head, one to the right of it (+x). The IR side
  // faces yaw + rotation + pi.
  auto sim =
      Load(Robot("r", "0,0,0", 90) + Cube("ahead", "0,0.175,0") + Cube("right", "0.12,0.1,0"));
  ManipulatorProbe& p = Probe(*sim);
  auto seen = [&](double rotation) {
    p.rotation = rotation;
    Ticks(*sim, 2);
    return Values(p)[2];
  };
  EXPECT_GT(seen(ManipulatorActuator::kIrSide), 0.3f)
      << "IR side to the front: the cube ahead, 3 cm away";
  EXPECT_EQ(seen(ManipulatorActuator::kMagnetSide), 0.0f)
      << "IR side to the back: it faces the body";
  EXPECT_NEAR(seen(M_PI / 2), 0.13, 0.01)
      << "facing 90 + 90 + 180 = 0 degrees: the cube on the right, 7.5 cm away";
  EXPECT_EQ(seen(-M_PI / 2), 0.0f) << "facing 180 degrees: nothing there";
}

TEST(ManipulatorSensor, TheRobotsOwnBodyHidesWhatIsBehindIt) {
  // Range 0.3 m. With the magnet to the front, the IR side faces the body:
  // a cube behind the robot, 20 cm from the IR face through the body, is
  // hidden; a cube 10 cm in front of the IR side turned forwards is seen.
  auto sim = Load(Robot("r", "0,0,0") + Cube("behind", "-0.15,0,0") + Cube("ahead", "0.245,0,0"),
                  "range=\"0.3\"");
  ManipulatorProbe& p = Probe(*sim);
  p.rotation = ManipulatorActuator::kMagnetSide;
  Ticks(*sim, 3);
  for (float x : Values(p)) EXPECT_EQ(x, 0.0f);
  p.rotation = ManipulatorActuator::kIrSide;
  Ticks(*sim, 2);
  EXPECT_NEAR(Values(p)[2], ExpectedOnFace(2, 0.215, 0.03, 0.3), 1e-5);
  EXPECT_GT(Values(p)[2], 0.09f);
}

TEST(ManipulatorSensor, HeldCubeIsNotSeen) {
  auto sim = Load(Robot("r", "0,0,0") + Cube("c", "0.175,0,0"));
  ManipulatorProbe& p = Probe(*sim);
  Ticks(*sim, 3);
  EXPECT_GT(Values(p)[2], 0.3f);
  sim->space().Get<ManipulatorState>(sim->space().Find("r").index)->held =
      sim->space().Find("c").index;
  Ticks(*sim, 1);
  for (float x : Values(p)) EXPECT_EQ(x, 0.0f);
}

TEST(ManipulatorSensor, TallThingsAreSeenAtAnyHeightBeyondRangeNothing) {
  // A 30 cm box 2 cm in front of the IR face.
  const std::string box =
      "<box id=\"b\" size=\"0.04,0.2,0.3\" movable=\"true\"><body position=\"0.155,0,0\"/></box>";
  auto sim = Load(Robot("r", "0,0,0") + box);
  ManipulatorProbe& p = Probe(*sim);
  for (double elevation : {0.03, 0.1, 0.2}) {
    p.elevation = elevation;
    Ticks(*sim, 2);
    for (int i = 0; i < 6; ++i)
      EXPECT_NEAR(Values(p)[i], ExpectedOnFace(i, 0.135, 0.1), 1e-5) << elevation << " " << i;
  }
  // Moved to 12 cm from the IR face: beyond the 0.1 m range.
  sim->space().pose(sim->space().Find("b").index).position.x() = kIrFaceX + 0.12 + 0.02;
  Ticks(*sim, 1);
  for (float x : Values(p)) EXPECT_EQ(x, 0.0f);
  // With range 0.2 it is seen again.
  auto longer = Load(Robot("r", "0,0,0") + box, "range=\"0.2\"");
  longer->space().pose(longer->space().Find("b").index).position.x() = kIrFaceX + 0.12 + 0.02;
  Ticks(*longer, 2);
  EXPECT_NEAR(Values(Probe(*longer))[2], ExpectedOnFace(2, kIrFaceX + 0.12, 0.1, 0.2), 1e-5);
  EXPECT_GT(Values(Probe(*longer))[2], 0.08f);
}

TEST(ManipulatorSensor, NoiseIsReproducibleAndDropsReadZero) {
  const std::string arena = Robot("r", "0,0,0") + Cube("c", "0.175,0,0");
  auto a = Load(arena, "noise=\"gaussian\" noise_std_dev=\"0.05\"");
  auto b = Load(arena, "noise=\"gaussian\" noise_std_dev=\"0.05\"");
  bool changed = false;
  for (int t = 0; t < 5; ++t) {
    a->Step();
    b->Step();
    const auto va = Values(Probe(*a)), vb = Values(Probe(*b));
    EXPECT_EQ(va, vb);
    for (float x : va) EXPECT_TRUE(x >= 0 && x <= 1) << x;
    changed = changed || std::abs(va[2] - va[3]) > 1e-6;
  }
  EXPECT_TRUE(changed) << "noise makes the two middle sensors differ";
  auto dropped = Load(arena, "drop_probability=\"1\"");
  Ticks(*dropped, 3);
  for (float x : Values(Probe(*dropped))) EXPECT_EQ(x, 0.0f);
}

TEST(ManipulatorSensor, ResultsDoNotDependOnTheThreadCount) {
  // 40 robots in a grid, cubes between them, noisy sensors.
  std::string arena;
  for (int i = 0; i < 40; ++i) {
    const double x = -1.5 + 0.4 * (i % 8), y = -1.5 + 0.5 * (i / 8);
    arena += Robot("r" + std::to_string(i), std::to_string(x) + "," + std::to_string(y) + ",0",
                   37.0 * i);
    arena += Cube("c" + std::to_string(i),
                  std::to_string(x + 0.17) + "," + std::to_string(y + 0.01 * (i % 5)) + ",0");
  }
  std::vector<uint64_t> hashes;
  for (int threads : {0, 1, 2}) {
    auto sim = Load(arena, "noise=\"gaussian\" noise_std_dev=\"0.02\"", threads);
    Ticks(*sim, 5);
    hashes.push_back(sim->StateHash());
  }
  EXPECT_EQ(hashes[0], hashes[1]);
  EXPECT_EQ(hashes[0], hashes[2]);
}

void ExpectMentions(const std::string& message, const std::vector<std::string>& parts) {
  for (const auto& p : parts)
    EXPECT_NE(message.find(p), std::string::npos) << "'" << p << "' in: " << message;
}

TEST(ManipulatorSensor, RobotsAndEnginesThatCannotCarryItAreRejected) {
  const std::string no_arm =
      LoadError(Experiment(Robot("r", "0,0,0", 0, false),
                           "<manipulator_probe id=\"mp\"><sensors><manipulator/></sensors>"
                           "</manipulator_probe>",
                           "4,4,1", "", kDouble));
  ExpectMentions(no_arm, {"<manipulator>: robot 'r' (a marxbot", "cannot carry this sensor",
                          "declare the marxbot with manipulator=\"true\""});
  const std::string none =
      LoadError(Experiment(Robot("r", "0,0,0"),
                           "<manipulator_probe id=\"mp\"><sensors><manipulator/></sensors>"
                           "</manipulator_probe>",
                           "4,4,1", "", "<manipulator_sensor_none id=\"n\"/>"));
  ExpectMentions(none, {"<manipulator>: robot 'r' (a marxbot", "cannot carry this sensor",
                        "its physics engine (manipulator_sensor_none 'n') does not simulate the "
                        "manipulator of a marxbot; use ",
                        "manipulator_sensor_double"});
}

// The check is made for each robot, not once per controller: a robot
// without the arm after one with it is rejected by name.
TEST(ManipulatorSensor, ARobotWithoutTheArmIsRejectedAfterOneWithIt) {
  const std::string second = LoadError(Experiment(
      Robot("a", "-1,0,0") + Robot("b", "1,0,0", 0, false), Controllers(), "4,4,1", "", kDouble));
  ExpectMentions(second, {"<manipulator>: robot 'b' (a marxbot", "cannot carry this sensor",
                          "declare the marxbot with manipulator=\"true\""});
  EXPECT_EQ(second.find("robot 'a'"), std::string::npos) << second;
}

TEST(ManipulatorSensor, BadAttributesAreReportedWithElementAndLine) {
  auto error = [](const std::string& attributes) {
    return LoadError(
        Experiment(Robot("r", "0,0,0"), "\n" + Controllers(attributes), "4,4,1", "", kDouble));
  };
  ExpectMentions(error("range=\"0\""), {":2:", "<manipulator>", "attribute 'range'", "> 0"});
  ExpectMentions(error("range=\"far\""), {"attribute 'range'", "not a finite number"});
  ExpectMentions(error("noise=\"gaussian\""), {"attribute 'noise_std_dev'"});
  ExpectMentions(error("rnage=\"0.1\""), {"attribute 'rnage'", "did you mean 'range'"});
}

TEST(ManipulatorSensor, RegisteredAttributesMatchTheReadme) {
  const auto* entry = Registry<SensorSystem>::Get().Find("manipulator");
  ASSERT_NE(entry, nullptr);
  const std::vector<std::string> registered = entry->info.AttributeNames();
  EXPECT_EQ(registered, (std::vector<std::string>{"range", "noise", "noise_std_dev", "noise_range",
                                                  "drop_probability"}));
  EXPECT_EQ(testing::ReadmeAttributes("sensors/manipulator"), registered);
}

}  // namespace
}  // namespace colony
