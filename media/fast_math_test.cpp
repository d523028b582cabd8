// FastAtan2 agrees with std::atan2 to 1e-8 rad everywhere, including the
// axes and the diagonals where the argument reduction switches branches.
#include "media/fast_math.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace colony {
namespace {

TEST(FastAtan2, AgreesWithTheLibraryWithin1e8) {
  std::mt19937_64 gen(3);
  std::uniform_real_distribution<double> u(-10, 10);
  double worst = 0;
  for (int i = 0; i < 1000000; ++i) {
    const double x = u(gen), y = u(gen);
    worst = std::max(worst, std::abs(FastAtan2(y, x) - std::atan2(y, x)));
  }
  EXPECT_LT(worst, 1e-8);
  // Every direction around the circle, at several scales.
  for (int k = -720; k <= 720; ++k) {
    const double a = M_PI * k / 720;
    for (double r : {1e-6, 1.0, 1e4}) {
      const double x = r * std::cos(a), y = r * std::sin(a);
      EXPECT_NEAR(FastAtan2(y, x), std::atan2(y, x), 1e-8) << "angle " << a << " radius " << r;
    }
  }
}

TEST(FastAtan2, SinglePrecisionAgreesWithTheLibraryWithin4e7) {
  std::mt19937_64 gen(4);
  std::uniform_real_distribution<float> u(-10, 10);
  double worst = 0;
  for (int i = 0; i < 1000000; ++i) {
    const float x = u(gen), y = u(gen);
    worst = std::max(worst, std::abs(FastAtan2f(y, x) -
                                     std::atan2(static_cast<double>(y), static_cast<double>(x))));
  }
  EXPECT_LT(worst, 4e-7);
  EXPECT_EQ(FastAtan2f(0.0f, 1.0f), 0.0f);
  EXPECT_EQ(FastAtan2f(0.0f, 0.0f), 0.0f);
  EXPECT_NEAR(FastAtan2f(0.0f, -1.0f), M_PI, 4e-7);
  EXPECT_NEAR(FastAtan2f(1.0f, 0.0f), M_PI / 2, 4e-7);
  EXPECT_NEAR(FastAtan2f(-1.0f, 0.0f), -M_PI / 2, 4e-7);
}

TEST(FastAtan2, AxesAndOrigin) {
  EXPECT_EQ(FastAtan2(0.0, 1.0), 0.0);
  EXPECT_NEAR(FastAtan2(1.0, 0.0), M_PI / 2, 1e-15);
  EXPECT_NEAR(FastAtan2(-1.0, 0.0), -M_PI / 2, 1e-15);
  EXPECT_NEAR(FastAtan2(0.0, -1.0), M_PI, 1e-15);  // behind: +pi
  EXPECT_NEAR(FastAtan2(-0.0, -1.0), -M_PI, 1e-15);
  EXPECT_EQ(FastAtan2(0.0, 0.0), 0.0);
  EXPECT_NEAR(FastAtan2(1.0, 1.0), M_PI / 4, 1e-8);
  EXPECT_NEAR(FastAtan2(-1.0, -1.0), -3 * M_PI / 4, 1e-8);
}

}  // namespace
}  // namespace colony
