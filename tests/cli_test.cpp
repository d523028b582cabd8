// The colony program as a user runs it: the demo shortened, the output
// contract, exit statuses and messages for bad command lines.
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/test_util.h"

namespace {

namespace fs = std::filesystem;

using Result = colony::testing::CommandResult;

Result Colony(const std::string& args) {
  return colony::testing::RunCommand(std::string(COLONY_EXE) + " " + args);
}

using colony::testing::ReadFile;

fs::path TempDir(const std::string& name) {
  return colony::testing::FreshTempDir("colony_cli_test", name);
}

TEST(Cli, DemoShortenedWritesTheOutputContract) {
  const fs::path out = TempDir("demo");
  const Result r = Colony("run " COLONY_SOURCE_DIR
                          "/experiments/diffusion.xml --set framework.experiment.length=5 --out " +
                          out.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("results in " + out.string()), std::string::npos) << r.output;
  const std::string summary = ReadFile(out / "summary.json");
  for (const char* key : {"\"ticks\": 50", "\"simulated_seconds\": 5", "\"wall_seconds\"",
                          "\"robots\": 120", "\"threads\": 2", "\"seed\": 1",
                          "\"robot_steps_per_second\"", "\"final_state_hash\": \""}) {
    EXPECT_NE(summary.find(key), std::string::npos) << key << " missing in\n" << summary;
  }
  // The resolved experiment carries the override.
  EXPECT_NE(ReadFile(out / "experiment.xml").find("length=\"5\""), std::string::npos);
  // metrics.csv: header and a row every 10 ticks from tick 0, robots wandered off.
  std::istringstream metrics(ReadFile(out / "metrics.csv"));
  std::string header, line, first, last;
  std::getline(metrics, header);
  EXPECT_EQ(header, "tick,time,robots,mean_displacement,mean_path_length,in_contact,contact_ticks");
  int rows = 0;
  while (std::getline(metrics, line)) {
    if (rows == 0) first = line;
    last = line;
    ++rows;
  }
  EXPECT_EQ(rows, 6);
  EXPECT_EQ(first.substr(0, 12), "0,0,120,0,0,") << first;  // tick 0: nobody moved yet
  EXPECT_EQ(last.substr(0, 7), "50,5,12");
  fs::remove_all(out);
}

TEST(Cli, SeedAndThreadsFromCommandLine) {
  const fs::path a = TempDir("a"), b = TempDir("b"), c = TempDir("c");
  const std::string base =
      "run " COLONY_SOURCE_DIR
      "/experiments/diffusion.xml --quiet --set framework.experiment.length=3 ";
  ASSERT_EQ(Colony(base + "--threads 1 --seed 5 --out " + a.string()).status, 0);
  ASSERT_EQ(Colony(base + "--threads 2 --seed 5 --out " + b.string()).status, 0);
  ASSERT_EQ(Colony(base + "--threads 2 --seed 6 --out " + c.string()).status, 0);
  auto hash = [](const fs::path& dir) {
    const std::string s = ReadFile(dir / "summary.json");
    const size_t k = s.find("final_state_hash");
    return s.substr(k, 40);
  };
  EXPECT_EQ(hash(a), hash(b));
  EXPECT_NE(hash(a), hash(c));
  EXPECT_NE(ReadFile(a / "summary.json").find("\"seed\": 5"), std::string::npos);
  for (const auto& d : {a, b, c}) fs::remove_all(d);
}

// 0 threads runs everything on the calling thread: the final line and
// summary.json say 1 thread, not 0.
TEST(Cli, ZeroThreadsAreReportedAsOne) {
  const fs::path out = TempDir("zero_threads");
  const Result r = Colony("run " COLONY_SOURCE_DIR
                          "/experiments/diffusion.xml --threads 0 "
                          "--set framework.experiment.length=1 --out " +
                          out.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find(", 1 thread)"), std::string::npos) << r.output;
  EXPECT_NE(ReadFile(out / "summary.json").find("\"threads\": 1,"), std::string::npos);
  fs::remove_all(out);
}

// A huge arena is refused with exit status 2 naming the attribute, at once.
TEST(Cli, HugeArenaExitsWithStatus2) {
  const Result r =
      Colony("run " COLONY_SOURCE_DIR "/experiments/diffusion.xml --set arena.size=1e9,1e9,1e9");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find(
                "<arena> attribute 'size': '1e9,1e9,1e9' is out of range; accepted: a number in "
                "(0, 100000]"),
            std::string::npos)
      << r.output;
}

TEST(Cli, QuietPrintsNothing) {
  const fs::path out = TempDir("quiet");
  const Result r =
      Colony("run " COLONY_SOURCE_DIR
             "/experiments/diffusion.xml --quiet --set framework.experiment.length=1 --out " +
             out.string());
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.output, "");
  fs::remove_all(out);
}

TEST(Cli, BadCommandLinesExitWithStatus2AndSayWhy) {
  struct Case {
    std::string args, expected;
  } cases[] = {
      {"", "usage"},
      {"fly", "unknown command 'fly'"},
      {"run", "needs an experiment file"},
      {"run " COLONY_SOURCE_DIR "/experiments/diffusion.xml --threads -1",
       "--threads: '-1' is not accepted"},
      {"run " COLONY_SOURCE_DIR "/experiments/diffusion.xml --threads two",
       "--threads: 'two' is not accepted"},
      {"run " COLONY_SOURCE_DIR "/experiments/diffusion.xml --seed", "--seed needs a value"},
      {"run " COLONY_SOURCE_DIR "/experiments/diffusion.xml --frobnicate",
       "unknown option '--frobnicate'"},
      {"run " COLONY_SOURCE_DIR "/experiments/diffusion.xml --set length", "expected PATH=VALUE"},
      {"run " COLONY_SOURCE_DIR "/experiments/diffusion.xml --set framework.experiment.length=-3",
       "attribute 'length': '-3' is out of range"},
      {"run " COLONY_SOURCE_DIR "/experiments/diffusion.xml --set framework.experimnt.length=3",
       "did you mean 'experiment'"},
      {"run /no/such/file.xml", "no such file"},
      {"query no_such_plugin", "no plugin kind or plugin named 'no_such_plugin'"},
  };
  for (const auto& c : cases) {
    const Result r = Colony(c.args);
    EXPECT_EQ(r.status, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.args << "\n" << r.output;
  }
}

TEST(Cli, BadInputLeavesNoResult) {
  const fs::path out = TempDir("bad");
  const Result r =
      Colony("run " COLONY_SOURCE_DIR "/experiments/diffusion.xml --set arena.size=0,0,0 --out " +
             out.string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_FALSE(fs::exists(out / "summary.json"));
}

TEST(Cli, QueryListsPluginsWithTheirAttributes) {
  const Result all = Colony("query");
  ASSERT_EQ(all.status, 0) << all.output;
  for (const char* label : {"marxbot", "foot-bot", "box", "cylinder", "light", "kinematics2d",
                            "proximity", "ground", "positioning", "wheel_encoders",
                            "differential_steering", "leds", "diffusion", "diffusion_metrics"}) {
    EXPECT_NE(all.output.find(label), std::string::npos) << label;
  }
  const Result one = Colony("query proximity");
  ASSERT_EQ(one.status, 0);
  EXPECT_NE(one.output.find("noise_std_dev"), std::string::npos) << one.output;
  EXPECT_NE(one.output.find("range = a number > 0 (m)"), std::string::npos) << one.output;
  // The attributes the core reads on every sensor and controller element.
  for (const char* attribute : {"period = a number of seconds", "phase = a number of seconds",
                                "bus = true, false  [default: false]"}) {
    EXPECT_NE(one.output.find(attribute), std::string::npos) << attribute << "\n" << one.output;
  }
  const Result controller = Colony("query diffusion");
  EXPECT_NE(controller.output.find("rate = a number of steps per second"), std::string::npos)
      << controller.output;
  const Result kind = Colony("query engine");
  EXPECT_NE(kind.output.find("kinematics2d"), std::string::npos);
  EXPECT_EQ(kind.output.find("marxbot"), std::string::npos);
}

// Physics models say which components they simulate: what decides which
// engine accepts a gripper or a manipulator.
TEST(Cli, QueryShowsWhatEachPhysicsModelSimulates) {
  const Result models = Colony("query physics_model");
  ASSERT_EQ(models.status, 0) << models.output;
  EXPECT_NE(
      models.output.find(
          "kinematics2d:marxbot\n      circular footprint moved by its differential drive; stops "
          "at obstacles; with manipulator=\"true\" a kinematic head (elevation, rotation, tilt) "
          "whose magnet carries pockets\n      simulates: drive, manipulator\n"),
      std::string::npos)
      << models.output;
  if (colony::testing::HaveEngine("dynamics2d") || colony::testing::HaveEngine("dynamics3d")) {
    EXPECT_NE(models.output.find("simulates: drive, gripper"), std::string::npos) << models.output;
  }
  if (colony::testing::HaveEngine("dynamics3d")) {
    EXPECT_NE(models.output.find("simulates: drive, manipulator"), std::string::npos)
        << models.output;
  }
  EXPECT_NE(models.output.find(
                "kinematics2d:box\n      fixed obstacle, movable or not (not pushed in this "
                "engine)\n      simulates: (no components)\n"),
            std::string::npos)
      << models.output;
}

TEST(Cli, Version) {
  const Result r = Colony("version");
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.output.rfind("colony ", 0), 0u);
}

}  // namespace
