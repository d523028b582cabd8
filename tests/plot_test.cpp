// colony plot (PlotCommand, apps/colony/plot.cpp) on a real run folder and a
// real sweep made by the colony program: the PNG files it draws, and what it
// says about a mistake.
#include <filesystem>
#include <fstream>

#include "apps/colony/sweep.h"
#include "tests/test_util.h"

namespace {

namespace fs = std::filesystem;

using colony::sweep::PlotCommand;
using colony::testing::ReadFile;

bool OnPath(const std::string& program) {
  return std::system(("command -v " + program + " >/dev/null 2>&1").c_str()) == 0;
}

// A PNG file: its signature, and an image of more than a few bytes.
bool IsPng(const fs::path& file) {
  if (!fs::exists(file) || fs::file_size(file) < 1000) return false;
  return ReadFile(file).compare(0, 8, "\x89PNG\r\n\x1a\n") == 0;
}

// PlotCommand's exit status and what it printed on standard error.
std::pair<int, std::string> Plot(const std::vector<std::string>& args) {
  ::testing::internal::CaptureStderr();
  const int status = PlotCommand(args);
  return {status, ::testing::internal::GetCapturedStderr()};
}

// A sweep over loop functions sweep_metrics' scale (metric "value", scale x
// tick + seed, for 20 ticks), 2 scales x 3 seeds, summarized.
class PlotTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(colony::testing::FreshTempDir("colony_plot_test", "sweep"));
    fs::create_directories(*dir_);
    const fs::path exp = *dir_ / "metrics.xml";
    std::ofstream(exp) << "<colony><framework><experiment length=\"2\" ticks_per_second=\"10\" "
                          "random_seed=\"1\"/></framework>"
                          "<loop_functions library=\"" COLONY_BINARY_DIR
                          "/tests/plugins/libsweep_metrics.so\" label=\"sweep_metrics\"><params "
                          "scale=\"1\"/></loop_functions>"
                          "<arena size=\"2,2,1\" center=\"0,0,0.5\"/>"
                          "<physics_engines><kinematics2d id=\"k2d\"/></physics_engines></colony>";
    const auto r = colony::testing::RunCommand(
        COLONY_EXE " sweep " + exp.string() +
        " --param loop_functions.params.scale=0.5,1 --seeds 1..3 --quiet --out " +
        (*dir_ / "sweep").string() + " && " COLONY_EXE " sweep --summarize --quiet " +
        (*dir_ / "sweep").string());
    ASSERT_EQ(r.status, 0) << r.output;
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
  }
  void SetUp() override {
    if (!OnPath("gnuplot")) GTEST_SKIP() << "gnuplot is not installed (Debian: gnuplot-nox)";
  }
  static fs::path sweep() { return *dir_ / "sweep"; }
  static fs::path* dir_;
};
fs::path* PlotTest::dir_ = nullptr;

TEST_F(PlotTest, ARunsTimeSeries) {
  const fs::path run = sweep() / "runs" / "scale=1_seed=2";
  const auto [status, err] = Plot({run.string(), "--metric", "value", "--quiet"});
  EXPECT_EQ(status, 0) << err;
  EXPECT_TRUE(IsPng(run / "plot-value.png"));
}

TEST_F(PlotTest, ASweepsMeanWithABandPerCombination) {
  const fs::path png = *dir_ / "series.png";
  for (const std::string band : {"quantiles", "std", "none"}) {
    fs::remove(png);
    const auto [status, err] = Plot(
        {sweep().string(), "--metric=value", "--band", band, "--out", png.string(), "--quiet"});
    EXPECT_EQ(status, 0) << band << ": " << err;
    EXPECT_TRUE(IsPng(png)) << band;
  }
  // Kept for a look: build/tests/plot_test_series.png.
  Plot({sweep().string(), "--metric", "value", "--out",
        COLONY_BINARY_DIR "/tests/plot_test_series.png", "--quiet"});
}

TEST_F(PlotTest, AFinalValueAgainstAParameter) {
  const auto [status, err] =
      Plot({sweep().string(), "--metric", "value", "--against", "loop_functions.params.scale"});
  EXPECT_EQ(status, 0) << err;
  EXPECT_TRUE(IsPng(sweep() / "plot-value-loop_functions.params.scale.png"));
}

TEST_F(PlotTest, MistakesAreNamed) {
  const std::string run = (sweep() / "runs" / "scale=1_seed=2").string();
  struct Case {
    std::vector<std::string> args;
    std::string expected;
  } cases[] = {
      {{run, "--metric", "valeu"},
       "'valeu' is not a metric of " + run + "/metrics.csv; did you mean 'value'?"},
      {{sweep().string(), "--metric", "valeu"}, "did you mean 'value'?"},
      {{sweep().string(), "--metric", "value", "--against", "scale"},
       "'scale' is not a swept parameter; they are loop_functions.params.scale"},
      {{run, "--metric", "value", "--against", "x"}, "--against needs a sweep folder"},
      {{run}, "--metric NAME is needed"},
      {{"/no/such/dir", "--metric", "value"}, "neither a run folder"},
      {{run, "--metric", "value", "--band", "quantile"}, "did you mean 'quantiles'?"},
      {{run, "--metric", "value", "--out", "x.jpg"}, "name the file .png"},
      {{run, "--metrc", "value"}, "unknown option '--metrc'; did you mean '--metric'?"},
  };
  for (const auto& c : cases) {
    const auto [status, err] = Plot(c.args);
    EXPECT_EQ(status, 2) << c.expected << "\n" << err;
    EXPECT_NE(err.find(c.expected), std::string::npos) << err;
    EXPECT_NE(err.find("run 'colony plot --help' for usage"), std::string::npos) << err;
  }
  // A sweep not yet summarized.
  const fs::path bare = *dir_ / "bare";
  fs::create_directories(bare);
  std::ofstream(bare / "sweep.xml") << "<sweep/>";
  const auto [status, err] = Plot({bare.string(), "--metric", "value"});
  EXPECT_EQ(status, 2);
  EXPECT_NE(err.find("has no summary_timeseries.csv; run 'colony sweep --summarize " +
                     bare.string() + "' first"),
            std::string::npos)
      << err;
}

TEST(Plot, HelpNamesEveryOption) {
  ::testing::internal::CaptureStdout();
  EXPECT_EQ(PlotCommand({"--help"}), 0);
  const std::string help = ::testing::internal::GetCapturedStdout();
  for (const char* option : {"usage: colony plot", "--metric", "--against", "--band", "--out"}) {
    EXPECT_NE(help.find(option), std::string::npos) << option << "\n" << help;
  }
}

}  // namespace
