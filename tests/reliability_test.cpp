// What a run leaves behind when things go wrong, as a user finds it: a full
// disk, kill -9, Ctrl-C with frames being drawn, a controller that crashes
// or throws something odd, an output folder already in use.
#include <signal.h>
#include <spawn.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "core/output.h"
#include "tests/test_util.h"

namespace {

namespace fs = std::filesystem;
using colony::testing::ReadFile;

fs::path TempDir(const std::string& name) {
  return colony::testing::FreshTempDir("colony_reliability_test", name);
}

// A started `colony` process, its output going to a log file.
struct Process {
  pid_t pid = -1;
  fs::path log;
};

Process Start(const std::vector<std::string>& args, const fs::path& log) {
  fs::create_directories(log.parent_path());
  std::vector<std::string> words{COLONY_EXE};
  words.insert(words.end(), args.begin(), args.end());
  return {colony::testing::SpawnWithOutput(words, log.string()), log};
}

// Sends `signal_number` to the started process (never to a group: a pid of
// -1 would reach every process).
void Signal(const Process& p, int signal_number) {
  ASSERT_GT(p.pid, 0);
  kill(p.pid, signal_number);
}

// The raw wait status.
int Wait(const Process& p) {
  int status = 0;
  if (p.pid <= 0) return -1;
  waitpid(p.pid, &status, 0);
  return status;
}

// Runs colony to the end: (exit status or 128 + signal, output).
std::pair<int, std::string> RunColony(const std::vector<std::string>& args, const fs::path& log) {
  const int status = Wait(Start(args, log));
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return {code, ReadFile(log)};
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

size_t Fields(const std::string& line) {
  return static_cast<size_t>(std::count(line.begin(), line.end(), ',')) + 1;
}

// Every line of a CSV file is a whole row: it ends with a newline and has
// the header's number of fields. Returns the rows (header excluded).
std::vector<std::string> ExpectWholeRows(const fs::path& csv) {
  const std::string text = ReadFile(csv);
  if (text.empty()) return {};
  EXPECT_EQ(text.back(), '\n') << csv << " ends mid-row";
  auto lines = Lines(text);
  const size_t fields = Fields(lines.front());
  for (const auto& line : lines) EXPECT_EQ(Fields(line), fields) << csv << ": '" << line << "'";
  lines.erase(lines.begin());
  return lines;
}

uint64_t TickOf(const std::string& row) { return std::stoull(row.substr(0, row.find(','))); }

// A one-robot experiment with the test controller in `mode` from tick `at`
// on, and the diffusion metrics every tick.
fs::path MisbehaveExperiment(const fs::path& dir, const std::string& mode, int at,
                             int length_seconds) {
  fs::create_directories(dir);
  const fs::path file = dir / (mode + ".xml");
  std::ofstream(file)
      << "<colony><framework><experiment length=\"" << length_seconds
      << "\" ticks_per_second=\"10\" random_seed=\"1\"/></framework>"
         "<controllers><sweep_misbehave id=\"m\" library=\"" COLONY_BINARY_DIR
         "/tests/plugins/libsweep_misbehave.so\"><params mode=\""
      << mode << "\" at=\"" << at
      << "\"/></sweep_misbehave></controllers>"
         "<loop_functions label=\"diffusion_metrics\" library=\"diffusion_metrics\"/>"
         "<arena size=\"2,2,1\" center=\"0,0,0.5\"><marxbot id=\"r\"><body position=\"0,0,0\"/>"
         "<controller config=\"m\"/></marxbot></arena>"
         "<physics_engines><kinematics2d id=\"k2d\"/></physics_engines>"
         "<output metrics_every=\"1\" hash_every=\"1\"/></colony>";
  return file;
}

// A small tmpfs mounted for the test (root only); unmounted at the end.
class TinyDisk {
 public:
  explicit TinyDisk(const fs::path& dir, const std::string& size) : dir_(dir) {
    fs::create_directories(dir);
    mounted_ = mount("tmpfs", dir.c_str(), "tmpfs", 0, ("size=" + size).c_str()) == 0;
    if (!mounted_) why_ = std::strerror(errno);
  }
  ~TinyDisk() {
    if (mounted_) umount(dir_.c_str());
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  bool mounted() const { return mounted_; }
  const std::string& why() const { return why_; }

 private:
  fs::path dir_;
  bool mounted_ = false;
  std::string why_;
};

const std::string kDiffusion = COLONY_SOURCE_DIR "/experiments/diffusion.xml";

TEST(Reliability, DiskFillingUpMidRunFailsNamingTheFileAndReason) {
  const fs::path root = TempDir("full_mid");
  TinyDisk disk(root / "disk", "48k");
  if (!disk.mounted())
    GTEST_SKIP() << "cannot mount a tmpfs here (" << disk.why() << "); needs root";
  // 120 robots, a metrics row every tick for 300 s: far more than 48 KiB.
  const fs::path out = root / "disk" / "run";
  const auto [status, output] =
      RunColony({"run", kDiffusion, "--quiet", "--set", "framework.experiment.length=300", "--set",
                 "output.metrics_every=1", "--out", out.string()},
                root / "log");
  EXPECT_EQ(status, 1) << output;
  EXPECT_NE(output.find("cannot write '" + (out / "metrics.csv").string() + "'"), std::string::npos)
      << output;
  EXPECT_NE(output.find("No space left on device"), std::string::npos) << output;
  EXPECT_EQ(output.find("results in"), std::string::npos) << output;
  // What is there is whole rows; nothing says the run finished.
  EXPECT_FALSE(ExpectWholeRows(out / "metrics.csv").empty());
  if (fs::exists(out / "summary.json")) {
    EXPECT_NE(colony::SummaryProblem(ReadFile(out / "summary.json")), "");
  }
}

TEST(Reliability, AlreadyFullDiskFailsAtTheStart) {
  const fs::path root = TempDir("full_start");
  TinyDisk disk(root / "disk", "16k");
  if (!disk.mounted())
    GTEST_SKIP() << "cannot mount a tmpfs here (" << disk.why() << "); needs root";
  {
    std::ofstream fill(root / "disk" / "fill");
    const std::string block(4096, 'x');
    for (int i = 0; i < 16 && fill; ++i) fill << block << std::flush;
  }
  const fs::path out = root / "disk" / "run";
  const auto [status, output] = RunColony({"run", kDiffusion, "--quiet", "--set",
                                           "framework.experiment.length=1", "--out", out.string()},
                                          root / "log");
  EXPECT_EQ(status, 1) << output;
  EXPECT_NE(output.find("No space left on device"), std::string::npos) << output;
  EXPECT_FALSE(fs::exists(out / "summary.json"));
}

TEST(Reliability, KillMinus9LeavesWholeRowsAndNoSummary) {
  const fs::path dir = TempDir("kill9"), out = dir / "run";
  // The slow controller takes about a millisecond a tick: 100,000 ticks.
  const fs::path exp = MisbehaveExperiment(dir, "slow", 1, 10000);
  const Process p = Start({"run", exp.string(), "--quiet", "--out", out.string()}, dir / "log");
  ASSERT_GT(p.pid, 0);
  // Rows are written out at least every second.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (Lines(ReadFile(out / "metrics.csv")).size() < 10 &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  Signal(p, SIGKILL);
  const int status = Wait(p);
  ASSERT_TRUE(WIFSIGNALED(status));
  const auto metrics = ExpectWholeRows(out / "metrics.csv");
  const auto hashes = ExpectWholeRows(out / "hashes.csv");
  EXPECT_GE(metrics.size(), 9u);
  EXPECT_GE(hashes.size(), 9u);
  EXPECT_FALSE(fs::exists(out / "summary.json"));
}

TEST(Reliability, SummaryProblemRejectsWhatIsNotAFinishedRun) {
  colony::RunSummary s;
  s.ticks = 30;
  s.metrics = {{"robots", 1}};
  const std::string good = s.ToJson();
  EXPECT_EQ(colony::SummaryProblem(good), "");
  EXPECT_NE(colony::SummaryProblem(""), "");
  EXPECT_NE(colony::SummaryProblem(good.substr(0, good.size() / 2)).find("not valid JSON"),
            std::string::npos);
  std::string no_ticks = good;
  no_ticks.replace(no_ticks.find("\"ticks\""), 7, "\"tocks\"");
  EXPECT_NE(colony::SummaryProblem(no_ticks).find("\"ticks\""), std::string::npos);
  s.completed = false;
  s.stop_reason = "interrupted by SIGINT after tick 3";
  EXPECT_NE(colony::SummaryProblem(s.ToJson()).find("did not complete (interrupted by SIGINT"),
            std::string::npos);
}

TEST(Reliability, InterruptWritesWhatWasDoneAndSaysSo) {
  const fs::path dir = TempDir("sigint"), out = dir / "run", frames = dir / "frames";
#ifdef COLONY_TEST_FRAMES
  // Off-screen frames every tick, two cameras.
  const std::string exp = COLONY_SOURCE_DIR "/experiments/rendering.xml";
  const size_t wanted_frames = 6;
#else
  const std::string exp = MisbehaveExperiment(dir, "slow", 1, 10000).string();
  const size_t wanted_frames = 0;
  fs::create_directories(frames);
#endif
  std::vector<std::string> args = {
      "run", exp, "--quiet", "--set", "framework.experiment.length=1000", "--out", out.string()};
  if (wanted_frames) args.insert(args.end(), {"--frames", frames.string()});
  const Process p = Start(args, dir / "log");
  ASSERT_GT(p.pid, 0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  auto frame_count = [&] {
    std::error_code ec;
    size_t n = 0;
    for (const auto& e : fs::directory_iterator(frames, ec)) n += e.path().extension() == ".png";
    return n;
  };
  auto row_count = [&] { return Lines(ReadFile(out / "metrics.csv")).size(); };
  while ((frame_count() < wanted_frames || row_count() < 3) &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  Signal(p, SIGINT);
  const int status = Wait(p);
  ASSERT_TRUE(WIFEXITED(status)) << ReadFile(p.log);
  EXPECT_EQ(WEXITSTATUS(status), 130) << ReadFile(p.log);
  EXPECT_NE(ReadFile(p.log).find("interrupted by SIGINT"), std::string::npos) << ReadFile(p.log);
  // The summary says it stopped early, and where.
  const std::string summary = ReadFile(out / "summary.json");
  EXPECT_NE(summary.find("\"completed\": false"), std::string::npos) << summary;
  EXPECT_NE(summary.find("interrupted by SIGINT"), std::string::npos) << summary;
  EXPECT_NE(colony::SummaryProblem(summary), "");
  const size_t k = summary.find("\"ticks\": ");
  ASSERT_NE(k, std::string::npos);
  const uint64_t ticks = std::stoull(summary.substr(k + 9));
  EXPECT_GT(ticks, 0u);
  EXPECT_LT(ticks, 10000u);
  // Metrics up to the last tick.
  const auto rows = ExpectWholeRows(out / "metrics.csv");
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(TickOf(rows.back()), ticks);
  // Every frame is a whole PNG: its signature first, its IEND chunk last.
  size_t pngs = 0;
  for (const auto& e : fs::directory_iterator(frames)) {
    EXPECT_EQ(e.path().extension(), ".png") << e.path() << " left behind";
    const std::string bytes = ReadFile(e.path());
    ASSERT_GT(bytes.size(), 20u) << e.path();
    EXPECT_EQ(bytes.substr(1, 3), "PNG") << e.path();
    EXPECT_EQ(bytes.substr(bytes.size() - 8, 4), "IEND") << e.path();
    ++pngs;
  }
  EXPECT_GE(pngs, wanted_frames);
}

TEST(Reliability, ControllerSegfaultIsReportedWithRobotControllerAndTick) {
  const fs::path dir = TempDir("segfault"), out = dir / "run";
  const fs::path exp = MisbehaveExperiment(dir, "segfault", 50, 100);
  const auto [status, output] =
      RunColony({"run", exp.string(), "--quiet", "--out", out.string()}, dir / "log");
  EXPECT_EQ(status, 128 + SIGSEGV) << output;
  EXPECT_NE(
      output.find(
          "crashed with SIGSEGV (segmentation fault) in controller 'sweep_misbehave' of robot 'r' "
          "at tick 50"),
      std::string::npos)
      << output;
  EXPECT_NE(output.find("libsweep_misbehave.so"), std::string::npos) << output;
  // The metrics of ticks 0 to 49 are on disk.
  const auto rows = ExpectWholeRows(out / "metrics.csv");
  ASSERT_EQ(rows.size(), 50u);
  EXPECT_EQ(TickOf(rows.back()), 49u);
  EXPECT_FALSE(fs::exists(out / "summary.json"));
}

TEST(Reliability, ControllerAbortIsReported) {
  const fs::path dir = TempDir("abort"), out = dir / "run";
  const auto [status, output] = RunColony(
      {"run", MisbehaveExperiment(dir, "crash", 5, 10).string(), "--quiet", "--out", out.string()},
      dir / "log");
  EXPECT_EQ(status, 128 + SIGABRT) << output;
  EXPECT_NE(
      output.find(
          "crashed with SIGABRT (aborted) in controller 'sweep_misbehave' of robot 'r' at tick 5"),
      std::string::npos)
      << output;
}

TEST(Reliability, ControllerThrowingANonStandardExceptionIsReported) {
  const fs::path dir = TempDir("throw_int"), out = dir / "run";
  const auto [status, output] =
      RunColony({"run", MisbehaveExperiment(dir, "throw_int", 7, 10).string(), "--quiet", "--out",
                 out.string()},
                dir / "log");
  EXPECT_EQ(status, 1) << output;
  EXPECT_NE(
      output.find(
          "controller 'sweep_misbehave' of robot 'r' failed at tick 7: it threw something that is "
          "not a std::exception"),
      std::string::npos)
      << output;
  // Known metrics are kept and the summary says the run did not complete.
  EXPECT_EQ(TickOf(ExpectWholeRows(out / "metrics.csv").back()), 6u);
  EXPECT_NE(colony::SummaryProblem(ReadFile(out / "summary.json")).find("did not complete"),
            std::string::npos);
}

TEST(Reliability, OutputFoldersInUseAreRefusedUnlessOverwrite) {
  const fs::path dir = TempDir("reuse"), out = dir / "run", frames = dir / "frames";
  const std::vector<std::string> base = {"run", kDiffusion, "--quiet", "--set",
                                         "framework.experiment.length=1"};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = base;
    args.insert(args.end(), extra.begin(), extra.end());
    return RunColony(args, dir / "log");
  };
  ASSERT_EQ(with({"--set", "output.hash_every=1", "--out", out.string()}).first, 0);
  ASSERT_TRUE(fs::exists(out / "hashes.csv"));
  const auto refused = with({"--out", out.string()});
  EXPECT_EQ(refused.first, 2) << refused.second;
  EXPECT_NE(refused.second.find("--out '" + out.string() +
                                "' is not empty (it holds experiment.xml, hashes.csv"),
            std::string::npos)
      << refused.second;
  EXPECT_NE(refused.second.find("--overwrite"), std::string::npos);
  // --overwrite: the old run's files go, a file of the user's stays.
  std::ofstream(out / "notes.txt") << "mine\n";
  ASSERT_EQ(with({"--out", out.string(), "--overwrite"}).first, 0);
  EXPECT_FALSE(fs::exists(out / "hashes.csv"));
  EXPECT_TRUE(fs::exists(out / "summary.json"));
  EXPECT_TRUE(fs::exists(out / "notes.txt"));
  // --frames likewise.
  fs::create_directories(frames);
  std::ofstream(frames / "old_000001.png") << "old";
  const auto frames_refused = with({"--out", (dir / "run2").string(), "--frames", frames.string()});
  EXPECT_EQ(frames_refused.first, 2) << frames_refused.second;
  EXPECT_NE(frames_refused.second.find("--frames '" + frames.string() + "' is not empty"),
            std::string::npos)
      << frames_refused.second;
}

}  // namespace
