// Random streams: reproducible per owner, independent between owners, and
// with the distributions they claim. Suites are named core_test_* so
// `ctest -R core_test` selects them.
#include "core/random.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace colony {
namespace {

std::vector<uint64_t> Draw(RandomStream stream, int n = 100) {
  std::vector<uint64_t> out;
  for (int i = 0; i < n; ++i) out.push_back(stream.NextU64());
  return out;
}

TEST(core_test_random, SameSeedAndOwnerGiveTheSameSequence) {
  EXPECT_EQ(Draw(RandomStream::For(7, "mb12", "sensor/proximity")),
            Draw(RandomStream::For(7, "mb12", "sensor/proximity")));
  EXPECT_EQ(Draw(RandomStream(42)), Draw(RandomStream(42)));
  EXPECT_EQ(Draw(RandomStream()), Draw(RandomStream(0)));
}

TEST(core_test_random, DifferentOwnersPurposesAndSeedsDiffer) {
  const auto base = Draw(RandomStream::For(7, "mb12", "controller"));
  EXPECT_NE(Draw(RandomStream::For(7, "mb13", "controller")), base);
  EXPECT_NE(Draw(RandomStream::For(7, "mb12", "sensor/proximity")), base);
  EXPECT_NE(Draw(RandomStream::For(8, "mb12", "controller")), base);
  // Owner and purpose are kept apart: "ab"+"c" is not "a"+"bc".
  EXPECT_NE(Draw(RandomStream::For(1, "ab", "c")), Draw(RandomStream::For(1, "a", "bc")));
  // Streams of neighbouring owners share no values at all.
  const auto a = Draw(RandomStream::For(1, "mb1", "controller"), 1000);
  const auto b = Draw(RandomStream::For(1, "mb2", "controller"), 1000);
  for (uint64_t v : a) EXPECT_EQ(std::count(b.begin(), b.end(), v), 0);
}

TEST(core_test_random, ACopyContinuesTheSameSequence) {
  RandomStream s(3);
  s.NextU64();
  RandomStream copy = s;
  EXPECT_EQ(Draw(copy, 10), Draw(s, 10));
}

TEST(core_test_random, UniformStaysInRange) {
  RandomStream s(1);
  double sum = 0;
  for (int i = 0; i < 10000; ++i) {
    const double u = s.Uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    const double v = s.Uniform(-2.0, 3.0);
    ASSERT_GE(v, -2.0);
    ASSERT_LT(v, 3.0);
    sum += v;
  }
  EXPECT_NEAR(sum / 10000, 0.5, 0.1);
}

TEST(core_test_random, UniformIntCoversEveryValue) {
  RandomStream s(2);
  std::vector<int> counts(6, 0);
  for (int i = 0; i < 6000; ++i) {
    const uint64_t k = s.UniformInt(6);
    ASSERT_LT(k, 6u);
    ++counts[k];
  }
  for (int c : counts) EXPECT_NEAR(c, 1000, 150);
  EXPECT_EQ(s.UniformInt(0), 0u);
  EXPECT_EQ(s.UniformInt(1), 0u);
}

TEST(core_test_random, GaussianHasTheRequestedMeanAndStdDev) {
  RandomStream s = RandomStream::For(5, "mb0", "noise");
  const int n = 10000;
  double sum = 0, sum_sq = 0;
  for (int i = 0; i < n; ++i) {
    const double v = s.Gaussian(3.0, 2.0);
    ASSERT_TRUE(std::isfinite(v));
    sum += v;
    sum_sq += v * v;
  }
  const double mean = sum / n;
  const double std_dev = std::sqrt(sum_sq / n - mean * mean);
  // Standard errors: 0.02 for the mean, about 0.014 for the deviation.
  EXPECT_NEAR(mean, 3.0, 0.1);
  EXPECT_NEAR(std_dev, 2.0, 0.1);
  // A zero deviation gives the mean exactly.
  EXPECT_EQ(s.Gaussian(1.5, 0.0), 1.5);
}

TEST(core_test_random, BernoulliMatchesItsProbability) {
  RandomStream s(9);
  int hits = 0;
  for (int i = 0; i < 10000; ++i) hits += s.Bernoulli(0.25);
  EXPECT_NEAR(hits / 10000.0, 0.25, 0.02);
  EXPECT_FALSE(s.Bernoulli(0.0));
  EXPECT_TRUE(s.Bernoulli(1.0));
}

}  // namespace
}  // namespace colony
