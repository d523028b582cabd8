// colony sweep as a user runs it: the grid, resuming after an interruption,
// crashing and hanging runs, MPI ranks, array-job shards, summaries, runs
// made with a rebuilt plugin, extended grids, time series over seeds, and
// bad command lines. Every sweep spawns the real program.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "tests/test_util.h"

extern char** environ;

namespace {

namespace fs = std::filesystem;

const std::string kDiffusion = COLONY_SOURCE_DIR "/experiments/diffusion.xml";

using Result = colony::testing::CommandResult;

// Runs a shell command, collecting its standard output and error.
Result Shell(const std::string& command) { return colony::testing::RunCommand(command); }

// Runs the colony program, after `launcher` (e.g. "mpirun -np 2") if given.
Result Colony(const std::string& args, const std::string& launcher = "") {
  return Shell(launcher + COLONY_EXE + " " + args);
}

// Starts `colony sweep ...` in the background (output discarded).
pid_t StartSweep(const std::vector<std::string>& args) {
  std::vector<std::string> all{COLONY_EXE, "sweep"};
  all.insert(all.end(), args.begin(), args.end());
  const pid_t pid = colony::testing::SpawnWithOutput(all, "/dev/null");
  EXPECT_GT(pid, 0);
  return pid;
}

std::string Join(const std::vector<std::string>& args) {
  std::string s;
  for (const auto& a : args) s += " '" + a + "'";
  return s;
}

using colony::testing::ReadFile;

fs::path TempDir(const std::string& name) {
  return colony::testing::FreshTempDir("colony_sweep_test", name);
}

// results.csv as rows of column -> value.
using Table = std::vector<std::map<std::string, std::string>>;

// One line of CSV (RFC 4180, no line breaks inside fields).
std::vector<std::string> SplitCsv(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
      fields.back() += '"';
      ++i;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

// A CSV file as Python's csv module reads it: rows of fields (JSON).
nlohmann::json PythonCsv(const fs::path& file) {
  const Result r = Shell(
      "/usr/bin/python3 -c \"import csv, json, sys; print(json.dumps(list(csv.reader(open("
      "sys.argv[1], newline='', encoding='utf-8')))))\" " +
      file.string());
  EXPECT_EQ(r.status, 0) << r.output;
  return nlohmann::json::parse(r.output, nullptr, false);
}

Table ReadTable(const fs::path& csv) {
  std::istringstream in(ReadFile(csv));
  std::string line;
  std::getline(in, line);
  const auto header = SplitCsv(line);
  Table table;
  while (std::getline(in, line)) {
    const auto fields = SplitCsv(line);
    EXPECT_EQ(fields.size(), header.size()) << line;
    auto& row = table.emplace_back();
    for (size_t i = 0; i < header.size() && i < fields.size(); ++i) row[header[i]] = fields[i];
  }
  return table;
}

size_t CountRowFiles(const fs::path& dir) {
  size_t n = 0;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir / "runs", ec)) {
    n += fs::exists(e.path() / "row.csv");
  }
  return n;
}

// A one-robot experiment with the test controller sweep_misbehave, whose
// params.mode a sweep varies; each run appends a line to `count_file`.
// `library`: the controller's plugin (default: the one the build made).
fs::path MisbehaveExperiment(const fs::path& dir, const fs::path& count_file,
                             const fs::path& library = COLONY_BINARY_DIR
                             "/tests/plugins/libsweep_misbehave.so") {
  fs::create_directories(dir);
  const fs::path file = dir / "misbehave.xml";
  std::ofstream(file)
      << "<colony><framework><experiment length=\"1\" ticks_per_second=\"10\" random_seed=\"1\"/>"
         "</framework><controllers><sweep_misbehave id=\"m\" library=\""
      << library.string() << "\"><params mode=\"none\" count_file=\"" << count_file.string()
      << "\"/></sweep_misbehave></controllers>"
         "<arena size=\"2,2,1\" center=\"0,0,0.5\"><marxbot id=\"r\"><body position=\"0,0,0\"/>"
         "<controller config=\"m\"/></marxbot></arena>"
         "<physics_engines><kinematics2d id=\"k2d\"/></physics_engines></colony>";
  return file;
}

size_t Lines(const fs::path& file) {
  std::istringstream in(ReadFile(file));
  size_t n = 0;
  for (std::string line; std::getline(in, line);) ++n;
  return n;
}

bool OnPath(const std::string& program) {
  return std::system(("command -v " + program + " >/dev/null 2>&1").c_str()) == 0;
}

TEST(Sweep, TwoParametersTimesThreeSeedsMakeSixRunsAndRows) {
  const fs::path out = TempDir("grid");
  const Result r =
      Colony("sweep " + kDiffusion +
             " --param arena.distribute.entity.quantity=10,20 --param framework.experiment.length=1"
             " --seeds 1..3 --jobs 2 --out " +
             out.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("6 runs: 6 ok, 0 failed, 0 timeout"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("elapsed"), std::string::npos)
      << "no progress line when not on a terminal\n"
      << r.output;
  const Table table = ReadTable(out / "results.csv");
  ASSERT_EQ(table.size(), 6u);
  const char* quantities[] = {"10", "10", "10", "20", "20", "20"};
  for (size_t i = 0; i < 6; ++i) {
    const auto& row = table[i];
    EXPECT_EQ(row.at("arena.distribute.entity.quantity"), quantities[i]);
    EXPECT_EQ(row.at("framework.experiment.length"), "1");
    EXPECT_EQ(row.at("seed"), std::to_string(i % 3 + 1));
    EXPECT_EQ(row.at("status"), "ok");
    EXPECT_EQ(row.at("ticks"), "10");
    EXPECT_EQ(row.at("robots"), quantities[i]);
    EXPECT_EQ(row.at("metrics.robots"), quantities[i]);
    EXPECT_GT(std::stod(row.at("mean_displacement")), 0);
    EXPECT_GT(std::stod(row.at("wall_seconds")), 0);
    // The run's own folder holds its output contract.
    const fs::path run = out / "runs" / row.at("run");
    for (const char* f : {"experiment.xml", "metrics.csv", "summary.json"}) {
      EXPECT_TRUE(fs::exists(run / f)) << run / f;
    }
    EXPECT_NE(ReadFile(run / "summary.json").find("\"seed\": " + row.at("seed")),
              std::string::npos);
  }
  // Seeds differ, so do the runs.
  EXPECT_NE(table[0].at("final_state_hash"), table[1].at("final_state_hash"));
  // The same command again has nothing left to do.
  const Result again =
      Colony("sweep " + kDiffusion +
             " --param arena.distribute.entity.quantity=10,20 --param framework.experiment.length=1"
             " --seeds 1..3 --jobs 2 --out " +
             out.string());
  EXPECT_EQ(again.status, 0) << again.output;
  EXPECT_NE(again.output.find("(0 of them run now)"), std::string::npos) << again.output;
  fs::remove_all(out);
}

TEST(Sweep, InterruptedSweepResumesWithoutRerunningFinishedRuns) {
  const fs::path out = TempDir("resume");
  const std::vector<std::string> args{kDiffusion, "--param", "framework.experiment.length=100",
                                      "--seeds",  "1..8",    "--jobs",
                                      "1",        "--out",   out.string()};
  // Interrupt with SIGINT after two runs, then kill with SIGKILL after four.
  std::map<std::string, fs::file_time_type> finished;
  for (auto [sig, after] : {std::pair{SIGINT, 2}, std::pair{SIGKILL, 4}}) {
    const pid_t pid = StartSweep(args);
    for (int i = 0; i < 600 && CountRowFiles(out) < static_cast<size_t>(after); ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    kill(pid, sig);
    int status = 0;
    waitpid(pid, &status, 0);
    if (sig == SIGINT) {
      EXPECT_EQ(WEXITSTATUS(status), 128 + SIGINT);
    }
    std::this_thread::sleep_for(
        std::chrono::milliseconds(100));  // any orphaned run would go on writing
    ASSERT_LT(CountRowFiles(out), 8u)
        << "the sweep ended before it was interrupted; make the runs longer";
  }
  for (const auto& e : fs::directory_iterator(out / "runs")) {
    if (fs::exists(e.path() / "row.csv")) {
      finished[e.path().filename()] = fs::last_write_time(e.path() / "summary.json");
    }
  }
  ASSERT_GE(finished.size(), 4u);
  const Result r = Colony("sweep" + Join(args));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("8 runs: 8 ok"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("(" + std::to_string(8 - finished.size()) + " of them run now)"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(ReadTable(out / "results.csv").size(), 8u);
  for (const auto& [run, time] : finished) {
    EXPECT_EQ(fs::last_write_time(out / "runs" / run / "summary.json"), time)
        << "run " << run << " ran again";
  }
  fs::remove_all(out);
}

TEST(Sweep, CrashedRunIsRecordedAsFailedOthersSucceed) {
  const fs::path out = TempDir("crash"), tmp = TempDir("crash_exp");
  const fs::path exp = MisbehaveExperiment(tmp, tmp / "count");
  const Result r = Colony("sweep " + exp.string() +
                          " --param controllers.sweep_misbehave[m].params.mode=none,crash"
                          " --seeds 1,2 --out " +
                          out.string());
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("4 runs: 2 ok, 2 failed, 0 timeout"), std::string::npos) << r.output;
  const Table table = ReadTable(out / "results.csv");
  ASSERT_EQ(table.size(), 4u);
  for (const auto& row : table) {
    const bool crash = row.at("controllers.sweep_misbehave[m].params.mode") == "crash";
    EXPECT_EQ(row.at("status"), crash ? "failed" : "ok");
    if (crash) {
      EXPECT_NE(row.at("detail").find("killed by signal 6"), std::string::npos) << row.at("detail");
    }
    EXPECT_EQ(fs::exists(out / "runs" / row.at("run") / "summary.json"), !crash);
  }
  // --retry-failed runs the failed ones again, and only them.
  const Result retry = Colony("sweep " + exp.string() +
                              " --param controllers.sweep_misbehave[m].params.mode=none,crash"
                              " --seeds 1,2 --retry-failed --out " +
                              out.string());
  EXPECT_EQ(retry.status, 1);
  EXPECT_NE(retry.output.find("(2 of them run now)"), std::string::npos) << retry.output;
  EXPECT_EQ(Lines(tmp / "count"), 6u);
  fs::remove_all(out);
  fs::remove_all(tmp);
}

TEST(Sweep, HangingRunIsKilledAtItsTimeout) {
  const fs::path out = TempDir("hang"), tmp = TempDir("hang_exp");
  const fs::path exp = MisbehaveExperiment(tmp, tmp / "count");
  const auto t0 = std::chrono::steady_clock::now();
  const Result r = Colony("sweep " + exp.string() +
                          " --param controllers.sweep_misbehave[m].params.mode=none,hang"
                          " --timeout 1 --out " +
                          out.string());
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_LT(seconds, 10);
  const Table table = ReadTable(out / "results.csv");
  ASSERT_EQ(table.size(), 2u);
  EXPECT_EQ(table[0].at("status"), "ok");
  EXPECT_EQ(table[1].at("status"), "timeout");
  EXPECT_NE(table[1].at("detail").find("timeout of 1 s"), std::string::npos);
  EXPECT_GE(std::stod(table[1].at("wall_seconds")), 1.0);
  EXPECT_LT(std::stod(table[1].at("wall_seconds")), 5.0);
  fs::remove_all(out);
  fs::remove_all(tmp);
}

// A run that did not complete still tells how far it got: the last complete
// row of its metrics.csv.
TEST(Sweep, TimedOutRunKeepsItsLastMetrics) {
  const fs::path out = TempDir("partial");
  const Result r =
      Colony("sweep " + kDiffusion +
             " --param framework.experiment.length=100000 --param output.metrics_every=1"
             " --timeout 0.5 --quiet --out " +
             out.string());
  EXPECT_EQ(r.status, 1) << r.output;
  const Table table = ReadTable(out / "results.csv");
  ASSERT_EQ(table.size(), 1u);
  EXPECT_EQ(table[0].at("status"), "timeout");
  EXPECT_GT(std::stoll(table[0].at("ticks")), 0);
  EXPECT_FALSE(table[0].at("mean_displacement").empty());
  EXPECT_EQ(table[0].at("final_state_hash"), "");
  fs::remove_all(out);
}

TEST(Sweep, MpiRanksRunEveryRunExactlyOnce) {
  if (!OnPath("mpirun")) GTEST_SKIP() << "mpirun is not installed";
  const fs::path out = TempDir("mpi"), tmp = TempDir("mpi_exp");
  const fs::path exp = MisbehaveExperiment(tmp, tmp / "count");
  const Result r = Colony("sweep " + exp.string() + " --seeds 1..6 --jobs 1 --out " + out.string(),
                          "mpirun -np 2 --oversubscribe --allow-run-as-root ");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("6 runs: 6 ok"), std::string::npos) << r.output;
  EXPECT_EQ(Lines(tmp / "count"), 6u) << "each run ran exactly once";
  const Table table = ReadTable(out / "results.csv");
  ASSERT_EQ(table.size(), 6u);
  for (size_t i = 0; i < 6; ++i) EXPECT_EQ(table[i].at("seed"), std::to_string(i + 1));
  fs::remove_all(out);
  fs::remove_all(tmp);
}

TEST(Sweep, CollectedShardsGiveTheUnshardedTable) {
  const fs::path whole = TempDir("whole"), shared = TempDir("shared"), one = TempDir("one"),
                 two = TempDir("two"), merged = TempDir("merged");
  const std::string grid =
      " --param arena.distribute.entity.quantity=10,20 --param framework.experiment.length=1"
      " --seeds 1..3 --quiet --out ";
  ASSERT_EQ(Colony("sweep " + kDiffusion + grid + whole.string()).status, 0);
  // Shards in one shared folder, merged there.
  ASSERT_EQ(Colony("sweep " + kDiffusion + grid + shared.string() + " --shard 1/2").status, 0);
  const Result early = Colony("sweep --collect " + shared.string());
  EXPECT_EQ(early.status, 1);
  EXPECT_NE(early.output.find("3 runs have not finished"), std::string::npos) << early.output;
  ASSERT_EQ(Colony("sweep " + kDiffusion + grid + shared.string() + " --shard 2/2").status, 0);
  const Result collect = Colony("sweep --collect " + shared.string());
  ASSERT_EQ(collect.status, 0) << collect.output;
  EXPECT_NE(collect.output.find("collected 6 of 6 runs"), std::string::npos) << collect.output;
  // Shards in folders of their own, merged into a third.
  ASSERT_EQ(Colony("sweep " + kDiffusion + grid + one.string() + " --shard 1/2").status, 0);
  ASSERT_EQ(Colony("sweep " + kDiffusion + grid + two.string() + " --shard 2/2").status, 0);
  ASSERT_EQ(
      Colony("sweep --collect " + one.string() + " " + two.string() + " --out " + merged.string())
          .status,
      0);
  // The same table, timings aside.
  auto untimed = [](Table t) {
    for (auto& row : t) {
      for (const char* c : {"wall_seconds", "step_seconds", "robot_steps_per_second"}) row.erase(c);
    }
    return t;
  };
  const Table expected = untimed(ReadTable(whole / "results.csv"));
  ASSERT_EQ(expected.size(), 6u);
  EXPECT_EQ(untimed(ReadTable(shared / "results.csv")), expected);
  EXPECT_EQ(untimed(ReadTable(merged / "results.csv")), expected);
  EXPECT_EQ(ReadFile(whole / "results.csv").substr(0, 200),
            ReadFile(merged / "results.csv").substr(0, 200));
  for (const auto& d : {whole, shared, one, two, merged}) fs::remove_all(d);
}

TEST(Sweep, ScalabilitySweepFileRunsAndSummarizes) {
  const fs::path out = TempDir("scalability");
  const Result r =
      Colony("sweep " COLONY_SOURCE_DIR "/experiments/sweeps/diffusion-scalability.xml --out " +
             out.string());
  ASSERT_EQ(r.status, 0) << r.output;
  const Table table = ReadTable(out / "results.csv");
  ASSERT_EQ(table.size(), 12u);
  const Result s = Colony("sweep --summarize " + out.string());
  ASSERT_EQ(s.status, 0) << s.output;
  EXPECT_NE(s.output.find("arena.distribute.entity.quantity=200"), std::string::npos) << s.output;
  EXPECT_NE(s.output.find("mean_displacement"), std::string::npos) << s.output;
  // summary.csv: the robots metric over 3 seeds of each swarm size.
  const Table summary = ReadTable(out / "summary.csv");
  size_t found = 0;
  for (const auto& row : summary) {
    if (row.at("metric") != "robots") continue;
    ++found;
    EXPECT_EQ(row.at("count"), "3");
    EXPECT_EQ(row.at("mean"), row.at("arena.distribute.entity.quantity"));
    EXPECT_EQ(row.at("median"), row.at("arena.distribute.entity.quantity"));
    EXPECT_EQ(row.at("std_dev"), "0");
  }
  EXPECT_EQ(found, 4u);
  // A plot with gnuplot, or a clear word that it is missing.
  const Result plot =
      Colony("sweep --summarize " + out.string() +
             " --plot robot_steps_per_second:arena.distribute.entity.quantity --quiet");
  if (OnPath("gnuplot")) {
    EXPECT_EQ(plot.status, 0) << plot.output;
    EXPECT_TRUE(
        fs::exists(out / "plot-robot_steps_per_second-arena.distribute.entity.quantity.png"));
  } else {
    EXPECT_EQ(plot.status, 1);
    EXPECT_NE(plot.output.find("gnuplot, which is not installed"), std::string::npos)
        << plot.output;
  }
  fs::remove_all(out);
}

TEST(Sweep, ProgressOnATerminal) {
  if (!OnPath("script")) GTEST_SKIP() << "script (util-linux) is not installed";
  const fs::path out = TempDir("progress");
  const std::string command = std::string(COLONY_EXE) + " sweep " + kDiffusion +
                              " --param framework.experiment.length=1 --seeds 1..2 --out " +
                              out.string();
  const Result r = Shell("script -qec \"" + command + "\" /dev/null");
  EXPECT_NE(r.output.find("2/2 done (0 failed, 0 timeout), 0 running"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("elapsed"), std::string::npos) << r.output;
  fs::remove_all(out);
}

TEST(Sweep, AnotherSweepInTheSameFolderIsRefused) {
  const fs::path out = TempDir("other");
  const std::string base = "sweep " + kDiffusion +
                           " --param framework.experiment.length=1 --seeds 1 --quiet --out " +
                           out.string();
  ASSERT_EQ(Colony(base).status, 0);
  const Result r = Colony(base + " --param arena.distribute.entity.quantity=5");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("holds another sweep (it sweeps framework.experiment.length, not "
                          "framework.experiment.length, arena.distribute.entity.quantity); "
                          "choose another --out"),
            std::string::npos)
      << r.output;
  fs::remove_all(out);
}

// Runs of the misbehave experiment: how many lines its count file has.
size_t RunsMade(const fs::path& tmp) {
  return fs::exists(tmp / "count") ? Lines(tmp / "count") : 0;
}

TEST(Sweep, MoreSeedsAndValuesRunOnlyTheNewRuns) {
  const fs::path out = TempDir("extend"), tmp = TempDir("extend_exp");
  const fs::path exp = MisbehaveExperiment(tmp, tmp / "count");
  const std::string base = "sweep " + exp.string() + " --out " + out.string();
  ASSERT_EQ(Colony(base + " --seeds 1..2").status, 0);
  EXPECT_EQ(RunsMade(tmp), 2u);
  std::map<std::string, fs::file_time_type> first;
  for (const auto& row : ReadTable(out / "results.csv")) {
    first[row.at("run")] = fs::last_write_time(out / "runs" / row.at("run") / "summary.json");
  }
  ASSERT_EQ(first.size(), 2u);
  // Seeds 1..2 -> 1..4: two new runs, the first two kept.
  const Result more = Colony(base + " --seeds 1..4");
  ASSERT_EQ(more.status, 0) << more.output;
  EXPECT_NE(more.output.find("seeds 1..2 -> 1..4 (2 runs of the sweep reused)"), std::string::npos)
      << more.output;
  EXPECT_NE(more.output.find("4 runs: 4 ok, 0 failed, 0 timeout (2 of them run now)"),
            std::string::npos)
      << more.output;
  EXPECT_EQ(RunsMade(tmp), 4u);
  for (const auto& [run, time] : first) {
    EXPECT_EQ(fs::last_write_time(out / "runs" / run / "summary.json"), time)
        << "run " << run << " ran again";
  }
  Table table = ReadTable(out / "results.csv");
  ASSERT_EQ(table.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(table[i].at("seed"), std::to_string(i + 1));
    EXPECT_EQ(table[i].at("run"), "seed=" + std::to_string(i + 1));
  }
  // A parameter's values, two of them: the four runs at the old value stay.
  const std::string at = " --param controllers.sweep_misbehave[m].params.at=";
  ASSERT_EQ(Colony(base + " --seeds 1..4" + at + "1").status, 2)
      << "a new parameter is another sweep";
  fs::remove_all(out);
  ASSERT_EQ(Colony(base + " --seeds 1..2" + at + "1").status, 0);
  const Result values = Colony(base + " --seeds 1..4" + at + "1,2");
  ASSERT_EQ(values.status, 0) << values.output;
  EXPECT_NE(values.output.find("8 runs: 8 ok, 0 failed, 0 timeout (6 of them run now)"),
            std::string::npos)
      << values.output;
  table = ReadTable(out / "results.csv");
  ASSERT_EQ(table.size(), 8u);
  EXPECT_EQ(table[0].at("run"), "at=1_seed=1");
  EXPECT_EQ(table[7].at("run"), "at=2_seed=4");
  // Fewer seeds again: nothing to run, the table holds the grid's runs.
  const Result fewer = Colony(base + " --seeds 1" + at + "1,2");
  ASSERT_EQ(fewer.status, 0) << fewer.output;
  EXPECT_NE(fewer.output.find("2 runs: 2 ok, 0 failed, 0 timeout (0 of them run now)"),
            std::string::npos)
      << fewer.output;
  EXPECT_EQ(ReadTable(out / "results.csv").size(), 2u);
  EXPECT_EQ(RunsMade(tmp), 4u + 2u + 6u);
  fs::remove_all(out);
  fs::remove_all(tmp);
}

// A plugin the experiment loads by library= path, rebuilt between two runs
// of the same sweep command (simulated: bytes appended to a copy of it,
// which still loads): the resumed sweep refuses, naming it, until told what
// to do with the runs made with the old one.
TEST(Sweep, RebuiltPluginMakesAResumedSweepRefuseUntilToldWhatToDo) {
  const fs::path out = TempDir("stale"), tmp = TempDir("stale_exp");
  const fs::path library = tmp / "lib" / "libsweep_misbehave.so";
  fs::create_directories(library.parent_path());
  fs::copy_file(COLONY_BINARY_DIR "/tests/plugins/libsweep_misbehave.so", library);
  const fs::path exp = MisbehaveExperiment(tmp, tmp / "count", library);
  const std::string command = "sweep " + exp.string() + " --seeds 1..2 --out " + out.string();
  ASSERT_EQ(Colony(command).status, 0);
  EXPECT_NE(ReadFile(out / "sweep.xml").find(library.string()), std::string::npos)
      << "the manifest records the plugin";
  // Unchanged: nothing to do.
  EXPECT_NE(Colony(command).output.find("(0 of them run now)"), std::string::npos);

  std::ofstream(library, std::ios::app) << "rebuilt";
  const std::string results = ReadFile(out / "results.csv");
  const Result refused = Colony(command);
  EXPECT_EQ(refused.status, 2) << refused.output;
  EXPECT_NE(refused.output.find("the code has changed since its runs were made:\n  " +
                                library.string() + " has changed (SHA-256 "),
            std::string::npos)
      << refused.output;
  EXPECT_NE(refused.output.find("2 runs were made with the old code: give --rerun-stale to run "
                                "them again, or --keep-stale to keep them"),
            std::string::npos)
      << refused.output;
  EXPECT_EQ(RunsMade(tmp), 2u);
  EXPECT_EQ(ReadFile(out / "results.csv"), results) << "a refused sweep changes nothing";

  // --keep-stale: kept, and marked.
  const Result kept = Colony(command + " --keep-stale");
  ASSERT_EQ(kept.status, 0) << kept.output;
  EXPECT_NE(kept.output.find("(0 of them run now)"), std::string::npos) << kept.output;
  EXPECT_EQ(RunsMade(tmp), 2u);
  for (const auto& row : ReadTable(out / "results.csv")) EXPECT_EQ(row.at("stale"), "true");
  // The manifest now records the new plugin: the same command goes on, and
  // says what it keeps.
  const Result again = Colony(command);
  EXPECT_EQ(again.status, 0) << again.output;
  EXPECT_NE(again.output.find("2 runs made with other code than now (stale=true in results.csv"),
            std::string::npos)
      << again.output;

  // --rerun-stale: run with the new plugin.
  const Result rerun = Colony(command + " --rerun-stale");
  ASSERT_EQ(rerun.status, 0) << rerun.output;
  EXPECT_NE(rerun.output.find("(2 of them run now)"), std::string::npos) << rerun.output;
  EXPECT_EQ(RunsMade(tmp), 4u);
  for (const auto& row : ReadTable(out / "results.csv")) EXPECT_EQ(row.at("stale"), "false");

  // Rebuilt again: --rerun-stale straight away reruns without asking.
  std::ofstream(library, std::ios::app) << "again";
  EXPECT_NE(Colony(command + " --rerun-stale").output.find("(2 of them run now)"),
            std::string::npos);
  EXPECT_EQ(RunsMade(tmp), 6u);
  EXPECT_EQ(Colony(command + " --rerun-stale --keep-stale").status, 2);
  fs::remove_all(out);
  fs::remove_all(tmp);
}

// The test loop functions sweep_metrics (tests/plugins/sweep_metrics.cpp):
// one metric named `name`, worth scale x tick + seed, for 3 ticks.
fs::path MetricsExperiment(const fs::path& dir, const std::string& name) {
  fs::create_directories(dir);
  const fs::path file = dir / "metrics.xml";
  std::ofstream(file)
      << "<colony><framework><experiment length=\"0.3\" ticks_per_second=\"10\" "
         "random_seed=\"1\"/></framework>"
         "<loop_functions library=\"" COLONY_BINARY_DIR
         "/tests/plugins/libsweep_metrics.so\" label=\"sweep_metrics\"><params name='"
      << name
      << "' scale=\"1\"/></loop_functions>"
         "<arena size=\"2,2,1\" center=\"0,0,0.5\"/>"
         "<physics_engines><kinematics2d id=\"k2d\"/></physics_engines></colony>";
  return file;
}

TEST(Sweep, MetricNamedWithCommaAndQuotesSurvivesEveryTable) {
  const fs::path out = TempDir("quoted"), tmp = TempDir("quoted_exp");
  const std::string name = "dist,to \"light\"";
  const fs::path exp = MetricsExperiment(tmp, "dist,to &quot;light&quot;");
  const Result r = Colony("sweep " + exp.string() + " --seeds 1..2 --quiet --out " + out.string());
  ASSERT_EQ(r.status, 0) << r.output;
  // results.csv as Python reads it: the column, and the final values 3 + seed.
  const auto rows = PythonCsv(out / "results.csv");
  ASSERT_EQ(rows.size(), 3u) << ReadFile(out / "results.csv");
  const auto& header = rows[0];
  const auto column = std::find(header.begin(), header.end(), name);
  ASSERT_NE(column, header.end()) << header;
  const size_t c = static_cast<size_t>(column - header.begin());
  EXPECT_EQ(rows[1][c], "4");
  EXPECT_EQ(rows[2][c], "5");
  // The summaries name it the same.
  ASSERT_EQ(Colony("sweep --summarize --quiet " + out.string()).status, 0);
  const auto summary = PythonCsv(out / "summary.csv");
  bool found = false;
  for (const auto& row : summary) {
    if (row[0] == name) {
      found = true;
      EXPECT_EQ(row[2], "4.5");  // mean
    }
  }
  EXPECT_TRUE(found) << summary;
  const auto series = PythonCsv(out / "summary_timeseries.csv");
  ASSERT_EQ(series.size(), 5u) << series;  // header, ticks 0 to 3
  EXPECT_EQ(series[1][0], name);
  fs::remove_all(out);
  fs::remove_all(tmp);
}

// Two runs of a sweep, at the same time, each writing a table through the
// run-folder API: each table lands in its own run folder with its own rows,
// and nothing is written to the directory the sweep was started from.
TEST(Sweep, RunsWritingTablesThroughTheRunFolderApiNeverTouchEachOthersFiles) {
  const fs::path out = TempDir("tables"), tmp = TempDir("tables_exp"), cwd = TempDir("tables_cwd");
  fs::create_directories(tmp);
  fs::create_directories(cwd);
  const fs::path exp = tmp / "tables.xml";
  std::ofstream(exp)
      << "<colony><framework><experiment length=\"0.3\" ticks_per_second=\"10\" "
         "random_seed=\"1\"/></framework><loop_functions library=\"" COLONY_BINARY_DIR
         "/tests/plugins/libsweep_metrics.so\" label=\"sweep_metrics\"><params "
         "table=\"tracks/ticks.csv\"/></loop_functions>"
         "<arena size=\"2,2,1\" center=\"0,0,0.5\"/>"
         "<physics_engines><kinematics2d id=\"k2d\"/></physics_engines></colony>";
  const Result r = Shell("cd " + cwd.string() + " && " + COLONY_EXE + " sweep " + exp.string() +
                         " --seeds 1..2 --jobs 2 --quiet --out " + out.string());
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* seed : {"1", "2"}) {
    const fs::path table = out / "runs" / (std::string("seed=") + seed) / "tracks" / "ticks.csv";
    const auto rows = PythonCsv(table);
    ASSERT_EQ(rows.size(), 5u) << ReadFile(table);  // header, ticks 0 to 3
    EXPECT_EQ(rows[0], nlohmann::json({"tick", "seed"}));
    for (size_t i = 1; i < rows.size(); ++i) {
      EXPECT_EQ(rows[i][0], std::to_string(i - 1));
      EXPECT_EQ(rows[i][1], seed) << table;
    }
  }
  EXPECT_TRUE(fs::is_empty(cwd)) << "something was written to the sweep's current directory";
  fs::remove_all(out);
  fs::remove_all(tmp);
  fs::remove_all(cwd);
}

TEST(Sweep, SummaryTimeseriesHoldsStatisticsOverSeedsPerTick) {
  const fs::path out = TempDir("series"), tmp = TempDir("series_exp");
  const fs::path exp = MetricsExperiment(tmp, "value");
  const Result r =
      Colony("sweep " + exp.string() +
             " --param loop_functions.params.scale=1,2 --seeds 1,2 --quiet --out " + out.string());
  ASSERT_EQ(r.status, 0) << r.output;
  const Result s = Colony("sweep --summarize " + out.string());
  ASSERT_EQ(s.status, 0) << s.output;
  EXPECT_NE(s.output.find("per tick in " + out.string() + "/summary_timeseries.csv"),
            std::string::npos)
      << s.output;
  const auto series = PythonCsv(out / "summary_timeseries.csv");
  ASSERT_TRUE(series.is_array());
  ASSERT_EQ(series.size(), 1u + 2 * 4) << series;  // 2 scales x ticks 0..3
  EXPECT_EQ(series[0], nlohmann::json({"loop_functions.params.scale", "metric", "tick", "time",
                                       "count", "mean", "std_dev", "min", "q10", "q25", "median",
                                       "q75", "q90", "max"}));
  // Scale 2 at tick 3, by hand from the two runs' metrics.csv (2 x 3 + seed).
  std::vector<double> values;
  for (const char* run : {"scale=2_seed=1", "scale=2_seed=2"}) {
    const auto metrics = PythonCsv(out / "runs" / run / "metrics.csv");
    ASSERT_EQ(metrics.size(), 5u) << metrics;
    ASSERT_EQ(metrics[4][0], "3");
    values.push_back(std::stod(metrics[4][2].get<std::string>()));
  }
  EXPECT_EQ(values, (std::vector<double>{7, 8}));
  const auto& row = series[8];
  ASSERT_EQ(row[0], "2");
  EXPECT_EQ(row[1], "value");
  EXPECT_EQ(row[2], "3");
  EXPECT_EQ(std::stod(row[3].get<std::string>()), 0.3);
  EXPECT_EQ(row[4], "2");
  const double mean = (values[0] + values[1]) / 2;
  EXPECT_EQ(std::stod(row[5].get<std::string>()), mean);
  EXPECT_DOUBLE_EQ(std::stod(row[6].get<std::string>()),
                   std::sqrt((std::pow(values[0] - mean, 2) + std::pow(values[1] - mean, 2)) / 1));
  const char* expected[] = {"7", "7.1", "7.25", "7.5", "7.75", "7.9", "8"};
  for (size_t i = 0; i < 7; ++i) EXPECT_EQ(row[7 + i], expected[i]) << series[0][7 + i];
  fs::remove_all(out);
  fs::remove_all(tmp);
}

TEST(Sweep, AnOlderSweepFolderIsReadButNotResumed) {
  const fs::path out = TempDir("older"), tmp = TempDir("older_exp");
  const fs::path exp = MetricsExperiment(tmp, "value");
  const std::string command = "sweep " + exp.string() + " --seeds 1 --quiet --out " + out.string();
  ASSERT_EQ(Colony(command).status, 0);
  // What colony sweep wrote before run folders were named by values: runs/0000
  // and a manifest without run_folders or <code>.
  fs::rename(out / "runs" / "seed=1", out / "runs" / "0000");
  for (const fs::path& table : {out / "results.csv", out / "runs" / "0000" / "row.csv"}) {
    std::string text = ReadFile(table);
    text.replace(text.find("\nseed=1,"), 8, "\n0000,");
    std::ofstream(table) << text;
  }
  std::string manifest = ReadFile(out / "sweep.xml");
  const std::string folders = " run_folders=\"by-values\"";
  manifest.erase(manifest.find(folders), folders.size());
  const size_t code = manifest.find("<!-- The code");
  manifest.erase(code, manifest.find("</code>") + 7 - code);
  std::ofstream(out / "sweep.xml") << manifest;
  const Result r = Colony(command);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("was made by an older colony sweep"), std::string::npos) << r.output;
  EXPECT_EQ(Colony("sweep --summarize --quiet " + out.string()).status, 0);
  const Result collect = Colony("sweep --collect " + out.string());
  EXPECT_EQ(collect.status, 0) << collect.output;
  EXPECT_NE(collect.output.find("collected 1 of 1 runs"), std::string::npos) << collect.output;
  fs::remove_all(out);
  fs::remove_all(tmp);
}

TEST(Sweep, CommandLineHasHelpSuggestionsAndShortErrors) {
  for (const std::string mode : {"", " --collect", " --summarize"}) {
    const Result help = Colony("sweep" + mode + " --help");
    EXPECT_EQ(help.status, 0) << mode << "\n" << help.output;
    EXPECT_NE(help.output.find("usage: colony sweep" + mode + " [OPTIONS]"), std::string::npos)
        << help.output;
  }
  EXPECT_NE(Colony("sweep --help").output.find("--rerun-stale"), std::string::npos);
  EXPECT_NE(Colony("sweep --summarize --help").output.find("summary_timeseries.csv"),
            std::string::npos);
  struct Case {
    std::string args, expected;
  } cases[] = {
      {kDiffusion + " --seed 3", "unknown option '--seed'; did you mean '--seeds'?"},
      {kDiffusion + " --retry-faild", "did you mean '--retry-failed'?"},
      {kDiffusion + " --sumarize", "did you mean '--summarize'?"},
      {kDiffusion + " --jobs", "--jobs needs a value"},
      {kDiffusion + " --rerun-stale --keep-stale", "excludes"},
      {"--collect /tmp --outt x", "unknown option '--outt'; did you mean '--out'?"},
      {"--summarize /tmp --plott a:b", "did you mean '--plot'?"},
  };
  for (const auto& c : cases) {
    const Result r = Colony("sweep " + c.args);
    EXPECT_EQ(r.status, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.args << "\n" << r.output;
    // Short: the message and where the usage is, not the usage.
    EXPECT_LE(std::count(r.output.begin(), r.output.end(), '\n'), 2) << r.output;
    EXPECT_NE(r.output.find("run 'colony sweep"), std::string::npos) << r.output;
  }
  // --opt=value.
  const fs::path out = TempDir("equals");
  const Result r =
      Colony("sweep " + kDiffusion +
             " --param=framework.experiment.length=1 --seeds=2 --quiet --out=" + out.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(ReadTable(out / "results.csv").at(0).at("seed"), "2");
  fs::remove_all(out);
}

TEST(Sweep, BadInputIsRejectedBeforeAnythingRuns) {
  const fs::path out = TempDir("bad");
  struct Case {
    std::string args, expected;
  } cases[] = {
      {"--param framework.experimnt.length=1,2", "did you mean 'experiment'"},
      {"--param framework.experiment.length=",
       "--param framework.experiment.length: empty value list"},
      {"--param framework.experiment.length=1,,2", "empty value in '1,,2'"},
      {"--param framework.experiment.length=1,1", "value '1' is given twice"},
      {"--param framework.experiment.length=1,-3", "attribute 'length': '-3' is out of range"},
      {"--param length", "expected PATH=V1,V2,..."},
      {"--seeds 5..1", "range '5..1' ends before it starts"},
      {"--seeds one", "--seeds 'one': 'one' is not accepted"},
      {"--seeds 1,1", "seed 1 is given twice"},
      {"--jobs 0", "--jobs: '0' is not accepted"},
      {"--shard 3/2", "expected I/N with 1 <= I <= N"},
      {"--shard 1", "expected I/N"},
      {"--timeout -1", "--timeout: '-1' is not accepted; expected seconds > 0"},
      {"--frobnicate", "unknown option '--frobnicate'"},
  };
  for (const auto& c : cases) {
    const Result r = Colony("sweep " + kDiffusion + " " + c.args + " --out " + out.string());
    EXPECT_EQ(r.status, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_FALSE(fs::exists(out)) << c.args << ": something was written";
  }
  EXPECT_EQ(Colony("sweep").status, 2);
  EXPECT_NE(Colony("sweep /no/such.xml").output.find("no such file"), std::string::npos);
  EXPECT_NE(Colony("sweep --summarize /no/such/dir").output.find("has no results.csv"),
            std::string::npos);
  EXPECT_NE(Colony("sweep --collect /no/such/dir").output.find("not a sweep folder"),
            std::string::npos);
}

}  // namespace
