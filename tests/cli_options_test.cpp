// The colony program's command line as a user meets it (CLI11): --help on
// every command, --opt=value, suggestions for typos in short messages, log
// levels, the tick in log lines, run.log in the run folder, the progress bar
// on a terminal, and output folders that are never mixed.
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "core/text.h"
#include "tests/test_util.h"

namespace {

namespace fs = std::filesystem;

using colony::testing::ReadFile;
using Result = colony::testing::CommandResult;

const std::string kDiffusion = COLONY_SOURCE_DIR "/experiments/diffusion.xml";
// Three robots for one simulated second; velocity 1 m/s is beyond the wheels'
// limit, so each robot's actuator warns once, at the first tick that acts on
// a command.
const std::string kWarningRun = kDiffusion +
                                " --set framework.experiment.length=1"
                                " --set arena.distribute.entity.quantity=3"
                                " --set controllers.diffusion[dc].params.velocity=1";

Result Colony(const std::string& args) {
  return colony::testing::RunCommand(std::string(COLONY_EXE) + " " + args);
}

fs::path TempDir(const std::string& name) {
  return colony::testing::FreshTempDir("colony_cli_options_test", name);
}

size_t Lines(const std::string& text) {
  return static_cast<size_t>(std::count(text.begin(), text.end(), '\n'));
}

bool Has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

std::string FinalHash(const std::string& output) {
  const size_t at = output.find("final state hash ");
  return at == std::string::npos ? "" : output.substr(at, 33);
}

TEST(CliOptions, HelpOnEveryCommandExitsZeroAndListsItsOptions) {
  struct Case {
    std::string args;
    std::vector<std::string> shows;
  } cases[] = {
      {"--help", {"usage: colony", "run", "query", "sweep", "version", "Exit status"}},
      {"help", {"usage: colony", "run", "query"}},
      {"run --help",
       {"usage: colony run", "--threads N", "--seed S", "--set PATH=VALUE", "--out DIR",
        "--overwrite", "--quiet", "--log-level LEVEL", "--frames DIR", "--video FILE.mp4",
        "hides warnings", "run.log"}},
      {"run -h", {"usage: colony run", "--log-level"}},
      {"help run", {"usage: colony run", "--log-level"}},
      // --help wins over a missing or bad argument.
      {"run --threads two --help", {"usage: colony run"}},
      {"query --help", {"usage: colony query", "KIND|NAME"}},
      {"version --help", {"usage: colony version"}},
      {"sweep --help", {"colony sweep"}},
  };
  for (const auto& c : cases) {
    const Result r = Colony(c.args);
    EXPECT_EQ(r.status, 0) << c.args << "\n" << r.output;
    for (const auto& part : c.shows) EXPECT_TRUE(Has(r.output, part)) << c.args << "\n" << r.output;
  }
  // No command at all: the overview, as an error.
  const Result none = Colony("");
  EXPECT_EQ(none.status, 2);
  EXPECT_TRUE(Has(none.output, "usage: colony")) << none.output;
  const Result version = Colony("--version");
  EXPECT_EQ(version.status, 0);
  EXPECT_EQ(version.output.rfind("colony ", 0), 0u) << version.output;
}

TEST(CliOptions, OptionValuesAfterAnEqualsSignMeanTheSame) {
  const fs::path a = TempDir("equals_a"), b = TempDir("equals_b");
  const std::string base = "run " + kDiffusion + " --threads=1 ";
  const Result spaced =
      Colony(base + "--seed 3 --set framework.experiment.length=2 --out " + a.string());
  const Result equals =
      Colony(base + "--seed=3 --set=framework.experiment.length=2 --out=" + b.string());
  ASSERT_EQ(spaced.status, 0) << spaced.output;
  ASSERT_EQ(equals.status, 0) << equals.output;
  EXPECT_FALSE(FinalHash(spaced.output).empty()) << spaced.output;
  EXPECT_EQ(FinalHash(spaced.output), FinalHash(equals.output));
  EXPECT_TRUE(Has(ReadFile(b / "summary.json"), "\"seed\": 3")) << ReadFile(b / "summary.json");
  EXPECT_TRUE(Has(equals.output, "20 ticks")) << equals.output;
  // Another seed, another hash: the value was read.
  const Result other =
      Colony(base + "--seed=4 --set=framework.experiment.length=2 --out=" + (a / "other").string());
  EXPECT_NE(FinalHash(other.output), FinalHash(equals.output));
  fs::remove_all(a);
  fs::remove_all(b);
}

// A bad command line: exit status 2 and a short message (the problem, then
// where the usage is), never the whole usage.
TEST(CliOptions, MistakesGetShortMessagesWithSuggestions) {
  struct Case {
    std::string args, expected, usage;
  } cases[] = {
      {"run " + kDiffusion + " --seeed 3", "unknown option '--seeed'; did you mean '--seed'?",
       "run"},
      {"run " + kDiffusion + " --seeed=3", "unknown option '--seeed'; did you mean '--seed'?",
       "run"},
      {"run " + kDiffusion + " --thread 2", "did you mean '--threads'?", "run"},
      {"run " + kDiffusion + " --overwrit", "did you mean '--overwrite'?", "run"},
      {"run " + kDiffusion + " -q", "unknown option '-q'; did you mean '--quiet'?", "run"},
      {"run " + kDiffusion + " --log-level verbose",
       "--log-level: 'verbose' is not accepted; expected error, warning, info, debug", "run"},
      {"run " + kDiffusion + " --log-level=warnign", "(did you mean 'warning'?)", "run"},
      {"run " + kDiffusion + " --seed=-1", "--seed: '-1' is not accepted", "run"},
      {"run " + kDiffusion + " --out", "--out needs a value", "run"},
      {"run " + kDiffusion + " --out ''", "--out needs a folder", "run"},
      {"rnu " + kDiffusion, "unknown command 'rnu'; did you mean 'run'?", ""},
      {"qeury", "unknown command 'qeury'; did you mean 'query'?", ""},
      {"--frobnicate", "unknown option '--frobnicate'", ""},
      {"query proximty", "no plugin kind or plugin named 'proximty'; did you mean 'proximity'",
       "query"},
      {"query sensr", "did you mean 'sensor'", "query"},
      {"query a b", "query takes at most one KIND or NAME", "query"},
      {"version now", "version takes nothing, not 'now'", "version"},
  };
  for (const auto& c : cases) {
    const Result r = Colony(c.args);
    EXPECT_EQ(r.status, 2) << c.args << "\n" << r.output;
    EXPECT_EQ(r.output.rfind("colony: ", 0), 0u) << c.args << "\n" << r.output;
    EXPECT_TRUE(Has(r.output, c.expected)) << c.args << "\n" << r.output;
    const std::string usage =
        "run 'colony" + (c.usage.empty() ? "" : " " + c.usage) + " --help' for usage\n";
    EXPECT_TRUE(Has(r.output, usage)) << c.args << "\n" << r.output;
    EXPECT_LE(Lines(r.output), 3u) << c.args << "\n" << r.output;
    EXPECT_FALSE(Has(r.output, "Options:")) << c.args << "\n" << r.output;
  }
}

TEST(CliOptions, LogLevelsQuietAndRunLog) {
  const fs::path dir = TempDir("levels");
  auto run = [&](const std::string& name, const std::string& extra) {
    return Colony("run " + kWarningRun + " --out " + (dir / name).string() + " " + extra);
  };
  const std::regex warning(
      R"(colony: warning: \[tick [0-9]+\] robot 'mb0': differential_steering wheel speed 1 m/s)");
  const std::regex tick_two(R"(colony: warning: \[tick 2\] robot 'mb[0-2]')");

  // Default (info): warnings, each with its tick; no debug lines.
  const Result normal = run("normal", "");
  ASSERT_EQ(normal.status, 0) << normal.output;
  EXPECT_TRUE(std::regex_search(normal.output, warning)) << normal.output;
  // The first tick that acts on the controllers' commands.
  EXPECT_TRUE(std::regex_search(normal.output, tick_two)) << normal.output;
  EXPECT_FALSE(Has(normal.output, "colony: debug:")) << normal.output;
  // run.log holds the same lines.
  const std::string log = ReadFile(dir / "normal" / "run.log");
  EXPECT_TRUE(std::regex_search(log, warning)) << log;
  EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 3) << log;
  EXPECT_TRUE(Has(normal.output, "summary.json, run.log)")) << normal.output;

  // debug: more lines, on the terminal and in run.log.
  const Result debug = run("debug", "--log-level debug");
  ASSERT_EQ(debug.status, 0) << debug.output;
  EXPECT_TRUE(Has(debug.output, "colony: debug: loaded ")) << debug.output;
  EXPECT_TRUE(std::regex_search(debug.output, warning)) << debug.output;
  EXPECT_TRUE(Has(ReadFile(dir / "debug" / "run.log"), "colony: debug: loaded "));

  // --quiet: nothing on the terminal, the warnings still in run.log.
  const Result quiet = run("quiet", "--quiet");
  ASSERT_EQ(quiet.status, 0) << quiet.output;
  EXPECT_EQ(quiet.output, "");
  EXPECT_TRUE(std::regex_search(ReadFile(dir / "quiet" / "run.log"), warning));

  // error: warnings are not logged at all.
  const Result errors = run("errors", "--log-level=error");
  ASSERT_EQ(errors.status, 0) << errors.output;
  EXPECT_FALSE(Has(errors.output, "warning")) << errors.output;
  EXPECT_TRUE(fs::exists(dir / "errors" / "run.log"));
  EXPECT_EQ(ReadFile(dir / "errors" / "run.log"), "");
  // The same results whatever is logged.
  EXPECT_EQ(FinalHash(normal.output), FinalHash(debug.output));
  EXPECT_EQ(FinalHash(normal.output), FinalHash(errors.output));
  fs::remove_all(dir);
}

// Without --out the run folder is made after loading: lines logged before are
// kept and written to its run.log first.
TEST(CliOptions, FreshRunFolderGetsRunLog) {
  const fs::path dir = TempDir("fresh");
  fs::create_directories(dir);
  const Result r = colony::testing::RunCommand("cd " + dir.string() + " && " + COLONY_EXE +
                                               " run " + kWarningRun + " --log-level debug");
  ASSERT_EQ(r.status, 0) << r.output;
  std::vector<fs::path> folders;
  for (const auto& e : fs::directory_iterator(dir / "runs")) folders.push_back(e.path());
  ASSERT_EQ(folders.size(), 1u);
  const std::string log = ReadFile(folders[0] / "run.log");
  EXPECT_EQ(log.rfind("colony: debug: loaded ", 0), 0u) << log;
  EXPECT_TRUE(Has(log, "colony: warning: [tick 2] robot 'mb0'")) << log;
  fs::remove_all(dir);
}

// A failed run says why in run.log too.
TEST(CliOptions, RunLogHoldsTheFailure) {
  const fs::path out = TempDir("failure");
  const Result r = Colony("run " + kDiffusion + " --set arena.size=0,0,0 --out " + out.string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(Has(r.output, "colony: error: ")) << r.output;
  EXPECT_TRUE(Has(ReadFile(out / "run.log"), "attribute 'size'")) << ReadFile(out / "run.log");
  fs::remove_all(out);
}

// On a terminal the progress bar is erased before each log line and drawn
// again after, and its last state ends with a newline before the closing
// lines. `script` gives the run a pseudo-terminal.
TEST(CliOptions, LogLinesNeverRunIntoTheProgressBar) {
  if (!colony::OnPath("script")) GTEST_SKIP() << "no 'script' (util-linux) to make a terminal";
  const fs::path out = TempDir("terminal");
  const std::string command =
      std::string(COLONY_EXE) + " run " + kWarningRun + " --out " + out.string();
  const Result r = colony::testing::RunCommand("script -qec \"" + command + "\" /dev/null");
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string erase = "\r\x1b[2K";
  // Every warning starts on an erased line.
  size_t warnings = 0;
  for (size_t at = r.output.find("colony: warning:"); at != std::string::npos;
       at = r.output.find("colony: warning:", at + 1)) {
    ++warnings;
    EXPECT_GE(at, erase.size());
    EXPECT_EQ(r.output.substr(at - erase.size(), erase.size()), erase) << r.output;
  }
  EXPECT_EQ(warnings, 3u) << r.output;
  // The bar was drawn, and its last line ended before the closing lines.
  const size_t bar = r.output.rfind("100%");
  const size_t closing = r.output.find("10 ticks (");
  ASSERT_NE(bar, std::string::npos) << r.output;
  ASSERT_NE(closing, std::string::npos) << r.output;
  EXPECT_LT(bar, closing);
  const std::string between = r.output.substr(bar, closing - bar);
  EXPECT_TRUE(Has(between, "\n")) << between;
  EXPECT_EQ(r.output.find("colony: warning:", bar), std::string::npos) << r.output;
  fs::remove_all(out);
}

#ifdef COLONY_TEST_FRAMES
// A --frames folder that holds a previous run's frames is refused, so they
// cannot be mixed into this run's (or stitched into its --video); with
// --overwrite they are removed first.
TEST(CliOptions, NonEmptyFramesFolderIsRefusedUnlessOverwrite) {
  const fs::path dir = TempDir("frames"), frames = dir / "frames";
  fs::create_directories(frames);
  std::ofstream(frames / "camera0_000099.png") << "a frame of an older run";
  const std::string base = "run " + kDiffusion +
                           " --set framework.experiment.length=0.2"
                           " --set arena.distribute.entity.quantity=3 --frames " +
                           frames.string();
  const Result refused = Colony(base + " --out " + (dir / "run1").string());
  EXPECT_EQ(refused.status, 2) << refused.output;
  EXPECT_TRUE(Has(refused.output, "--frames '" + frames.string() + "' is not empty"))
      << refused.output;
  EXPECT_TRUE(Has(refused.output, "--overwrite")) << refused.output;
  EXPECT_LE(Lines(refused.output), 3u) << refused.output;
  EXPECT_TRUE(fs::exists(frames / "camera0_000099.png"));
  EXPECT_FALSE(fs::exists(dir / "run1" / "summary.json"));

  const Result replaced = Colony(base + " --overwrite --out " + (dir / "run2").string());
  ASSERT_EQ(replaced.status, 0) << replaced.output;
  EXPECT_FALSE(fs::exists(frames / "camera0_000099.png"));
  size_t pngs = 0;
  for (const auto& e : fs::directory_iterator(frames)) pngs += e.path().extension() == ".png";
  EXPECT_EQ(pngs, 3u);  // the initial state and 2 ticks
  // The closing line names the frames folder.
  EXPECT_TRUE(Has(replaced.output, "; frames in " + frames.string() + "/")) << replaced.output;
  fs::remove_all(dir);
}
#endif

}  // namespace
