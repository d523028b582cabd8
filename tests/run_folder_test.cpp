// The run folder as a user and a loop-functions author see it: tables
// written there by name (and nowhere without one), CSV quoting that Python's
// csv module reads back, metric names checked at load, metrics.csv from tick
// 0, and run folders that reproduce their run from any directory, with
// their provenance in summary.json.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>

#include "core/output.h"
#include "core/plugin_loader.h"
#include "core/run_files.h"
#include "core/table_writer.h"
#include "tests/test_util.h"

namespace colony {
namespace {

namespace fs = std::filesystem;
using testing::ReadFile;

fs::path TempDir(const std::string& name) {
  return testing::FreshTempDir("colony_run_folder_test", name);
}

// Python's csv module's reading of `file`, as JSON rows of fields.
nlohmann::json PythonCsv(const fs::path& file) {
  const auto r = testing::RunCommand(
      "/usr/bin/python3 -c \"import csv, json, sys; print(json.dumps(list(csv.reader(open("
      "sys.argv[1], newline='', encoding='utf-8')))))\" " +
      file.string());
  EXPECT_EQ(r.status, 0) << r.output;
  return nlohmann::json::parse(r.output, nullptr, false);
}

TEST(RunFolder, CsvQuotingRoundTripsThroughPython) {
  const fs::path dir = TempDir("quoting");
  const std::vector<std::string> texts = {
      "plain", "a,b", "say \"hi\"", "two\nlines", "cr\rlf\r\n", "", " spaced ", "\"", "été ✓"};
  const std::vector<double> numbers = {0.1 + 0.2, -1e-300, 12345678.9, 1.0 / 3, 0};
  {
    Table table =
        Table::Create((dir / "q.csv").string(), {{"name, with \"comma\"", ColumnType::kText},
                                                 {"value", ColumnType::kNumber},
                                                 {"n", ColumnType::kInteger}});
    for (size_t i = 0; i < texts.size(); ++i) {
      table.Text(texts[i]).Number(numbers[i % numbers.size()]).Integer(-7 * int64_t(i));
      table.EndRow();
    }
    table.Close();
  }
  const auto rows = PythonCsv(dir / "q.csv");
  ASSERT_TRUE(rows.is_array()) << ReadFile(dir / "q.csv");
  ASSERT_EQ(rows.size(), texts.size() + 1);
  EXPECT_EQ(rows[0], nlohmann::json({"name, with \"comma\"", "value", "n"}));
  for (size_t i = 0; i < texts.size(); ++i) {
    EXPECT_EQ(rows[i + 1][0], texts[i]) << i;
    // Numbers read back as the same doubles.
    EXPECT_EQ(std::stod(rows[i + 1][1].get<std::string>()), numbers[i % numbers.size()]) << i;
    EXPECT_EQ(rows[i + 1][2], std::to_string(-7 * int64_t(i)));
  }
  fs::remove_all(dir);
}

TEST(RunFolder, TableMistakesAreNamed) {
  const auto sim = testing::LoadXml(testing::Experiment(""));
  auto message = [&](auto&& make) -> std::string {
    try {
      make();
    } catch (const std::exception& e) {
      return e.what();
    }
    return "";
  };
  const std::vector<TableColumn> columns = {{"a", ColumnType::kNumber}};
  EXPECT_NE(message([&] {
              Table::InRunFolder(*sim, "../up.csv", columns);
            }).find("expected a file name relative to the run folder, inside it"),
            std::string::npos);
  EXPECT_NE(message([&] {
              Table::InRunFolder(*sim, "/tmp/abs.csv", columns);
            }).find("relative to the run folder"),
            std::string::npos);
  EXPECT_NE(message([&] {
              Table::InRunFolder(*sim, "t.txt", columns);
            }).find("accepted endings: .csv, .csv.gz (gzip), .h5 or .hdf5"),
            std::string::npos);
  EXPECT_NE(message([&] {
              Table::InRunFolder(*sim, "t.csv", {{"a"}, {"a"}});
            }).find("two columns are named 'a'"),
            std::string::npos);
  Table t = Table::InRunFolder(*sim, "t.csv", {{"a"}, {"b", ColumnType::kText}});
  EXPECT_NE(message([&] { t.Text("x"); }).find("column 'a' holds a number, not a text"),
            std::string::npos);
  t.Number(1);
  EXPECT_NE(message([&] { t.EndRow(); }).find("a row of 1 cells; it has 2 columns"),
            std::string::npos);
}

// Writes a table in the run folder: one row per tick (positions of every
// entity in CSV or HDF5, params file="...").
class TableWriting : public LoopFunctions {
 public:
  void Init(const Params& params) override {
    table_ = Table::InRunFolder(sim(), params.GetString("file", "tables/ticks.csv"),
                                {{"tick", ColumnType::kInteger}, {"note", ColumnType::kText}});
    Row();
  }
  void PostStep() override { Row(); }
  void Destroy() override { table_.Close(); }

 private:
  void Row() {
    table_.Integer(static_cast<int64_t>(sim().tick()))
        .Text("tick, \"" + std::to_string(sim().tick()) + "\"");
    table_.EndRow();
  }
  Table table_;
};
COLONY_REGISTER_LOOP_FUNCTIONS(TableWriting, "table_writing", "test only: a table per tick",
                               {{"file", "a name", "tables/ticks.csv", "the table"}});

std::string TableExperiment(const std::string& file) {
  return testing::Experiment(
      "", "", "4,4,1",
      "<loop_functions label=\"table_writing\"><params file=\"" + file + "\"/></loop_functions>");
}

TEST(RunFolder, LoopFunctionsWriteTablesIntoTheRunFolderByName) {
  const fs::path run = TempDir("run") / "not_made_yet";
  for (const std::string file : {"tables/ticks.csv", "ticks.h5"}) {
    ExperimentOptions options;
    options.text = TableExperiment(file);
    options.run_folder = run.string();
    {
      auto sim = Simulation::Load(options);
      for (int i = 0; i < 3; ++i) sim->Step();
    }
    ASSERT_TRUE(fs::exists(run / file)) << file;
  }
  const auto rows = PythonCsv(run / "tables/ticks.csv");
  EXPECT_EQ(rows, nlohmann::json::parse(R"([["tick", "note"], ["0", "tick, \"0\""],
      ["1", "tick, \"1\""], ["2", "tick, \"2\""], ["3", "tick, \"3\""]])"));
  fs::remove_all(run.parent_path());
}

TEST(RunFolder, WithoutARunFolderTablesWriteNowhere) {
  const fs::path cwd = TempDir("cwd");
  fs::create_directories(cwd);
  const fs::path before = fs::current_path();
  fs::current_path(cwd);
  {
    auto sim = testing::LoadXml(TableExperiment("ticks.csv"));
    for (int i = 0; i < 3; ++i) sim->Step();
    Table t = Table::InRunFolder(*sim, "t.h5", {{"a"}});
    EXPECT_FALSE(t.writing());
    t.Number(1).EndRow();
    t.Close();
  }
  fs::current_path(before);
  EXPECT_TRUE(fs::is_empty(cwd)) << "something was written to the current directory";
  fs::remove_all(cwd);
}

// Reads the run folder it is given (params: none).
class FolderReader : public Controller {
 public:
  void ControlStep() override { seen = run_folder(); }
  static inline std::string seen;
};
COLONY_REGISTER_CONTROLLER(FolderReader, "folder_reader", "test only: reads run_folder()");

TEST(RunFolder, ControllersSeeTheRunFolder) {
  ExperimentOptions options;
  options.text = testing::Experiment(
      "<marxbot id=\"r\"><body position=\"0,0,0\"/><controller config=\"f\"/></marxbot>",
      "<folder_reader id=\"f\"/>");
  options.run_folder = "/somewhere/run";
  Simulation::Load(options)->Step();
  EXPECT_EQ(FolderReader::seen, "/somewhere/run");
  options.run_folder = "";
  Simulation::Load(options)->Step();
  EXPECT_EQ(FolderReader::seen, "");
}

// Sets metric params name in Init (and params later from tick 2 on).
class MetricNamed : public LoopFunctions {
 public:
  void Init(const Params& params) override {
    name_ = params.GetString("name");
    later_ = params.GetString("later", "");
    sim().metrics().Set(name_, 0.5);
  }
  void PostStep() override {
    sim().metrics().Set(name_, static_cast<double>(sim().tick()));
    if (!later_.empty() && sim().tick() >= 2) sim().metrics().Set(later_, 1);
  }

 private:
  std::string name_, later_;
};
COLONY_REGISTER_LOOP_FUNCTIONS(MetricNamed, "metric_named", "test only: one metric",
                               {{"name", "a name", "", "the metric"},
                                {"later", "a name", "", "a metric set from tick 2 on"}});

std::string MetricExperiment(const std::string& params) {
  return testing::Experiment(
      "", "", "4,4,1",
      "<loop_functions label=\"metric_named\"><params " + params + "/></loop_functions>");
}

TEST(RunFolder, MetricNamesCollidingWithBuiltInColumnsAreRejectedAtLoad) {
  for (const std::string name : {"time", "tick"}) {
    const std::string e = testing::LoadError(MetricExperiment("name=\"" + name + "\""));
    EXPECT_NE(e.find("<loop_functions>"), std::string::npos) << e;
    EXPECT_NE(e.find("metric '" + name +
                     "' of loop functions 'metric_named' has the name of one of metrics.csv's "
                     "own columns (tick, time); rename the metric"),
              std::string::npos)
        << e;
  }
  EXPECT_EQ(testing::LoadError(MetricExperiment("name=\"times\"")), "");
}

TEST(RunFolder, MetricNamesOfTwoLoopFunctionsMayNotCollide) {
  Metrics m;
  const std::string a = "counting", b = "timing";
  m.SetOwner(&a);
  m.Set("robots", 3);
  m.Set("robots", 4);  // its own metric, again
  m.SetOwner(&b);
  try {
    m.Set("robots", 5);
    ADD_FAILURE() << "no error";
  } catch (const MetricNameError& e) {
    EXPECT_STREQ(e.what(),
                 "metric 'robots' of loop functions 'timing' is already a metric of loop "
                 "functions 'counting'; give each metric its own name");
  }
}

TEST(RunFolder, MetricsCsvStartsAtTickZeroAndQuotesNames) {
  const fs::path dir = TempDir("metrics");
  {
    ExperimentOptions options;
    options.text = MetricExperiment("name='dist,to \"light\"'");
    options.run_folder = dir.string();
    auto sim = Simulation::Load(options);
    RunOutput output(dir.string(), *sim);
    RunToEnd(*sim, &output, 0, {});
  }
  const auto rows = PythonCsv(dir / "metrics.csv");
  ASSERT_EQ(rows.size(), 102u);  // header, ticks 0 to 100
  EXPECT_EQ(rows[0], nlohmann::json({"tick", "time", "dist,to \"light\""}));
  EXPECT_EQ(rows[1], nlohmann::json({"0", "0", "0.5"}));  // as Init set it
  EXPECT_EQ(rows[4], nlohmann::json({"3", "0.3", "3"}));
  fs::remove_all(dir);
}

TEST(RunFolder, AMetricFirstSetAfterTickZeroEndsTheRun) {
  const fs::path dir = TempDir("late_metric");
  ExperimentOptions options;
  options.text = MetricExperiment("name=\"a\" later=\"b\"");
  options.run_folder = dir.string();
  auto sim = Simulation::Load(options);
  RunOutput output(dir.string(), *sim);
  try {
    RunToEnd(*sim, &output, 0, {});
    ADD_FAILURE() << "no error";
  } catch (const RuntimeFailure& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "loop functions 'metric_named' failed in PostStep at tick 2: metric 'b' of loop "
                  "functions 'metric_named' was set for the first time after metrics.csv's header "
                  "was written (at tick 0, after Init); set every metric in Init too"),
              std::string::npos)
        << e.what();
  }
  fs::remove_all(dir);
}

// The colony program, run in `cwd`.
testing::CommandResult ColonyIn(const fs::path& cwd, const std::string& args) {
  return testing::RunCommand("cd '" + cwd.string() + "' && " COLONY_EXE " " + args);
}

std::string HashOf(const fs::path& run) {
  const auto j = nlohmann::json::parse(ReadFile(run / "summary.json"), nullptr, false);
  return j.is_object() ? j.value("final_state_hash", "") : "";
}

// experiments/diffusion.xml in folder `dir`, naming its plugin libraries by
// paths relative to it.
fs::path RelativeLibraryCopy(const fs::path& dir) {
  fs::create_directories(dir);
  std::string xml = ReadFile(COLONY_SOURCE_DIR "/experiments/diffusion.xml");
  for (const std::string name : {"diffusion_metrics", "diffusion"}) {
    const std::string attribute = "library=\"" + name + "\"";
    const size_t at = xml.find(attribute);
    EXPECT_NE(at, std::string::npos) << attribute;
    const fs::path lib = fs::path(COLONY_BINARY_DIR) / "lib/colony" / ("lib" + name + ".so");
    xml.replace(at, attribute.size(), "library=\"" + fs::relative(lib, dir).string() + "\"");
  }
  std::ofstream(dir / "diffusion.xml") << xml;
  return dir / "diffusion.xml";
}

TEST(RunFolder, ARunFolderReproducesItsRunFromAnotherDirectory) {
  const fs::path root = TempDir("reproduce");
  const fs::path exp = RelativeLibraryCopy(root / "experiment");
  fs::create_directories(root / "elsewhere" / "deeper");
  const std::string sets =
      " --set framework.experiment.length=2 --set arena.distribute.entity.quantity=30";
  auto r = ColonyIn(root / "experiment",
                    "run diffusion.xml --quiet --seed 7" + sets + " --out ../first");
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string written = ReadFile(root / "first" / "experiment.xml");
  EXPECT_NE(written.find("random_seed=\"7\""), std::string::npos) << written;
  EXPECT_NE(written.find("quantity=\"30\""), std::string::npos) << written;
  EXPECT_NE(written.find("library=\"" COLONY_BINARY_DIR "/lib/colony/libdiffusion.so\""),
            std::string::npos)
      << written;
  // From another folder, with no --seed and no --set: the same run.
  r = ColonyIn(root / "elsewhere" / "deeper", "run ../../first/experiment.xml --quiet --out out");
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string hash = HashOf(root / "first");
  EXPECT_FALSE(hash.empty());
  EXPECT_EQ(HashOf(root / "elsewhere" / "deeper" / "out"), hash);
  // The seed matters: the file's own seed gives another run.
  r = ColonyIn(root / "experiment", "run diffusion.xml --quiet" + sets + " --out ../seed1");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(HashOf(root / "seed1"), hash);
  fs::remove_all(root);
}

// A relative file other than a library: foraging's floor image, beside the
// experiment file.
TEST(RunFolder, RelativeFilesAreFoundFromTheRunFolder) {
  const fs::path root = TempDir("floor_image");
  fs::create_directories(root / "elsewhere");
  auto r = ColonyIn(root, "run " COLONY_SOURCE_DIR
                          "/experiments/foraging.xml --quiet --set framework.experiment.length=1 "
                          "--out first");
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string written = ReadFile(root / "first" / "experiment.xml");
  EXPECT_NE(written.find("path=\"" COLONY_SOURCE_DIR "/experiments/foraging_floor.png\""),
            std::string::npos)
      << written;
  EXPECT_NE(written.find("<foraging id=\"fc\" library=\"foraging\">"), std::string::npos)
      << "a bare library name stays";
  r = ColonyIn(root / "elsewhere", "run ../first/experiment.xml --quiet --out out");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(HashOf(root / "elsewhere" / "out"), HashOf(root / "first"));
  fs::remove_all(root);
}

TEST(RunFolder, SummaryCarriesProvenance) {
  const fs::path root = TempDir("provenance");
  fs::create_directories(root);
  const auto r = ColonyIn(root, "run " COLONY_SOURCE_DIR
                                "/experiments/diffusion.xml --quiet --seed 7 --set "
                                "framework.experiment.length=1 --out run");
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string text = ReadFile(root / "run" / "summary.json");
  EXPECT_EQ(SummaryProblem(text), "");
  const auto j = nlohmann::json::parse(text);
  EXPECT_EQ(j["colony_version"], ColonyVersion());
  EXPECT_TRUE(std::regex_match(j["git_revision"].get<std::string>(),
                               std::regex("[0-9a-f]{40}(-dirty)?|unknown")))
      << j["git_revision"];
  EXPECT_EQ(
      j["command_line"],
      nlohmann::json({COLONY_EXE, "run", COLONY_SOURCE_DIR "/experiments/diffusion.xml", "--quiet",
                      "--seed", "7", "--set", "framework.experiment.length=1", "--out", "run"}));
  // Each plugin library, with the SHA-256 sha256sum prints.
  ASSERT_EQ(j["plugin_libraries"].size(), 2u) << j["plugin_libraries"];
  for (const auto& library : j["plugin_libraries"]) {
    const std::string path = library["path"];
    EXPECT_TRUE(fs::path(path).is_absolute()) << path;
    const auto sum = testing::RunCommand("sha256sum '" + path + "'");
    EXPECT_EQ(library["sha256"], sum.output.substr(0, 64)) << path;
  }
  const std::regex iso("\\d{4}-\\d\\d-\\d\\dT\\d\\d:\\d\\d:\\d\\dZ");
  EXPECT_TRUE(std::regex_match(j["start_time"].get<std::string>(), iso)) << j["start_time"];
  EXPECT_TRUE(std::regex_match(j["end_time"].get<std::string>(), iso)) << j["end_time"];
  EXPECT_LE(j["start_time"].get<std::string>(), j["end_time"].get<std::string>());
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  EXPECT_EQ(j["host"], host);
  fs::remove_all(root);
}

// HDF5 is a plugin loaded on first use (core/table_formats.h): `colony
// version` and a run writing CSV never load libhdf5; a run writing its
// trajectories in HDF5 loads it and names the plugin in its provenance.
// LD_DEBUG=files makes the dynamic loader name every library it opens.
TEST(RunFolder, OnlyRunsThatUseHdf5LoadIt) {
  const fs::path root = TempDir("hdf5_on_demand");
  fs::create_directories(root);
  auto colony = [&](const std::string& args) {
    return testing::RunCommand("cd '" + root.string() + "' && LD_DEBUG=files " COLONY_EXE " " +
                               args);
  };
  auto plugins = [&](const std::string& run) {
    const auto j = nlohmann::json::parse(ReadFile(root / run / "summary.json"), nullptr, false);
    std::string paths;
    for (const auto& library : j["plugin_libraries"]) paths += library.value("path", "") + "\n";
    return paths;
  };
  auto r = colony("version");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("libcolony.so"), std::string::npos) << "no loader output:\n" << r.output;
  EXPECT_EQ(r.output.find("libhdf5"), std::string::npos) << r.output;
  const std::string run = "run " COLONY_SOURCE_DIR
                          "/experiments/diffusion.xml --quiet --set framework.experiment.length=1 "
                          "--set output.trajectories_every=1";
  r = colony(run + " --out csv");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::exists(root / "csv" / "trajectories.csv"));
  EXPECT_EQ(r.output.find("libhdf5"), std::string::npos) << r.output;
  EXPECT_EQ(plugins("csv").find("libcolony_hdf5.so"), std::string::npos) << plugins("csv");
  r = colony(run + " --set output.format=hdf5 --out hdf5");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_GT(fs::file_size(root / "hdf5" / "trajectories.h5"), 1000u);
  EXPECT_NE(r.output.find("libhdf5"), std::string::npos) << r.output;
  EXPECT_NE(plugins("hdf5").find("/libcolony_hdf5.so\n"), std::string::npos) << plugins("hdf5");
  fs::remove_all(root);
}

// Without the plugin (a program copied away from its plugins, the search
// path pointed at an empty folder), an HDF5 trajectories table stops the run
// (exit 1) before its first row, with a message naming the plugin and where
// it was looked for.
TEST(RunFolder, AMissingHdf5PluginIsNamed) {
  const std::vector<std::string> search = PluginSearchPath();
  if (fs::exists(fs::path(search.back()) / "libcolony_hdf5.so"))
    GTEST_SKIP() << "Colony is installed in " << search.back() << ": its plugin would be found";
  const fs::path root = TempDir("hdf5_missing");
  const fs::path exp = RelativeLibraryCopy(root / "experiment");
  fs::create_directories(root / "bin");
  fs::create_directories(root / "empty");
  fs::copy_file(COLONY_EXE, root / "bin" / "colony");
  const auto r = testing::RunCommand(
      "cd '" + root.string() + "' && COLONY_PLUGIN_PATH='" + (root / "empty").string() +
      "' bin/colony run experiment/diffusion.xml --quiet --set framework.experiment.length=1 "
      "--set output.trajectories_every=1 --set output.format=hdf5 --out run");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(testing::Mentions(
      r.output, {"HDF5 tables need the plugin colony_hdf5", "cannot load library 'colony_hdf5'",
                 (root / "empty" / "libcolony_hdf5.so").string() + " (no such file)"}))
      << r.output;
  EXPECT_FALSE(fs::exists(root / "run" / "trajectories.h5"));
  fs::remove_all(root);
}

}  // namespace
}  // namespace colony
