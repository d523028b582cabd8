// Scenarios a user would notice: a marXbot running the diffusion controller
// turns away from a wall before touching it; in a dense swarm no robot ever
// overlaps a wall or another robot.
#include <algorithm>
#include <array>
#include <cmath>

#include "core/geometry2d.h"
#include "tests/test_util.h"

namespace colony {
namespace {

using testing::Experiment;
using testing::LoadXml;

const char* kDiffusion =
    "<diffusion id=\"dc\" library=\"diffusion\"><actuators><differential_steering/></actuators>"
    "<sensors><proximity/></sensors><params alpha=\"7.5\" delta=\"0.1\" "
    "velocity=\"VELOCITY\"/></diffusion>";

std::string DiffusionController(const std::string& velocity) {
  std::string c = kDiffusion;
  c.replace(c.find("VELOCITY"), 8, velocity);
  return c;
}

TEST(Scenario, DiffusionRobotTurnsAwayFromWallBeforeTouching) {
  // Heading straight at the east wall (inner face at x = 1.9), 0.8 m away.
  auto sim =
      LoadXml(Experiment("<walls thickness=\"0.1\" height=\"0.5\"/>"
                         "<marxbot id=\"mb\"><body position=\"1.0,0,0\" "
                         "orientation=\"0,0,0\"/><controller config=\"dc\"/></marxbot>",
                         DiffusionController("0.05")));
  const EntityHandle robot = sim->space().Find("mb");
  const double wall_face = 1.9;
  double closest_gap = 1e9;
  double x_at_closest = 0;
  for (int t = 0; t < 600; ++t) {
    sim->Step();
    const Vec3 p = sim->space().pose(robot.index).position;
    const double gap = wall_face - (p.x() + 0.085);
    ASSERT_FALSE(sim->space().in_contact(robot.index)) << "touched at tick " << sim->tick();
    ASSERT_GT(gap, 0.0) << "overlapped the wall at tick " << sim->tick();
    if (gap < closest_gap) {
      closest_gap = gap;
      x_at_closest = p.x();
    }
  }
  // It got close (the sensors see 10 cm), turned until the wall was no
  // longer ahead, and drove on without ever touching it.
  EXPECT_LT(closest_gap, 0.1);
  const Space& space = sim->space();
  const double heading = YawOf(space.pose(robot.index).orientation);
  EXPECT_LT(std::cos(heading), 0.1) << "still facing the wall, heading " << heading;
  const Vec3 end = space.pose(robot.index).position;
  EXPECT_GT((end - Vec3(x_at_closest, 0, 0)).norm(), 0.3) << "it should have driven on";
}

TEST(Scenario, DenseSwarmNeverOverlaps) {
  // 150 robots on 7.8 m^2 (0.05 m^2 each; a robot's own footprint is
  // 0.023) driving at top speed, so they collide constantly.
  auto sim = LoadXml(
      Experiment("<walls thickness=\"0.1\" height=\"0.5\"/>"
                 "<box id=\"b\" size=\"0.5,0.5,0.3\"><body position=\"0,0,0\" "
                 "orientation=\"45,0,0\"/></box>"
                 "<distribute><position method=\"uniform\" min=\"-1.4,-1.4,0\" max=\"1.4,1.4,0\"/>"
                 "<orientation method=\"uniform\" min=\"0,0,0\" max=\"360,0,0\"/>"
                 "<entity quantity=\"150\" max_trials=\"1000\"><marxbot id=\"mb\"><controller "
                 "config=\"dc\"/></marxbot></entity>"
                 "</distribute>",
                 DiffusionController("0.3"), "3.2,3.2,1"),
      {}, 2);
  Space& space = sim->space();
  std::vector<uint32_t> robots, obstacles;
  for (uint32_t i = 0; i < space.slots(); ++i) {
    (space.flags(i) & kRobot ? robots : obstacles).push_back(i);
  }
  ASSERT_EQ(robots.size(), 150u);
  size_t contacts = 0;
  double moved = 0;
  for (int t = 0; t < 200; ++t) {
    std::vector<Vec2> before;
    for (uint32_t r : robots) before.push_back(space.pose(r).position.head<2>());
    sim->Step();
    for (size_t a = 0; a < robots.size(); ++a) {
      const Vec2 pa = space.pose(robots[a]).position.head<2>();
      moved += (pa - before[a]).norm();
      contacts += space.in_contact(robots[a]);
      for (size_t b = a + 1; b < robots.size(); ++b) {
        const Vec2 pb = space.pose(robots[b]).position.head<2>();
        ASSERT_GE((pa - pb).norm(), 2 * 0.085 - 1e-9)
            << space.id(robots[a]) << " overlaps " << space.id(robots[b]) << " at tick "
            << sim->tick();
      }
      for (uint32_t o : obstacles) {
        ASSERT_FALSE(CircleOverlapsFootprint(pa, 0.085 - 1e-9, space.pose(o), space.geometry(o)))
            << space.id(robots[a]) << " overlaps " << space.id(o) << " at tick " << sim->tick();
      }
    }
  }
  // The scene really was dense and moving.
  EXPECT_GT(contacts, 500u);
  EXPECT_GT(moved / robots.size(), 0.5);
}

// 200 marXbots placed at random in a walled 3.6 m square, numbered `order`.
auto LoadDistributed(const std::string& order) {
  return LoadXml(Experiment(
      "<walls thickness=\"0.1\" height=\"0.5\"/>"
      "<distribute><position method=\"uniform\" min=\"-1.8,-1.8,0\" max=\"1.8,1.8,0\"/>"
      "<orientation method=\"uniform\" min=\"0,0,0\" max=\"360,0,0\"/>"
      "<entity quantity=\"200\" max_trials=\"1000\" order=\"" +
          order +
          "\"><marxbot id=\"mb\"><controller config=\"dc\"/></marxbot></entity></distribute>",
      DiffusionController("0.05")));
}

// order="place" changes which robot stands where, not where robots stand:
// the same places as drawn, numbered along the floor, so that a robot's
// neighbours in memory are its neighbours on the floor.
TEST(Scenario, DistributeNumberedByPlaceKeepsThePlacesAndNumbersThemAlongTheFloor) {
  auto drawn = LoadDistributed("drawn"), by_place = LoadDistributed("place");
  auto places = [](const Simulation& sim) {
    std::vector<std::array<double, 4>> out;  // x, y, yaw, id number
    for (int i = 0; i < 200; ++i) {
      const EntityHandle h = sim.space().Find("mb" + std::to_string(i));
      EXPECT_TRUE(h.valid()) << "mb" << i;
      if (!h.valid()) continue;
      const Pose& p = sim.space().pose(h.index);
      out.push_back({p.position.x(), p.position.y(), YawOf(p.orientation), double(i)});
    }
    return out;
  };
  auto a = places(*drawn), b = places(*by_place);
  ASSERT_EQ(a.size(), 200u);
  ASSERT_EQ(b.size(), 200u);
  // Mean distance from robot i to robot i + 1.
  auto step = [](const std::vector<std::array<double, 4>>& v) {
    double sum = 0;
    for (size_t i = 1; i < v.size(); ++i)
      sum += std::hypot(v[i][0] - v[i - 1][0], v[i][1] - v[i - 1][1]);
    return sum / static_cast<double>(v.size() - 1);
  };
  // Drawn at random, consecutive robots are about half the arena apart; by
  // place, a few robot widths.
  EXPECT_GT(step(a), 1.2);
  EXPECT_LT(step(b), 0.5);
  // The same poses, whoever stands on them.
  auto by_place_of = [](std::vector<std::array<double, 4>> v) {
    for (auto& e : v) e[3] = 0;
    std::sort(v.begin(), v.end());
    return v;
  };
  EXPECT_EQ(by_place_of(a), by_place_of(b));
}

// Numbered by place, robots are stored in the order the space's grid lists
// them (row of cells by row of cells), the order kinematics2d's collision
// test walks: its per-robot arrays are then read and written in sequence.
TEST(Scenario, DistributeNumberedByPlaceIsStoredInTheOrderOfTheSpacesGrid) {
  auto in_grid_order = [](Simulation& sim) {
    sim.space().UpdateIndex();
    const std::vector<uint32_t>& by_cell = sim.space().movable_by_cell();
    EXPECT_EQ(by_cell.size(), 200u);
    return std::is_sorted(by_cell.begin(), by_cell.end());
  };
  EXPECT_TRUE(in_grid_order(*LoadDistributed("place")));
  EXPECT_FALSE(in_grid_order(*LoadDistributed("drawn")));
}

}  // namespace
}  // namespace colony
