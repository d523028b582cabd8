// The shelf-climbing experiment (experiments/handbot_shelf.xml; seed 000,
// 3.3.2): the hand-bot climbs the board with its rope and grippers, takes the
// book and brings it down, as a user running it sees in metrics.csv; the
// same results whatever the thread count; a frame of it shows the robot on
// its rope; and what it says when there is no board to climb.
#include <cmath>
#include <string>
#include <vector>

#include "actuators/handbot_arms/handbot_arms_state.h"
#include "core/image_renderer.h"
#include "tests/test_util.h"

namespace colony::testing {
namespace {

std::unique_ptr<Simulation> Load(uint64_t seed, std::vector<std::string> overrides = {},
                                 std::optional<int> threads = std::nullopt) {
  return LoadExperiment("handbot_shelf.xml", seed, std::move(overrides), threads);
}

TEST(handbot_shelf, TheBookComesDownForSeedsOneToThree) {
  for (uint64_t seed : {1, 2, 3}) {
    auto sim = Load(seed);
    const Space& space = sim->space();
    const uint32_t book = space.Find("book").index, robot = space.Find("climber").index,
                   board = space.Find("board").index;
    const double book_start = space.pose(book).position.z();
    bool held_book_high = false;  // the robot held it above the shelf's ledge
    int grips = 0;                // grips on the board, counted as they start
    bool gripping[2] = {false, false};
    while (!sim->Done()) {
      sim->Step();
      const HandbotArmsState& arms = *space.Get<HandbotArmsState>(robot);
      for (int k = 0; k < 2; ++k) {
        const bool on_board = arms.claws[k].held == board;
        if (on_board && !gripping[k]) ++grips;
        gripping[k] = on_board;
      }
      const bool book_held = arms.claws[0].held == book || arms.claws[1].held == book;
      if (book_held && space.pose(book).position.z() > book_start - 0.05) held_book_high = true;
    }
    EXPECT_EQ(Metric(*sim, "success"), 1) << "seed " << seed;
    EXPECT_EQ(Metric(*sim, "book_retrieved"), 1) << "seed " << seed;
    EXPECT_GT(Metric(*sim, "success_time"), 40) << "seed " << seed;
    EXPECT_LT(Metric(*sim, "success_time"), 180) << "seed " << seed;
    EXPECT_GT(Metric(*sim, "climb_height"), 0.4) << "seed " << seed;
    EXPECT_LT(Metric(*sim, "robot_z"), 0.05) << "seed " << seed << ": back on the floor";
    EXPECT_TRUE(held_book_high) << "seed " << seed << ": taken from the ledge by a gripper";
    // It climbed by alternating its grippers on the board: at least four
    // grips, each half a turn (0.12 m) above the last.
    EXPECT_GE(grips, 4) << "seed " << seed;
    EXPECT_LT(space.pose(book).position.z(), 0.3) << "seed " << seed;
  }
}

TEST(handbot_shelf, SameFinalHashWith0And1And2Threads) {
  std::vector<uint64_t> hashes;
  for (int threads : {0, 1, 2}) {
    auto sim = Load(2, {"framework.experiment.length=60"}, threads);
    while (!sim->Done()) sim->Step();
    hashes.push_back(sim->StateHash());
  }
  EXPECT_EQ(hashes[0], hashes[1]);
  EXPECT_EQ(hashes[0], hashes[2]);
}

TEST(handbot_shelf, AFrameShowsTheHandBotOnItsRope) {
  if (!HaveImageRenderer()) GTEST_SKIP() << "built without the OSMesa renderer";
  unsetenv("DISPLAY");
  auto sim = Load(1, {"framework.experiment.length=40"});
  while (!sim->Done()) sim->Step();
  const Space& space = sim->space();
  const EntityHandle robot = space.Find("climber");
  const Vec3 p = space.pose(robot.index).position;
  ASSERT_GT(p.z(), 0.1) << "climbing by 40 s";
  const auto renderer = MakeImageRenderer(*sim);
  // From 2.5 m away on -y (beside the board, which runs along x), level with
  // the hull, looking along +y; 320 x 240 pixels over 40 degrees.
  CameraView side;
  side.position = Vec3(p.x(), p.y() - 2.5, p.z() + 0.15);
  side.orientation = FromEulerZYX(DegToRad(90), 0, 0);
  side.fov = 40;
  side.far_clip = 10;
  side.width = 320;
  side.height = 240;
  auto draw = [&](EntityHandle hidden) {
    CameraView view = side;
    view.hidden = hidden;
    std::vector<uint8_t> rgb;
    renderer->Render(view, rgb);
    return rgb;
  };
  const auto with = draw({}), without = draw(robot);
  auto differs = [&](int x, int y) {
    const size_t i = (static_cast<size_t>(y) * 320 + x) * 3;
    return with[i] != without[i] || with[i + 1] != without[i + 1] || with[i + 2] != without[i + 2];
  };
  // The hand-bot: pixels around the image's centre (where it is) differ
  // with and without it.
  int robot_pixels = 0;
  for (int y = 100; y < 140; ++y)
    for (int x = 140; x < 180; ++x) robot_pixels += differs(x, y);
  EXPECT_GT(robot_pixels, 400) << "the hand-bot where it is";
  // The rope: above it, the centre columns differ in most rows up to the
  // top of the image.
  int rope_rows = 0;
  for (int y = 0; y < 60; ++y) {
    bool row = false;
    for (int x = 150; x <= 170; ++x) row = row || differs(x, y);
    rope_rows += row;
  }
  EXPECT_GT(rope_rows, 40) << "the rope runs up out of the image";
}

TEST(handbot_shelf, WithoutABoardTheRobotSaysSoAndStaysOnTheFloor) {
  // The board moved 1 m to the side: nothing for the grippers to hold.
  ::testing::internal::CaptureStderr();
  auto sim =
      Load(1, {"arena.box[board].body.position=0.555,1,0", "framework.experiment.length=40"});
  while (!sim->Done()) sim->Step();
  const std::string log = ::testing::internal::GetCapturedStderr();
  EXPECT_TRUE(Mentions(log, {"warning", "climber", "board", "gripper"})) << log;
  EXPECT_EQ(Metric(*sim, "success"), 0);
  EXPECT_LT(Metric(*sim, "climb_height"), 0.05);
}

TEST(handbot_shelf, BadLoopFunctionParametersAreRefused) {
  EXPECT_TRUE(Mentions(LoadError(ReadFile(COLONY_SOURCE_DIR "/experiments/handbot_shelf.xml"),
                                 {"loop_functions.params.book=nothing"}),
                       {"book", "nothing", "no entity"}));
}

}  // namespace
}  // namespace colony::testing
