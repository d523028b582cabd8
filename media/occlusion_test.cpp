// Occlusion tests: a segment is blocked exactly when it passes through a
// solid body at a height the body spans; the grid's gather finds every body
// a segment may cross, each once, whatever the cell size.
#include "media/occlusion.h"

#include <algorithm>
#include <random>
#include <set>
#include <string>

#include "media/test_util.h"

namespace colony {
namespace {

using testing::Experiment;
using testing::LoadXml;

std::string Box(const std::string& id, const std::string& size, const std::string& position,
                double yaw = 0) {
  return "<box id=\"" + id + "\" size=\"" + size + "\"><body position=\"" + position +
         "\" orientation=\"" + std::to_string(yaw) + ",0,0\"/></box>";
}

// Everything near (x, y) from `grid`, as an Occluders list.
Occluders Near(const OccluderGrid& grid, double x, double y, double reach,
               uint32_t self = 0xFFFFFFFFu) {
  Occluders out;
  grid.Gather(x, y, reach, self, out);
  return out;
}

TEST(Occlusion, SegmentsThroughABodyAtItsHeightAreBlocked) {
  // A box 1 m wide (y), 0.1 m deep (x), 0.3 m high at x = 1; a cylinder of
  // radius 0.1, from z = 0 to 0.2, at (-1, 0).
  auto sim = LoadXml(Experiment(
      Box("b", "0.1,1,0.3", "1,0,0") +
      "<cylinder id=\"c\" radius=\"0.1\" height=\"0.2\"><body position=\"-1,0,0\"/></cylinder>"));
  OccluderGrid grid;
  grid.Build(sim->space(), 1.0);
  const Occluders all = Near(grid, 0, 0, 5);
  ASSERT_EQ(all.size(), 2u);
  // Straight through the box, low and high.
  EXPECT_TRUE(all.Blocked(Vec3(0, 0, 0.1), Vec3(2, 0, 0.1), 0xFFFFFFFFu));
  EXPECT_FALSE(all.Blocked(Vec3(0, 0, 0.35), Vec3(2, 0, 0.35), 0xFFFFFFFFu));  // over it
  // Descending over it: enters above the top (0.3) and leaves below it.
  EXPECT_TRUE(all.Blocked(Vec3(0, 0, 0.4), Vec3(2, 0, 0.0), 0xFFFFFFFFu));
  // Around its end (it spans y in [-0.5, 0.5]).
  EXPECT_FALSE(all.Blocked(Vec3(0, 0.6, 0.1), Vec3(2, 0.6, 0.1), 0xFFFFFFFFu));
  // Stopping short of it.
  EXPECT_FALSE(all.Blocked(Vec3(0, 0, 0.1), Vec3(0.94, 0, 0.1), 0xFFFFFFFFu));
  // The cylinder: through, beside, over.
  EXPECT_TRUE(all.Blocked(Vec3(0, 0.05, 0.1), Vec3(-2, 0.05, 0.1), 0xFFFFFFFFu));
  EXPECT_FALSE(all.Blocked(Vec3(0, 0.11, 0.1), Vec3(-2, 0.11, 0.1), 0xFFFFFFFFu));
  EXPECT_FALSE(all.Blocked(Vec3(0, 0, 0.25), Vec3(-2, 0, 0.25), 0xFFFFFFFFu));
  // A body that is ignored (the sender, the LED's owner) does not block.
  const uint32_t box = sim->space().Find("b").index;
  EXPECT_FALSE(all.Blocked(Vec3(0, 0, 0.1), Vec3(2, 0, 0.1), box));
  // Nor does the observer itself, left out of the gather.
  EXPECT_EQ(Near(grid, 0, 0, 5, box).size(), 1u);
}

TEST(Occlusion, RotatedBoxes) {
  // A thin wall turned 45 degrees through the origin, from (-0.35, -0.35) to (0.35, 0.35).
  auto sim = LoadXml(Experiment(Box("w", "1,0.02,0.5", "0,0,0", 45)));
  OccluderGrid grid;
  grid.Build(sim->space(), 1.0);
  const Occluders all = Near(grid, 0, 0, 5);
  EXPECT_TRUE(all.Blocked(Vec3(-1, 1, 0.1), Vec3(1, -1, 0.1), 0xFFFFFFFFu));  // across it
  EXPECT_FALSE(
      all.Blocked(Vec3(-1, 0.8, 0.1), Vec3(-0.1, 0.8, 0.1), 0xFFFFFFFFu));  // beside its end
  EXPECT_TRUE(all.Blocked(Vec3(0.5, 0, 0.1), Vec3(0, 0.5, 0.1), 0xFFFFFFFFu));
}

TEST(Occlusion, GridGathersEveryBodyOnceWhateverTheCellSize) {
  // 60 boxes (some long, turned) and 60 cylinders at random; random segments:
  // the answer from the bodies gathered around the segment's start must be
  // that of testing every body, and no body may be gathered twice.
  std::mt19937 gen(9);
  std::uniform_real_distribution<double> u(-4.5, 4.5), inner(-3.2, 3.2), turn(0, 180),
      size(0.05, 2.5);
  std::string arena;
  for (int i = 0; i < 60; ++i) {
    arena += Box("b" + std::to_string(i), std::to_string(size(gen)) + ",0.05,0.3",
                 std::to_string(inner(gen)) + "," + std::to_string(inner(gen)) + ",0", turn(gen));
    arena += "<cylinder id=\"c" + std::to_string(i) +
             "\" radius=\"0.1\" height=\"0.2\"><body position=\"" + std::to_string(u(gen)) + "," +
             std::to_string(u(gen)) + ",0\"/></cylinder>";
  }
  auto sim = LoadXml(Experiment(arena, "", "10,10,1"));
  OccluderGrid everything;
  everything.Build(sim->space(), 100.0);
  const Occluders all = Near(everything, 0, 0, 100);
  ASSERT_EQ(all.size(), 120u);
  for (double cell : {0.3, 1.0, 3.0}) {
    OccluderGrid grid;
    grid.Build(sim->space(), cell);
    int blocked = 0;
    for (int q = 0; q < 2000; ++q) {
      const Vec3 a(u(gen), u(gen), 0.1), b(u(gen), u(gen), 0.1);
      Occluders near;
      grid.Gather(a.x(), a.y(), (b - a).head<2>().norm(), 0xFFFFFFFFu, near);
      std::set<uint32_t> unique;
      for (size_t k = 0; k < near.size(); ++k) unique.insert(near.item(k).slot);
      EXPECT_EQ(unique.size(), near.size()) << "a body gathered twice, cell " << cell;
      const bool expected = all.Blocked(a, b, 0xFFFFFFFFu);
      EXPECT_EQ(near.Blocked(a, b, 0xFFFFFFFFu), expected) << "cell " << cell << " segment " << q;
      blocked += expected;
    }
    EXPECT_GT(blocked, 200);  // the scene does block segments
    EXPECT_LT(blocked, 1900);
  }
}

}  // namespace
}  // namespace colony
