// The manipulator in kinematics2d, as seed 004's pick-up uses it: the head
// lowered with its IR side ahead finds a pocket with its IR sensors as the
// robot drives towards it; tilted onto the pocket's top with the magnet
// engaged it picks the pocket up, carries it as the robot drives, and drops
// it where the robot stands when the magnet is switched off. Also: the tilt
// moves at its speed within its range, and dynamics3d refuses it.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "actuators/differential_steering/differential_steering.h"
#include "actuators/manipulator/manipulator.h"
#include "actuators/manipulator/manipulator_state.h"
#include "entities/marxbot/marxbot.h"
#include "entities/objects/pocket.h"
#include "sensors/manipulator/manipulator.h"
#include "tests/test_util.h"

namespace colony {
namespace {

using testing::Experiment;
using testing::LoadXml;

// Sends the commands in its public fields; copies what the sensor read.
class PocketArmProbe : public Controller {
 public:
  void Init(const Params&) override {
    arm_ = &GetActuator<ManipulatorActuator>("manipulator");
    wheels_ = &GetActuator<DifferentialSteering>("differential_steering");
    sensor = &GetSensor<ManipulatorSensor>("manipulator");
  }
  void ControlStep() override {
    ir.clear();
    for (const auto& r : sensor->readings()) ir.push_back(r.value);
    wheels_->SetLinearVelocity(speed, speed);
    arm_->SetElevation(elevation);
    arm_->SetRotation(rotation);
    arm_->SetTilt(tilt);
    if (magnet) {
      arm_->EngageMagnet();
    } else {
      arm_->DisengageMagnet();
    }
  }
  double MiddleIr() const { return ir.empty() ? 0.0 : std::max(ir[2], ir[3]); }

  double speed = 0, elevation = 0.03, rotation = ManipulatorActuator::kIrSide, tilt = 0;
  bool magnet = false;
  const ManipulatorSensor* sensor = nullptr;
  std::vector<float> ir;

 private:
  ManipulatorActuator* arm_ = nullptr;
  DifferentialSteering* wheels_ = nullptr;
};
COLONY_REGISTER_CONTROLLER(PocketArmProbe, "pocket_arm_probe",
                           "test: scripted manipulator and wheels");

const std::string kControllers =
    "<pocket_arm_probe id=\"pp\"><actuators><manipulator/><differential_steering/></actuators>"
    "<sensors><manipulator/></sensors></pocket_arm_probe>";

std::string Robot(const std::string& id, const std::string& position) {
  return "<marxbot id=\"" + id + "\" manipulator=\"true\"><body position=\"" + position +
         "\" orientation=\"0,0,0\"/><controller config=\"pp\"/></marxbot>";
}

// A pocket lying across the robot's path (+x): its long axis along y.
std::string Pocket(const std::string& id, const std::string& position) {
  return "<pocket id=\"" + id + "\"><body position=\"" + position +
         "\" orientation=\"90,0,0\"/></pocket>";
}

std::unique_ptr<Simulation> Load(const std::string& arena, std::optional<int> threads = {},
                                 const std::string& engine = "<kinematics2d id=\"k2d\"/>") {
  return LoadXml(Experiment(arena, kControllers, "4,4,1", "", engine), {}, threads);
}

PocketArmProbe& Probe(Simulation& sim, const std::string& robot = "r") {
  return dynamic_cast<PocketArmProbe&>(*sim.ControllerOf(sim.space().Find(robot)));
}

const PocketState& PocketOf(Simulation& sim, const std::string& id) {
  return *sim.space().Get<PocketState>(sim.space().Find(id).index);
}

Pose Head(Simulation& sim, const std::string& robot = "r") {
  Pose head;
  EXPECT_TRUE(sim.Anchor(sim.space().Find(robot), ManipulatorState::kHeadAnchor, head));
  return head;
}

// Runs until `done` or `seconds` pass; returns whether `done` came.
template <class F>
bool RunUntil(Simulation& sim, double seconds, F done) {
  const int ticks = static_cast<int>(std::lround(seconds / sim.dt()));
  for (int t = 0; t < ticks; ++t) {
    sim.Step();
    if (done()) return true;
  }
  return false;
}

// Seed 004's approach and pick-up, then 1 m of carrying and the drop. The
// pocket lies 0.4 m ahead of the robot, across its path. Returns the
// simulation after the drop.
struct PickUpRun {
  std::unique_ptr<Simulation> sim;
  double detected_at = 0;  // robot x when the IR sensors first saw the pocket (m)
};

PickUpRun PickUpCarryDrop(const std::string& extra_arena = "", std::optional<int> threads = {},
                          const std::string& engine = "<kinematics2d id=\"k2d\"/>") {
  PickUpRun run;
  run.sim = Load(Robot("r", "-0.6,0,0") + Pocket("p", "-0.2,0,0") + extra_arena, threads, engine);
  Simulation& sim = *run.sim;
  PocketArmProbe& probe = Probe(sim);
  const uint32_t robot = sim.space().Find("r").index;
  // Lie down: IR side ahead (the head turns pi rad at 1 rad/s), lowest, IR
  // face turned 45 degrees down.
  probe.tilt = -M_PI / 4;
  testing::RunFor(sim, 4.0);
  EXPECT_TRUE(std::all_of(probe.ir.begin(), probe.ir.end(), [](float v) { return v == 0; }))
      << "the floor is not seen";
  // Drive towards the pocket until the IR sensors see it.
  probe.speed = 0.1;
  EXPECT_TRUE(RunUntil(sim, 5, [&] { return probe.MiddleIr() > 0.5; }))
      << "the IR sensors see the pocket";
  run.detected_at = sim.space().pose(robot).position.x();
  // Creep on until the body touches it, then rise onto its top: magnet face down.
  probe.speed = 0.05;
  testing::RunFor(sim, 1.0);
  probe.speed = 0;
  probe.tilt = M_PI / 2;
  testing::RunFor(sim, 3.0);
  EXPECT_EQ(PocketOf(sim, "p").holder, PocketState::kNobody) << "magnet still off";
  probe.magnet = true;
  EXPECT_TRUE(RunUntil(sim, 3, [&] { return probe.sensor->holding(); })) << "picks it up";
  // Raise it and drive 1 m.
  probe.elevation = 0.1;
  testing::RunFor(sim, 2.0);
  probe.speed = 0.1;
  testing::RunFor(sim, 10.0);
  probe.speed = 0;
  probe.magnet = false;
  testing::RunFor(sim, 0.5);
  return run;
}

void ExpectFoundPickedUpCarriedAndDropped(const PickUpRun& run) {
  Simulation& sim = *run.sim;
  // Seen when the pocket's near edge (x = -0.235) came within about 2 cm of
  // the IR face (0.115 ahead of the robot's axis).
  EXPECT_GT(run.detected_at, -0.235 - 0.115 - 0.025);
  EXPECT_LT(run.detected_at, -0.235 - 0.115 + 0.01);
  const PocketState& p = PocketOf(sim, "p");
  EXPECT_EQ(p.holder, PocketState::kNobody) << "dropped";
  EXPECT_FALSE(Probe(sim).sensor->holding());
  const Vec3 pocket = testing::PositionOf(sim, "p");
  const Vec3 robot = testing::PositionOf(sim, "r");
  const Pose head = Head(sim);
  EXPECT_GT(robot.x(), 0.6) << "the robot drove about 1 m with it (from -0.32)";
  EXPECT_LT((pocket.head<2>() - head.position.head<2>()).norm(), 0.03)
      << "dropped where the head is";
  EXPECT_NEAR(pocket.z(), 0.0, 1e-9) << "settled on the floor";
  EXPECT_NEAR(YawOf(sim.space().pose(sim.space().Find("p").index).orientation), M_PI / 2, 1e-6)
      << "its heading kept";
}

TEST(Manipulator2d, FindsPicksUpCarriesAndDropsAPocket) {
  ExpectFoundPickedUpCarriedAndDropped(PickUpCarryDrop());
}

TEST(Manipulator2d, Dynamics2dToo) {
  if (!testing::HaveEngine("dynamics2d")) GTEST_SKIP() << "dynamics2d not compiled in";
  ExpectFoundPickedUpCarriedAndDropped(PickUpCarryDrop("", {}, "<dynamics2d id=\"d2d\"/>"));
}

TEST(Manipulator2d, AHeldPocketMovesWithTheHead) {
  auto sim = Load(Robot("r", "-0.6,0,0") + Pocket("p", "-0.478,0,0"));
  PocketArmProbe& probe = Probe(*sim);
  probe.tilt = M_PI / 2;
  probe.magnet = true;
  ASSERT_TRUE(RunUntil(*sim, 4, [&] { return probe.sensor->holding(); }));
  const PocketState& p = PocketOf(*sim, "p");
  EXPECT_EQ(p.holder, sim->space().Find("r").index);
  probe.elevation = 0.12;
  probe.speed = 0.1;
  for (int t = 0; t < 40; ++t) {
    sim->Step();
    const Pose head = Head(*sim);
    const Vec3 face =
        head.position + 0.5 * marxbot::kHeadDepth * (head.orientation * Vec3::UnitX());
    const Vec3 pocket = testing::PositionOf(*sim, "p");
    EXPECT_LT((pocket.head<2>() - face.head<2>()).norm(), 0.03) << "tick " << t;
    EXPECT_NEAR(pocket.z() + pocket::kThickness, face.z(), 1e-6) << "hangs under the magnet";
  }
  EXPECT_GT(testing::PositionOf(*sim, "p").z(), 0.05) << "lifted";
}

TEST(Manipulator2d, ADroppedPocketSettlesOnThePocketBelow) {
  // A second pocket lies just beyond where the robot stops, 1 m on (its
  // body stops at x = 0.765; the carried pocket is then over x = 0.8).
  PickUpRun run = PickUpCarryDrop(Pocket("under", "0.81,0,0"));
  Simulation& sim = *run.sim;
  const Vec3 top = testing::PositionOf(sim, "p");
  const Vec3 below = testing::PositionOf(sim, "under");
  ASSERT_EQ(PocketOf(sim, "p").holder, PocketState::kNobody);
  EXPECT_NEAR(below.z(), 0.0, 1e-9);
  EXPECT_NEAR(top.z(), pocket::kThickness, 1e-9)
      << "on top of the other: " << top.transpose() << " / " << below.transpose() << " robot "
      << testing::PositionOf(sim, "r").transpose();
  EXPECT_GT(PocketOf(sim, "under").occlusion, 0.0);
}

TEST(Manipulator2d, TiltedIrRaysSeeAPocketTheUprightHeadMisses) {
  // IR side ahead, head at its lowest (centre 3 cm up). Upright, the rays
  // run 3 cm above the floor, over a 1.5 cm pocket. Tilted 45 degrees down,
  // the IR face's centre is at x = 0.1 + 0.015 cos 45, z = 0.03 - 0.015 sin 45,
  // and sensor i's ray, fanned f_i about the face's normal, drops 1 cm while
  // it advances 1 cm: a pocket whose near side is 1 cm ahead of the face is
  // hit there, at a distance 0.01 / (cos f_i sin 45), reading cos f_i sin 45.
  const double face_x = marxbot::kHeadPivotX + 0.015 * std::cos(M_PI / 4);
  const double near_side = face_x + 0.01;
  auto sim = Load(Robot("r", "0,0,0") + Pocket("p", std::to_string(near_side + 0.035) + ",0,0"));
  PocketArmProbe& probe = Probe(*sim);
  testing::RunFor(*sim, 4.0);  // the head turns its IR side ahead (pi rad at 1 rad/s)
  ASSERT_DOUBLE_EQ(probe.sensor->rotation(), M_PI);
  for (float v : probe.ir) EXPECT_EQ(v, 0.0f) << "upright: over the pocket";
  probe.tilt = -M_PI / 4;
  testing::RunFor(*sim, 1.5);
  ASSERT_EQ(probe.ir.size(), 6u);
  for (int i = 0; i < 6; ++i) {
    const double f = DegToRad(-37.5 + 15 * i);
    EXPECT_NEAR(probe.ir[i], std::cos(f) * std::sin(M_PI / 4), 1e-4) << "sensor " << i;
  }
}

TEST(Manipulator2d, TiltMovesAtItsSpeedWithinItsRange) {
  auto sim = Load(Robot("r", "0,0,0"));
  PocketArmProbe& probe = Probe(*sim);
  probe.tilt = 1.0;
  sim->Step();  // the command reaches the state
  double last = probe.sensor->tilt();
  for (int t = 0; t < 12; ++t) {
    sim->Step();
    const double now = probe.sensor->tilt();
    EXPECT_LE(now - last, 1.0 * sim->dt() + 1e-12) << "1 rad/s";
    last = now;
  }
  EXPECT_DOUBLE_EQ(probe.sensor->tilt(), 1.0);
  // Beyond the range: it goes to the limit, and says so.
  ::testing::internal::CaptureStderr();
  probe.tilt = 3.0;
  testing::RunFor(*sim, 2.0);
  const std::string said = ::testing::internal::GetCapturedStderr();
  EXPECT_DOUBLE_EQ(probe.sensor->tilt(), M_PI / 2);
  EXPECT_NE(said.find("tilt 3 rad"), std::string::npos) << said;
  EXPECT_NE(said.find("outside its range"), std::string::npos) << said;
  EXPECT_EQ(said.find("tilt 3 rad"), said.rfind("tilt 3 rad")) << "once: " << said;
}

TEST(Manipulator2d, TheMagnetHoldsOnlyAPocketItLiesOn) {
  // Upright head (tilt 0): the magnet faces ahead, not down: nothing held.
  auto sim = Load(Robot("r", "-0.6,0,0") + Pocket("p", "-0.478,0,0"));
  PocketArmProbe& probe = Probe(*sim);
  probe.magnet = true;
  testing::RunFor(*sim, 3.0);
  EXPECT_FALSE(probe.sensor->holding());
  // Face down but 3 cm above the top: nothing held.
  probe.tilt = M_PI / 2;
  probe.elevation = 0.06;
  testing::RunFor(*sim, 3.0);
  EXPECT_FALSE(probe.sensor->holding());
  probe.elevation = 0.03;
  testing::RunFor(*sim, 1.0);
  EXPECT_TRUE(probe.sensor->holding());
}

TEST(Manipulator2d, APocketUnderAnotherIsNotPulledOutOfTheHeap) {
  auto sim = Load(Robot("r", "-0.6,0,0") + Pocket("p", "-0.478,0,0") +
                  "<pocket id=\"top\"><body position=\"-0.478,0,0.1\" orientation=\"90,0,0\"/>"
                  "</pocket>");
  ASSERT_NEAR(testing::PositionOf(*sim, "top").z(), pocket::kThickness, 1e-9);
  PocketArmProbe& probe = Probe(*sim);
  probe.tilt = M_PI / 2;
  probe.magnet = true;
  testing::RunFor(*sim, 4.0);  // the face down on the lower pocket's top, inside the upper one
  EXPECT_FALSE(probe.sensor->holding()) << "the lower pocket has another on it";
  probe.elevation = 0.03 + pocket::kThickness;
  testing::RunFor(*sim, 1.0);
  ASSERT_TRUE(probe.sensor->holding());
  EXPECT_EQ(PocketOf(*sim, "top").holder, sim->space().Find("r").index);
}

TEST(Manipulator2d, APocketOverAnotherRobotStaysOnTheMagnetUntilItCanFallClear) {
  auto sim = Load(Robot("r", "-0.6,0,0") + Pocket("p", "-0.478,0,0") + Robot("o", "0,0,0"));
  PocketArmProbe& probe = Probe(*sim);
  PocketArmProbe& other = Probe(*sim, "o");
  probe.tilt = M_PI / 2;
  probe.magnet = true;
  ASSERT_TRUE(RunUntil(*sim, 4, [&] { return probe.sensor->holding(); }));
  probe.elevation = 0.1;
  testing::RunFor(*sim, 2.0);
  // Into the other robot: the pocket hangs over it.
  probe.speed = 0.1;
  testing::RunFor(*sim, 5.0);
  probe.speed = 0;
  ::testing::internal::CaptureStderr();
  probe.magnet = false;
  testing::RunFor(*sim, 2.0);
  const std::string log = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(PocketOf(*sim, "p").holder, PocketState::kNobody) << "not dropped onto the robot";
  EXPECT_NE(log.find("stays on the magnet until it can fall clear"), std::string::npos) << log;
  // Backing away, it falls clear, and the other robot can drive on.
  probe.speed = -0.1;
  testing::RunFor(*sim, 2.0);
  probe.speed = 0;
  EXPECT_EQ(PocketOf(*sim, "p").holder, PocketState::kNobody);
  EXPECT_NEAR(testing::PositionOf(*sim, "p").z(), 0.0, 1e-9);
  const double before = testing::PositionOf(*sim, "o").x();
  other.speed = 0.1;
  testing::RunFor(*sim, 2.0);
  EXPECT_GT(testing::PositionOf(*sim, "o").x(), before + 0.15) << "not stuck on the pocket";
}

TEST(Manipulator2d, ResultsDoNotDependOnTheThreadCount) {
  std::vector<uint64_t> hashes;
  for (int threads : {1, 2}) hashes.push_back(PickUpCarryDrop("", threads).sim->StateHash());
  EXPECT_EQ(hashes[0], hashes[1]);
}

TEST(Manipulator2d, Dynamics3dKeepsTheHeadUprightAndSaysSo) {
  if (!testing::HaveEngine("dynamics3d")) GTEST_SKIP() << "dynamics3d not compiled in";
  auto sim = Load(Robot("r", "0,0,0"), {}, "<dynamics3d id=\"d3d\"/>");
  PocketArmProbe& probe = Probe(*sim);
  ::testing::internal::CaptureStderr();
  probe.tilt = 1.0;
  testing::RunFor(*sim, 1.0);
  const std::string said = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(probe.sensor->tilt(), 0.0);
  EXPECT_NE(said.find("dynamics3d does not simulate the manipulator's tilt"), std::string::npos)
      << said;
}

}  // namespace
}  // namespace colony
