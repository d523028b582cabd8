// When devices with their own rates run (core/schedule.h), and what the bus
// accounting counts per poll and event (core/bus.h).
#include "core/schedule.h"

#include <gtest/gtest.h>

#include <vector>

#include "core/bus.h"

namespace colony {
namespace {

std::vector<uint64_t> DueTicks(Schedule schedule, uint64_t ticks) {
  std::vector<uint64_t> due;
  for (uint64_t t = 1; t <= ticks; ++t) {
    if (schedule.Due(t)) due.push_back(t);
  }
  return due;
}

TEST(Schedule, FifteenMillisecondsAt200TicksPerSecondIsEveryThirdTickFromTheFirst) {
  const auto due = DueTicks(Schedule(0.015 / 0.005, 0), 30);
  EXPECT_EQ(due, (std::vector<uint64_t>{1, 4, 7, 10, 13, 16, 19, 22, 25, 28}));
}

TEST(Schedule, SixtySevenHertzAt200TicksPerSecondRuns67TimesASecond) {
  // 200 / 67 = 2.985 ticks apart: 3 ticks but for one gap of 2 a second.
  const auto due = DueTicks(Schedule(200.0 / 67.0, 0), 2000);
  EXPECT_EQ(due.size(), 670u);
  EXPECT_EQ(std::vector<uint64_t>(due.begin(), due.begin() + 4),
            (std::vector<uint64_t>{1, 3, 6, 9}));
  int gaps_of_two = 0;
  for (size_t i = 1; i < due.size(); ++i) {
    const uint64_t gap = due[i] - due[i - 1];
    EXPECT_TRUE(gap == 2 || gap == 3) << "gap " << gap << " at tick " << due[i];
    gaps_of_two += gap == 2;
  }
  EXPECT_EQ(gaps_of_two, 10);  // one a second
}

TEST(Schedule, APhaseDelaysEveryRun) {
  EXPECT_EQ(DueTicks(Schedule(8, 2.5), 30), (std::vector<uint64_t>{3, 11, 19, 27}));
  EXPECT_TRUE(Schedule().every_tick());
  EXPECT_EQ(DueTicks(Schedule(), 3), (std::vector<uint64_t>{1, 2, 3}));
}

TEST(Bus, APollOf24TwoByteValuesIs61BytesAnd4087BytesASecondAt67Hz) {
  EXPECT_EQ(BusPollBytes(24), 61u);  // (24 x 2 + 3) + 2 x (2 + 3)
  EXPECT_EQ(67 * BusPollBytes(24), 4087u);
  EXPECT_EQ(BusPollBytes(24, 2, 3), 61u);
  EXPECT_EQ(BusEventBytes(), 7u);  // index and value, 2 x 2 + 3
}

}  // namespace
}  // namespace colony
