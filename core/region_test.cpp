#include "core/region.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "core/random.h"

namespace colony {
namespace {

Region Polygon(std::vector<Vec2> vertices) {
  Region r;
  r.vertices = std::move(vertices);
  return r;
}

// Values of one coordinate to test a box [lo, hi) with: its ends, the
// numbers just below them, both zeros, the infinities and NaN.
std::vector<double> Probes(double lo, double hi) {
  const double inf = std::numeric_limits<double>::infinity();
  return {lo,
          hi,
          0.0,
          -0.0,
          inf,
          -inf,
          std::numeric_limits<double>::quiet_NaN(),
          std::nextafter(lo, -inf),
          std::nextafter(hi, -inf)};
}

// The engines test an axis-aligned rectangle with four comparisons
// (PhysicsEngine::Holds): it must say what the crossing-number rule says for
// every point, those on the sides and corners included, whichever corner the
// polygon starts at.
TEST(Region, ABoxContainsExactlyWhatTheCrossingRuleContains) {
  const std::vector<std::vector<Vec2>> rectangles = {
      {{-5, -5}, {0, -5}, {0, 0}, {-5, 0}},
      {{0, -5}, {5, -5}, {5, 0}, {0, 0}},
      {{-0.3, 0.1}, {7.25, 0.1}, {7.25, 2.5}, {-0.3, 2.5}},
  };
  RandomStream rng(7);
  for (const auto& corners : rectangles) {
    for (int start = 0; start < 4; ++start) {
      std::vector<Vec2> v;
      for (int i = 0; i < 4; ++i) v.push_back(corners[(start + i) % 4]);
      Region region = Polygon(v);
      region.bottom = 0;
      region.top = 1;
      Vec2 lo, hi;
      ASSERT_TRUE(region.AxisAlignedBox(lo, hi));
      std::vector<double> xs = Probes(lo.x(), hi.x());
      std::vector<double> ys = Probes(lo.y(), hi.y());
      for (int k = 0; k < 200; ++k) {
        xs.push_back(rng.Uniform(lo.x() - 1, hi.x() + 1));
        ys.push_back(rng.Uniform(lo.y() - 1, hi.y() + 1));
      }
      int inside = 0;
      for (double x : xs) {
        for (double y : ys) {
          for (double z : {0.0, 0.5, 1.0, -0.1}) {
            const Vec3 p(x, y, z);
            ASSERT_EQ(region.BoxContains(lo, hi, p), region.Contains(p))
                << "start " << start << " at " << x << ", " << y << ", " << z;
            inside += region.Contains(p);
          }
        }
      }
      EXPECT_GT(inside, 1000);  // the points are not all outside
    }
  }
}

TEST(Region, OnlyAxisAlignedRectanglesAreBoxes) {
  Vec2 lo, hi;
  EXPECT_FALSE(Polygon({{0, 0}, {1, 0}, {0, 1}}).AxisAlignedBox(lo, hi));
  EXPECT_FALSE(Polygon({{0, -1}, {1, 0}, {0, 1}, {-1, 0}}).AxisAlignedBox(lo, hi));  // a diamond
  EXPECT_FALSE(Polygon({{0, 0}, {2, 0}, {2, 1}, {1, 2}}).AxisAlignedBox(lo, hi));
  EXPECT_FALSE(Polygon({{0, 0}, {1, 1}, {1, 0}, {0, 1}}).AxisAlignedBox(lo, hi));  // a bow tie
  EXPECT_FALSE(
      Polygon({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}).AxisAlignedBox(lo, hi));  // an L
  ASSERT_TRUE(Polygon({{1, 2}, {1, -3}, {4, -3}, {4, 2}}).AxisAlignedBox(lo, hi));  // clockwise
  EXPECT_EQ(lo, Vec2(1, -3));
  EXPECT_EQ(hi, Vec2(4, 2));
}

}  // namespace
}  // namespace colony
