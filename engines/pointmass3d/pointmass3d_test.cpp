// pointmass3d as a user sees it: flyers stop at walls and land on the floor
// and on objects, never interpenetrate one another even when a crowd goes
// for the same point, fly beside foot-bots simulated by kinematics2d, and a
// run is bit-identical whatever the number of threads.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "actuators/eyebot_propulsion/eyebot_propulsion.h"
#include "core/geometry2d.h"
#include "core/registry.h"
#include "entities/eyebot/eyebot.h"
#include "tests/test_util.h"

namespace colony {
namespace {

using testing::LoadError;
using testing::LoadXml;
using testing::Mentions;
using testing::PositionOf;
using testing::RunFor;

// Flies as its params say from the first tick: to (x, y, z) (position
// mode), or at (vx, vy, vz) (speed mode) if vx is given, or rotors off if
// off="true". With wander="true", to a new random point of the box
// [-w, w] x [-w, w] x [0.5, 2] every 2 s (w = params width).
class Pm3dPilot : public Controller {
 public:
  void Init(const Params& params) override {
    rotors_ = &GetActuator<EyebotPropulsionActuator>("eyebot_propulsion");
    wander_ = params.GetBool("wander", false);
    width_ = params.GetDouble("width", 1);
    if (params.GetBool("off", false)) {
      rotors_->Off();
    } else if (params.Has("vx")) {
      rotors_->SetVelocity(params.GetDouble("vx"), params.GetDouble("vy", 0),
                           params.GetDouble("vz", 0));
    } else if (!wander_) {
      rotors_->SetTargetPosition(params.GetDouble("x", 0), params.GetDouble("y", 0),
                                 params.GetDouble("z", 1));
    }
  }
  void ControlStep() override {
    if (!wander_ || ticks_++ % 20 != 0) return;
    rotors_->SetTargetPosition(rng().Uniform(-width_, width_), rng().Uniform(-width_, width_),
                               rng().Uniform(0.5, 2.0));
  }

 private:
  EyebotPropulsionActuator* rotors_ = nullptr;
  bool wander_ = false;
  double width_ = 1;
  int ticks_ = 0;
};
COLONY_REGISTER_CONTROLLER(Pm3dPilot, "pm3d_pilot", "test: flies to a point or at a velocity");

// Does nothing (a foot-bot standing by).
class Pm3dIdle : public Controller {
 public:
  void ControlStep() override {}
};
COLONY_REGISTER_CONTROLLER(Pm3dIdle, "pm3d_idle", "test: does nothing");
const std::string kIdle = "<pm3d_idle id=\"idle\"/>";
const std::string kMarxbot =
    "<marxbot id=\"m\"><body position=\"1,1,0\"/><controller config=\"idle\"/></marxbot>";

std::string Pilot(const std::string& id, const std::string& params) {
  return "<pm3d_pilot id=\"" + id + "\"><actuators><eyebot_propulsion/></actuators><params " +
         params + "/></pm3d_pilot>";
}

std::string Eyebot(const std::string& id, const std::string& position, const std::string& config) {
  return "<eyebot id=\"" + id + "\"><body position=\"" + position + "\"/><controller config=\"" +
         config + "\"/></eyebot>";
}

std::string Scene(const std::string& arena, const std::string& controllers,
                  const std::string& engines = "<pointmass3d id=\"pm3d\"/>",
                  const std::string& size = "6,6,3") {
  return "<colony><framework><experiment length=\"10\" ticks_per_second=\"10\" "
         "random_seed=\"5\"/></framework><controllers>" +
         controllers + "</controllers><arena size=\"" + size + "\" center=\"0,0,1.5\">" + arena +
         "</arena><physics_engines>" + engines + "</physics_engines></colony>";
}

const Twist& TwistOf(const Simulation& sim, const std::string& id) {
  return sim.space().twist(sim.space().Find(id).index);
}

// The deepest overlap (m) between two eye-bots of `sim` (upright cylinders),
// 0 if none.
// The most flyers may sink into each other (the engine's kHeldBackDepth): a
// shallower overlap is pushed apart over the next ticks.
constexpr double kMostOverlap = 0.02 + 1e-9;
double DeepestOverlap(const Simulation& sim) {
  const Space& space = sim.space();
  std::vector<uint32_t> bots;
  for (uint32_t s = 0; s < space.slots(); ++s) {
    if (space.alive(s) && space.Get<QuadrotorState>(s)) bots.push_back(s);
  }
  double deepest = 0;
  for (size_t a = 0; a < bots.size(); ++a) {
    for (size_t b = a + 1; b < bots.size(); ++b) {
      const Vec3& p = space.pose(bots[a]).position;
      const Vec3& q = space.pose(bots[b]).position;
      const double vertical = std::min(p.z(), q.z()) + eyebot::kHeight - std::max(p.z(), q.z());
      const double side = 2 * eyebot::kRadius - (p - q).head<2>().norm();
      deepest = std::max(deepest, std::min(vertical, side));
    }
  }
  return deepest;
}

TEST(Pointmass3d, AWallStopsAFlyerWithoutOverlap) {
  auto sim = LoadXml(Scene(Eyebot("e", "-1,0,0", "fly") +
                               "<box id=\"wall\" size=\"0.1,4,3\"><body position=\"1,0,0\"/></box>",
                           Pilot("fly", "x=\"2.5\" y=\"0\" z=\"1\"")));
  const uint32_t e = sim->space().Find("e").index;
  const uint32_t wall = sim->space().Find("wall").index;
  bool touched = false;
  for (int t = 0; t < 60; ++t) {
    sim->Step();
    const Pose& pose = sim->space().pose(e);
    EXPECT_FALSE(CircleOverlapsFootprint(pose.position.head<2>(), eyebot::kRadius - 1e-9,
                                         sim->space().pose(wall), sim->space().geometry(wall)))
        << "at tick " << t << ": " << pose.position.transpose();
    touched = touched || sim->space().in_contact(e);
  }
  EXPECT_TRUE(touched);
  EXPECT_NEAR(PositionOf(*sim, "e").x(), 1 - 0.05 - eyebot::kRadius, 1e-6) << "against the wall";
  EXPECT_NEAR(PositionOf(*sim, "e").z(), 1.0, 0.02);
  EXPECT_NEAR(TwistOf(*sim, "e").linear.x(), 0.0, 1e-9) << "no speed into the wall";
}

TEST(Pointmass3d, ARobotTooLightlyLiftedToLeaveTheFloorStaysWhereItIs) {
  // Told to fly to a point below the floor, 2 m away: its rotors never lift
  // it, and friction holds it where it stands (no creeping along the floor).
  auto sim =
      LoadXml(Scene(Eyebot("e", "0,0,0", "low"), Pilot("low", "x=\"2\" y=\"0\" z=\"-0.5\"")));
  RunFor(*sim, 3);
  EXPECT_EQ(PositionOf(*sim, "e"), Vec3(0, 0, 0));
}

TEST(Pointmass3d, AFlyerOverALowWallPassesAndOneBelowItsTopDoesNot) {
  const std::string wall = "<box id=\"wall\" size=\"0.1,4,1\"><body position=\"0,0,0\"/></box>";
  auto sim = LoadXml(Scene(
      Eyebot("high", "-1,1,0", "high") + Eyebot("low", "-1,-1,0", "low") + wall,
      Pilot("high", "x=\"1\" y=\"1\" z=\"1.2\"") + Pilot("low", "x=\"1\" y=\"-1\" z=\"0.5\"")));
  RunFor(*sim, 6);
  EXPECT_LT((PositionOf(*sim, "high") - Vec3(1, 1, 1.2)).norm(), 0.02);
  EXPECT_LT(PositionOf(*sim, "low").x(), -0.05 - eyebot::kRadius + 1e-6);
}

TEST(Pointmass3d, WithTheRotorsOffItFallsAndLandsOnAnObjectOrTheFloor) {
  auto sim = LoadXml(Scene(Eyebot("on_box", "0,0,1.5", "off") + Eyebot("on_floor", "2,0,2", "off") +
                               "<cylinder id=\"post\" radius=\"0.3\" height=\"0.8\">"
                               "<body position=\"0,0,0\"/></cylinder>",
                           Pilot("off", "off=\"true\"")));
  RunFor(*sim, 0.3);
  EXPECT_LT(TwistOf(*sim, "on_floor").linear.z(), -2.5) << "falling";
  RunFor(*sim, 1.7);
  EXPECT_EQ(PositionOf(*sim, "on_box").z(), 0.8);
  EXPECT_EQ(PositionOf(*sim, "on_floor").z(), 0.0);
  EXPECT_EQ(TwistOf(*sim, "on_box").linear.norm(), 0.0);
  EXPECT_EQ(TwistOf(*sim, "on_floor").linear.norm(), 0.0);
}

TEST(Pointmass3d, TwoFlyersSentToTheSamePointNeverInterpenetrate) {
  auto sim = LoadXml(Scene(Eyebot("a", "-1,0,0", "meet") + Eyebot("b", "1,0.05,0", "meet"),
                           Pilot("meet", "x=\"0\" y=\"0\" z=\"1\"")));
  for (int t = 0; t < 60; ++t) {
    sim->Step();
    ASSERT_LE(DeepestOverlap(*sim), kMostOverlap) << "at tick " << t;
  }
  const Vec3 a = PositionOf(*sim, "a"), b = PositionOf(*sim, "b");
  EXPECT_NEAR((a - b).head<2>().norm(), 2 * eyebot::kRadius, 0.01) << "side by side, touching";
  EXPECT_NEAR(a.z(), 1.0, 0.05);
  EXPECT_NEAR(b.z(), 1.0, 0.05);
}

TEST(Pointmass3d, AFlyerLandingOnAnotherStaysOnTop) {
  auto sim = LoadXml(Scene(Eyebot("below", "0,0,0", "off") + Eyebot("above", "0.1,0,1.5", "off"),
                           Pilot("off", "off=\"true\"")));
  for (int t = 0; t < 30; ++t) {
    sim->Step();
    ASSERT_LE(DeepestOverlap(*sim), kMostOverlap) << "at tick " << t;
  }
  EXPECT_EQ(PositionOf(*sim, "below").z(), 0.0);
  EXPECT_NEAR(PositionOf(*sim, "above").z(), eyebot::kHeight, 1e-9);
}

TEST(Pointmass3d, ACrowdGoingForOnePointNeverInterpenetrates) {
  // Two rings around the point, 28 and 20 eye-bots.
  std::string bots;
  const int count = 48;
  for (int i = 0; i < count; ++i) {
    const bool outer = i < 28;
    const double a = 2 * M_PI * (outer ? i / 28.0 : (i - 28) / 20.0);
    const double r = outer ? 2.6 : 1.8;
    bots += Eyebot("e" + std::to_string(i),
                   std::to_string(r * std::cos(a)) + "," + std::to_string(r * std::sin(a)) + ",0",
                   "meet");
  }
  auto sim = LoadXml(Scene(bots, Pilot("meet", "x=\"0\" y=\"0\" z=\"1.5\"")), {}, 2);
  for (int t = 0; t < 80; ++t) {
    sim->Step();
    ASSERT_LE(DeepestOverlap(*sim), kMostOverlap) << "at tick " << t;
  }
  // Jammed in two rings around the point, each pressed against its
  // neighbours (at most 2 cm into each, so a ring of n is at most n x 2 cm
  // shorter), at the height of the point.
  for (int i = 0; i < count; ++i) {
    const Vec3 p = PositionOf(*sim, "e" + std::to_string(i));
    const double ring =
        i < 28 ? 28 * 2 * eyebot::kRadius / (2 * M_PI) : 20 * 2 * eyebot::kRadius / (2 * M_PI);
    EXPECT_LE(p.head<2>().norm(), ring + 0.01) << "e" << i;
    EXPECT_GE(p.head<2>().norm(), ring - (i < 28 ? 28 : 20) * 0.02 / (2 * M_PI) - 0.01) << "e" << i;
    EXPECT_NEAR(p.z(), 1.5, 0.02) << "e" << i;
  }
}

TEST(Pointmass3d, FlyersAddedOrRemovedWhileRunningFlyOrNoLongerBlock) {
  auto sim = LoadXml(Scene(
      Eyebot("a", "0,0,0", "meet") + Eyebot("b", "1.5,0,0", "meet"),
      Pilot("meet", "x=\"0\" y=\"0\" z=\"1\"") + Pilot("corner", "x=\"-2\" y=\"-2\" z=\"2\"")));
  RunFor(*sim, 4);
  EXPECT_NEAR((PositionOf(*sim, "b") - PositionOf(*sim, "a")).norm(), 2 * eyebot::kRadius, 0.01)
      << "sharing the point, side by side";
  sim->RemoveEntity(sim->space().Find("a"));
  sim->AddEntity(Eyebot("c", "2,2,0", "corner"));
  RunFor(*sim, 5);
  EXPECT_LT((PositionOf(*sim, "b") - Vec3(0, 0, 1)).norm(), 0.02);
  EXPECT_LT((PositionOf(*sim, "c") - Vec3(-2, -2, 2)).norm(), 0.02);
}

// `count` eye-bots placed at random on the floor of an arena of half width
// `half` (m) around a 1 m box, each flying to a new random point of the
// middle, `width` wide, every 2 s.
std::string WanderingSwarm(int count, double half, double width) {
  const std::string lo = std::to_string(-half + 0.3), hi = std::to_string(half - 0.3);
  return Scene(
      "<box id=\"block\" size=\"1,1,1\"><body position=\"0,0,0\"/></box>"
      "<distribute><position method=\"uniform\" min=\"" +
          lo + "," + lo + ",0\" max=\"" + hi + "," + hi +
          ",0\"/><orientation method=\"uniform\" min=\"0,0,0\" max=\"360,0,0\"/>"
          "<entity quantity=\"" +
          std::to_string(count) +
          "\" max_trials=\"1000\"><eyebot id=\"e\"><controller config=\"wander\"/>"
          "</eyebot></entity></distribute>",
      Pilot("wander", "wander=\"true\" width=\"" + std::to_string(width) + "\""),
      "<pointmass3d id=\"pm3d\"/>",
      std::to_string(2 * half) + "," + std::to_string(2 * half) + ",3");
}

uint64_t FinalHash(const std::string& xml, int threads) {
  ExperimentOptions options;
  options.text = xml;
  options.threads = threads;
  auto sim = Simulation::Load(options);
  int contacts = 0;
  while (!sim->Done()) {
    sim->Step();
    for (uint32_t s = 0; s < sim->space().slots(); ++s) contacts += sim->space().in_contact(s);
  }
  EXPECT_GT(contacts, 100) << "crowded enough that they collide";
  EXPECT_LE(DeepestOverlap(*sim), kMostOverlap);
  return sim->StateHash();
}

void ExpectSameHashForAllThreadCounts(const std::string& xml) {
  const uint64_t reference = FinalHash(xml, 0);
  for (int threads : {1, 2, 4}) {
    EXPECT_EQ(FinalHash(xml, threads), reference) << "with " << threads << " threads";
  }
}

TEST(Pointmass3d, FiftyCrowdedFlyersGiveTheSameRunWhateverTheThreadCount) {
  ExpectSameHashForAllThreadCounts(WanderingSwarm(50, 3, 0.8));
}

// Several chunks of the engine's parallel phases.
TEST(Pointmass3d, SixHundredCrowdedFlyersGiveTheSameRunWhateverTheThreadCount) {
  ExpectSameHashForAllThreadCounts(WanderingSwarm(600, 10, 3));
}

TEST(Pointmass3d, EyebotsFlyInPointmass3dBesideFootbotsInKinematics2d) {
  auto sim = LoadXml(Scene(
      Eyebot("e", "-1,0,0", "fly") + kMarxbot, Pilot("fly", "x=\"1\" y=\"1\" z=\"1\"") + kIdle,
      "<kinematics2d id=\"k2d\"/><pointmass3d id=\"pm3d\" entities=\"eyebot\"/>"));
  EXPECT_EQ(sim->EngineOf(sim->space().Find("e"))->label(), "pointmass3d");
  EXPECT_EQ(sim->EngineOf(sim->space().Find("m"))->label(), "kinematics2d");
  RunFor(*sim, 5);
  EXPECT_LT((PositionOf(*sim, "e") - Vec3(1, 1, 1)).norm(), 0.02) << "above the foot-bot";
}

// Two pointmass3d engines, west and east of x = 0, each up to 3 m.
std::string Halves() {
  auto half = [](const std::string& id, double x0, double x1) {
    auto v = [](double x, double y) {
      return "<vertex point=\"" + std::to_string(x) + "," + std::to_string(y) + "\"/>";
    };
    return "<pointmass3d id=\"" + id +
           "\"><boundaries><top height=\"3\"/><bottom height=\"0\"/><sides size=\"4\">" +
           v(x0, -3) + v(x1, -3) + v(x1, 3) + v(x0, 3) + "</sides></boundaries></pointmass3d>";
  };
  return half("west", -3, 0) + half("east", 0, 3);
}

TEST(Pointmass3d, AFlyerCrossingIntoAnotherEnginesRegionFliesOnThere) {
  auto sim = LoadXml(
      Scene(Eyebot("e", "-2,0,0", "fly"), Pilot("fly", "x=\"2\" y=\"0\" z=\"1\""), Halves()));
  const EntityHandle e = sim->space().Find("e");
  EXPECT_EQ(sim->EngineOf(e)->id(), "west");
  double fastest = 0;
  for (int t = 0; t < 60; ++t) {
    sim->Step();
    fastest = std::max(fastest, TwistOf(*sim, "e").linear.head<2>().norm());
  }
  EXPECT_EQ(sim->EngineOf(e)->id(), "east");
  EXPECT_LT((PositionOf(*sim, "e") - Vec3(2, 0, 1)).norm(), 0.02);
  EXPECT_LE(fastest, eyebot::kMaxSpeed + 1e-9);
}

TEST(Pointmass3d, AnEngineThatCannotFlyEyebotsIsNamedWithTheOnesThatCan) {
  const std::string k2d =
      Scene(Eyebot("e", "0,0,0", "fly"), Pilot("fly", "z=\"1\""), "<kinematics2d id=\"k2d\"/>");
  EXPECT_TRUE(Mentions(LoadError(k2d), {"'eyebot'", "kinematics2d", "pointmass3d"}));
  // A marXbot in pointmass3d alone.
  EXPECT_TRUE(Mentions(LoadError(Scene(kMarxbot, kIdle)), {"'marxbot'", "pointmass3d"}));
  EXPECT_TRUE(Mentions(LoadError(Scene(Eyebot("e", "0,0,0", "fly"), Pilot("fly", "z=\"1\""),
                                       "<pointmass3d id=\"pm3d\" gravity=\"1\"/>")),
                       {"<pointmass3d", "gravity"}));
}

}  // namespace
}  // namespace colony
