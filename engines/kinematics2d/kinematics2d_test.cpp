// kinematics2d as a user sees it: robots move as their wheels say, stop at
// walls, objects and each other without ever overlapping, never push
// anything, and a run is bit-identical whatever the number of threads.
#include <cmath>
#include <string>
#include <vector>

#include "actuators/differential_steering/differential_steering.h"
#include "core/geometry2d.h"
#include "core/registry.h"
#include "sensors/proximity/proximity.h"
#include "tests/test_util.h"

namespace colony {
namespace {

using testing::Experiment;
using testing::LoadError;
using testing::LoadXml;

// Drives at params left/right (m/s) from the first tick; the test may change them.
class K2dDriver : public Controller {
 public:
  void Init(const Params& params) override {
    wheels_ = &GetActuator<DifferentialSteering>("differential_steering");
    left = params.GetDouble("left", 0);
    right = params.GetDouble("right", 0);
    wheels_->SetLinearVelocity(left, right);
  }
  void ControlStep() override { wheels_->SetLinearVelocity(left, right); }
  double left = 0, right = 0;

 private:
  DifferentialSteering* wheels_ = nullptr;
};

COLONY_REGISTER_CONTROLLER(K2dDriver, "k2d_driver", "test: drives at fixed wheel speeds");

// Random walk with obstacle avoidance: picks new random wheel speeds from its
// own stream every few ticks, turns away from what its proximity ring sees.
class K2dWander : public Controller {
 public:
  void Init(const Params& params) override {
    wheels_ = &GetActuator<DifferentialSteering>("differential_steering");
    proximity_ = &GetSensor<ProximitySensor>("proximity");
  }
  void ControlStep() override {
    double x = 0, y = 0;
    for (const auto& r : proximity_->readings()) {
      x += r.value * std::cos(r.angle);
      y += r.value * std::sin(r.angle);
    }
    if (ticks_++ % 7 == 0) {
      left_ = rng().Uniform(-0.1, 0.3);
      right_ = rng().Uniform(-0.1, 0.3);
    }
    if (x > 0.3) {
      wheels_->SetLinearVelocity(y > 0 ? 0.2 : -0.2, y > 0 ? -0.2 : 0.2);
    } else {
      wheels_->SetLinearVelocity(left_, right_);
    }
  }

 private:
  DifferentialSteering* wheels_ = nullptr;
  const ProximitySensor* proximity_ = nullptr;
  int ticks_ = 0;
  double left_ = 0, right_ = 0;
};

COLONY_REGISTER_CONTROLLER(K2dWander, "k2d_wander", "test: random walk with obstacle avoidance");

const std::string kDriver =
    "<k2d_driver id=\"drive\"><actuators><differential_steering/></actuators>"
    "<params left=\"0.1\" right=\"0.1\"/></k2d_driver>"
    "<k2d_driver id=\"still\"><actuators><differential_steering/></actuators></k2d_driver>";

std::string Robot(const std::string& id, const std::string& position, double yaw_degrees = 0,
                  const std::string& config = "drive") {
  return "<marxbot id=\"" + id + "\"><body position=\"" + position + "\" orientation=\"" +
         std::to_string(yaw_degrees) + ",0,0\"/><controller config=\"" + config + "\"/></marxbot>";
}

uint32_t Slot(const Simulation& sim, const std::string& id) { return sim.space().Find(id).index; }
const Pose& PoseOf(const Simulation& sim, const std::string& id) {
  return sim.space().pose(Slot(sim, id));
}
double Yaw(const Simulation& sim, const std::string& id) {
  return YawOf(PoseOf(sim, id).orientation);
}
K2dDriver& Driver(Simulation& sim, const std::string& id) {
  auto* d = dynamic_cast<K2dDriver*>(sim.ControllerOf(sim.space().Find(id)));
  EXPECT_NE(d, nullptr);
  return *d;
}

// Whether a robot overlaps any other solid entity or leaves the arena
// (touching is allowed). Returns a description, or "".
std::string Overlap(const Simulation& sim) {
  const Space& space = sim.space();
  for (uint32_t i = 0; i < space.slots(); ++i) {
    if (!space.alive(i) || !(space.flags(i) & kRobot)) continue;
    const Pose& p = space.pose(i);
    const double r = space.geometry(i).radius;
    const Vec2 c = p.position.head<2>();
    if (c.x() - r < space.arena_min().x() - 1e-12 || c.x() + r > space.arena_max().x() + 1e-12 ||
        c.y() - r < space.arena_min().y() - 1e-12 || c.y() + r > space.arena_max().y() + 1e-12) {
      return space.id(i) + " leaves the arena";
    }
    for (uint32_t j = 0; j < space.slots(); ++j) {
      if (j == i || !space.alive(j) || !(space.flags(j) & kSolid)) continue;
      if (CircleOverlapsFootprint(c, r - 1e-12, space.pose(j), space.geometry(j))) {
        return space.id(i) + " overlaps " + space.id(j);
      }
    }
  }
  return "";
}

TEST(Kinematics2d, FreeRobotDrivesAsItsWheelsSay) {
  auto sim = LoadXml(Experiment(Robot("r", "-1,0,0", 90), kDriver));
  for (int t = 0; t < 10; ++t) sim->Step();
  EXPECT_NEAR(PoseOf(*sim, "r").position.x(), -1.0, 1e-12);
  EXPECT_NEAR(PoseOf(*sim, "r").position.y(), 0.1, 1e-9);
  EXPECT_NEAR(PoseOf(*sim, "r").position.z(), 0.0, 1e-12);
  EXPECT_FALSE(sim->space().in_contact(Slot(*sim, "r")));
  const Twist& twist = sim->space().twist(Slot(*sim, "r"));
  EXPECT_NEAR(twist.linear.y(), 0.1, 1e-9);
}

TEST(Kinematics2d, RobotStopsAtAWallWithoutOverlappingAndKeepsTurning) {
  // 10 cm walls: the east wall's inner face is at x = 1.9. The robot drives
  // east at 0.3 m/s from x = 1.
  auto sim = LoadXml(
      Experiment("<walls thickness=\"0.1\" height=\"0.5\"/>" + Robot("r", "1,0.3,0"), kDriver));
  Driver(*sim, "r").left = Driver(*sim, "r").right = 0.3;
  for (int t = 0; t < 60; ++t) {
    sim->Step();
    ASSERT_EQ(Overlap(*sim), "") << "tick " << t;
  }
  const double x = PoseOf(*sim, "r").position.x();
  EXPECT_LE(x + 0.085, 1.9);
  EXPECT_GT(x + 0.085, 1.9 - 0.03);  // stopped less than one tick's travel short
  EXPECT_NEAR(PoseOf(*sim, "r").position.y(), 0.3, 1e-9);
  EXPECT_TRUE(sim->space().in_contact(Slot(*sim, "r")));
  EXPECT_EQ(sim->space().twist(Slot(*sim, "r")).linear.norm(), 0.0);
  // Blocked, it still turns: stop the wheels (within the acceleration
  // limit), then spin on the spot against the wall.
  Driver(*sim, "r").left = Driver(*sim, "r").right = 0;
  for (int t = 0; t < 2; ++t) sim->Step();
  EXPECT_NEAR(Yaw(*sim, "r"), 0.0, 1e-12);
  Driver(*sim, "r").left = -0.07;
  Driver(*sim, "r").right = 0.07;
  for (int t = 0; t < 6; ++t) sim->Step();  // the first still applies the stop
  EXPECT_NEAR(Yaw(*sim, "r"), 0.5, 1e-9);
  EXPECT_NEAR(PoseOf(*sim, "r").position.x(), x, 1e-12);
  // Turning while pushing forwards: it turns, slides off along the wall and
  // never overlaps it.
  Driver(*sim, "r").left = 0.05;
  Driver(*sim, "r").right = 0.1;
  for (int t = 0; t < 80; ++t) {
    sim->Step();
    ASSERT_EQ(Overlap(*sim), "") << "tick " << t;
  }
  EXPECT_GT(PoseOf(*sim, "r").position.y(), 0.35);
}

TEST(Kinematics2d, RobotStopsAtTheArenaEdgeWithoutWalls) {
  auto sim = LoadXml(Experiment(Robot("r", "0,1.5,0", 90), kDriver));
  Driver(*sim, "r").left = Driver(*sim, "r").right = 0.3;
  for (int t = 0; t < 40; ++t) {
    sim->Step();
    ASSERT_EQ(Overlap(*sim), "") << "tick " << t;
  }
  EXPECT_LE(PoseOf(*sim, "r").position.y() + 0.085, 2.0);
  EXPECT_GT(PoseOf(*sim, "r").position.y() + 0.085, 2.0 - 0.03);
  EXPECT_TRUE(sim->space().in_contact(Slot(*sim, "r")));
}

TEST(Kinematics2d, RobotsDrivingHeadOnNeverOverlap) {
  auto sim = LoadXml(Experiment(Robot("a", "-0.5,0,0", 0) + Robot("b", "0.5,0,0", 180), kDriver));
  for (const char* id : {"a", "b"}) Driver(*sim, id).left = Driver(*sim, id).right = 0.3;
  for (int t = 0; t < 40; ++t) {
    sim->Step();
    ASSERT_EQ(Overlap(*sim), "") << "tick " << t;
    const double gap = (PoseOf(*sim, "a").position - PoseOf(*sim, "b").position).norm();
    ASSERT_GE(gap, 0.17 - 1e-12) << "tick " << t;
  }
  const double gap = (PoseOf(*sim, "a").position - PoseOf(*sim, "b").position).norm();
  EXPECT_LT(gap, 0.17 + 2 * 0.03 + 1e-9);  // they got within one tick's travel of each other
  EXPECT_TRUE(sim->space().in_contact(Slot(*sim, "a")));
  EXPECT_TRUE(sim->space().in_contact(Slot(*sim, "b")));
  // Symmetric: neither got further than the other.
  EXPECT_NEAR(PoseOf(*sim, "a").position.x(), -PoseOf(*sim, "b").position.x(), 1e-12);
}

TEST(Kinematics2d, ARobotDrivingIntoAStandingOneStopsAndTheOtherStays) {
  auto sim = LoadXml(
      Experiment(Robot("mover", "-0.5,0,0") + Robot("standing", "0,0,0", 0, "still"), kDriver));
  for (int t = 0; t < 60; ++t) {
    sim->Step();
    ASSERT_EQ(Overlap(*sim), "") << "tick " << t;
  }
  EXPECT_EQ(PoseOf(*sim, "standing").position, Vec3(0, 0, 0));
  EXPECT_LT(PoseOf(*sim, "mover").position.x(), -0.17 + 1e-12);
  EXPECT_GT(PoseOf(*sim, "mover").position.x(), -0.17 - 0.01 - 1e-12);
}

TEST(Kinematics2d, MovableBoxIsNotPushed) {
  // kinematics2d treats every object as a fixed obstacle, movable or not:
  // use dynamics2d to push things.
  auto sim = LoadXml(Experiment(Robot("r", "-0.5,0,0") +
                                    "<box id=\"b\" size=\"0.2,0.2,0.2\" movable=\"true\" "
                                    "mass=\"0.5\"><body position=\"0,0,0\"/></box>"
                                    "<cylinder id=\"c\" radius=\"0.1\" height=\"0.2\" "
                                    "movable=\"true\"><body position=\"0,1,0\"/></cylinder>" +
                                    Robot("r2", "-0.5,1,0"),
                                kDriver));
  for (int t = 0; t < 60; ++t) {
    sim->Step();
    ASSERT_EQ(Overlap(*sim), "") << "tick " << t;
  }
  EXPECT_EQ(PoseOf(*sim, "b").position, Vec3(0, 0, 0));
  EXPECT_EQ(PoseOf(*sim, "c").position, Vec3(0, 1, 0));
  EXPECT_LE(PoseOf(*sim, "r").position.x(), -0.1 - 0.085 + 1e-12);
  EXPECT_LE(PoseOf(*sim, "r2").position.x(), -0.1 - 0.085 + 1e-12);
  EXPECT_TRUE(sim->space().in_contact(Slot(*sim, "r")));
  EXPECT_TRUE(sim->space().in_contact(Slot(*sim, "r2")));
}

TEST(Kinematics2d, RotatedBoxesBlockAlongTheirTrueOutline) {
  // A 1 m x 0.1 m box turned 45 degrees; a robot driving north at x = 0.3
  // meets the diagonal at y = 0.3 (minus the half-width along the diagonal).
  auto sim = LoadXml(Experiment(Robot("r", "0.3,-0.8,0", 90) +
                                    "<box id=\"b\" size=\"1,0.1,0.3\"><body "
                                    "position=\"0,0,0\" orientation=\"45,0,0\"/></box>",
                                kDriver));
  for (int t = 0; t < 150; ++t) {
    sim->Step();
    ASSERT_EQ(Overlap(*sim), "") << "tick " << t;
  }
  const double y = PoseOf(*sim, "r").position.y();
  // Closest approach of a circle of radius 0.085 to the line y = x, with the
  // slab half-width 0.05: distance from (0.3, y) to the line = (y - 0.3) / sqrt 2.
  EXPECT_LE(0.3 - y, (0.085 + 0.05) * std::sqrt(2.0) + 0.01 + 1e-9);
  EXPECT_GE(0.3 - y, (0.085 + 0.05) * std::sqrt(2.0) - 1e-9);
}

TEST(Kinematics2d, LowObjectsStillBlockButLightsDoNot) {
  // A 3 cm high box is below the proximity ring but not below the body.
  auto sim = LoadXml(
      Experiment(Robot("r", "-0.5,0,0") +
                     "<box id=\"low\" size=\"0.1,0.6,0.03\"><body position=\"0,0,0\"/></box>" +
                     Robot("l", "-0.5,1,0") + "<light id=\"light\" position=\"0,1,0.05\"/>",
                 kDriver));
  for (int t = 0; t < 30; ++t) sim->Step();
  EXPECT_LE(PoseOf(*sim, "r").position.x(), -0.05 - 0.085 + 1e-12);
  EXPECT_NEAR(PoseOf(*sim, "l").position.x(), -0.5 + 0.3,
              1e-9);  // drove straight through the light
}

TEST(Kinematics2d, RobotsAboveAnObstacleAreNotBlockedByIt) {
  // Footprints overlap only if heights do: a robot placed on a 20 cm shelf
  // level passes over a 10 cm box.
  auto sim =
      LoadXml(Experiment(Robot("r", "-0.5,0,0.1") +
                             "<box id=\"b\" size=\"0.2,0.6,0.1\"><body position=\"0,0,0\"/></box>",
                         kDriver));
  for (int t = 0; t < 30; ++t) sim->Step();
  EXPECT_NEAR(PoseOf(*sim, "r").position.x(), -0.5 + 0.3, 1e-9);
}

TEST(Kinematics2d, RobotOutsideTheArenaCannotBePlaced) {
  const std::string outside = LoadError(Experiment(Robot("r", "2.5,0,0"), kDriver));
  EXPECT_NE(outside.find("entity 'r' is outside the arena"), std::string::npos) << outside;
  // Partly outside counts: the body reaches 8.5 cm around its centre.
  const std::string partly = LoadError(Experiment(Robot("r", "1.95,0,0"), kDriver));
  EXPECT_NE(partly.find("outside the arena"), std::string::npos) << partly;
  EXPECT_EQ(LoadError(Experiment(Robot("r", "1.9,0,0"), kDriver)), "");
}

TEST(Kinematics2d, RobotsCannotBePlacedOnEachOtherOrInWalls) {
  const std::string robots =
      LoadError(Experiment(Robot("a", "0,0,0") + Robot("b", "0.1,0,0"), kDriver));
  EXPECT_NE(robots.find("overlaps 'a'"), std::string::npos) << robots;
  const std::string wall = LoadError(
      Experiment("<walls thickness=\"0.1\" height=\"0.5\"/>" + Robot("a", "1.85,0,0"), kDriver));
  EXPECT_NE(wall.find("overlaps 'wall_east'"), std::string::npos) << wall;
}

TEST(Kinematics2d, RemovedRobotNoLongerBlocks) {
  auto sim = LoadXml(
      Experiment(Robot("mover", "-0.5,0,0") + Robot("standing", "0,0,0", 0, "still"), kDriver));
  for (int t = 0; t < 40; ++t) sim->Step();
  const double stopped = PoseOf(*sim, "mover").position.x();
  EXPECT_LT(stopped, -0.17 + 1e-12);
  // Removed between two ticks (as a tool or test would), the robot must not
  // block anyone from the very next tick on. Exposes Simulation::RemoveEntity
  // leaving the spatial index stale until after the next physics step: the
  // engine still finds the removed robot and blocks the mover for one tick.
  sim->RemoveEntity(sim->space().Find("standing"));
  sim->Step();
  EXPECT_NEAR(PoseOf(*sim, "mover").position.x(), stopped + 0.01, 1e-9)
      << "blocked by a removed robot";
  EXPECT_FALSE(sim->space().in_contact(Slot(*sim, "mover")));
  for (int t = 0; t < 9; ++t) sim->Step();
  EXPECT_NEAR(PoseOf(*sim, "mover").position.x(), stopped + 0.1, 1e-9);
}

TEST(Kinematics2d, RobotRemovedByLoopFunctionsTimingNoLongerBlocks) {
  // The same, with the index refreshed as the step loop does after loop
  // functions remove entities: the mover drives on at once.
  auto sim = LoadXml(
      Experiment(Robot("mover", "-0.5,0,0") + Robot("standing", "0,0,0", 0, "still"), kDriver));
  for (int t = 0; t < 40; ++t) sim->Step();
  const double stopped = PoseOf(*sim, "mover").position.x();
  sim->RemoveEntity(sim->space().Find("standing"));
  sim->space().UpdateIndex();
  for (int t = 0; t < 10; ++t) sim->Step();
  EXPECT_NEAR(PoseOf(*sim, "mover").position.x(), stopped + 0.1, 1e-9);
}

std::string DenseScene(int quantity, const std::string& arena_size, const std::string& layout) {
  const std::string controllers =
      "<k2d_wander "
      "id=\"w\"><sensors><proximity/></sensors><actuators><differential_steering/></actuators></"
      "k2d_wander>";
  const std::string arena =
      "<walls thickness=\"0.1\" height=\"0.5\"/>"
      "<distribute><position method=\"grid\" center=\"0,0,0\" distances=\"0.19,0.19,0\" layout=\"" +
      layout +
      "\"/>"
      "<orientation method=\"uniform\" min=\"0,0,0\" max=\"360,0,0\"/>"
      "<entity quantity=\"" +
      std::to_string(quantity) +
      "\"><marxbot id=\"m\"><controller config=\"w\"/></marxbot></entity>"
      "</distribute>";
  return Experiment(arena, controllers, arena_size);
}

// Hash of every tick of a run.
std::vector<uint64_t> Hashes(const std::string& xml, int threads, int ticks, std::string* overlap) {
  auto sim = LoadXml(xml, {}, threads);
  std::vector<uint64_t> hashes;
  for (int t = 0; t < ticks; ++t) {
    sim->Step();
    hashes.push_back(sim->StateHash());
    if (overlap && overlap->empty()) {
      *overlap = Overlap(*sim);
      if (!overlap->empty()) *overlap += " at tick " + std::to_string(t);
    }
  }
  return hashes;
}

TEST(Kinematics2d, DenseSceneOfFiftyRobotsIsIdenticalWhateverTheThreadCount) {
  // 50 robots 19 cm apart (2 cm between bodies) in a 1.8 m square pen.
  const std::string xml = DenseScene(50, "1.8,1.8,1", "8,7,1");
  std::string overlap;
  const auto reference = Hashes(xml, 0, 150, &overlap);
  EXPECT_EQ(overlap, "");
  for (int threads : {1, 2, 4}) {
    EXPECT_EQ(Hashes(xml, threads, 150, nullptr), reference) << threads << " threads";
  }
}

TEST(Kinematics2d, DenseSceneOfSixHundredRobotsIsIdenticalWhateverTheThreadCount) {
  // Enough robots for the engine and the sensors to split work into chunks.
  const std::string xml = DenseScene(600, "5.2,5.2,1", "25,24,1");
  std::string overlap;
  const auto reference = Hashes(xml, 0, 60, &overlap);
  EXPECT_EQ(overlap, "");
  for (int threads : {1, 2, 4}) {
    EXPECT_EQ(Hashes(xml, threads, 60, nullptr), reference) << threads << " threads";
  }
}

TEST(Kinematics2d, DenseSceneActuallyMoves) {
  // Guards the determinism tests against a scene where nothing happens.
  auto sim = LoadXml(DenseScene(50, "1.8,1.8,1", "8,7,1"));
  std::vector<Vec3> start;
  for (uint32_t i = 0; i < sim->space().slots(); ++i)
    start.push_back(sim->space().pose(i).position);
  int blocked_ticks = 0;
  for (int t = 0; t < 100; ++t) {
    sim->Step();
    for (uint32_t i = 0; i < sim->space().slots(); ++i) blocked_ticks += sim->space().in_contact(i);
  }
  int moved = 0;
  for (uint32_t i = 0; i < sim->space().slots(); ++i)
    moved += (sim->space().pose(i).position - start[i]).norm() > 0.05;
  EXPECT_GT(moved, 25);
  EXPECT_GT(blocked_ticks, 50);  // collisions were resolved, not avoided
}

}  // namespace
}  // namespace colony
