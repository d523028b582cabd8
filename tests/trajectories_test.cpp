// The trajectories table (<output trajectories_every format compress>) as a
// user reads it: the rows and columns of a 3-robot run in CSV, gzip'ed CSV
// and HDF5 (read back with the HDF5 C API, and with h5py and pandas when
// they are installed), per-robot values from a controller and from loop
// functions, names refused, and the state hash unchanged by recording.
#include <hdf5.h>
#include <zlib.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>

#include "actuators/differential_steering/differential_steering.h"
#include "apps/colony/sweep.h"
#include "core/output.h"
#include "core/table_writer.h"
#include "tests/test_util.h"

namespace colony {
namespace {

namespace fs = std::filesystem;
using testing::ReadFile;

// Drives straight at params speed and gives its step count, a state label
// and (robot r1 only) a battery level. params give: "own" also gives "x"
// (a column of the table's own), "twice" gives "steps" twice, "late" gives
// "late" from its third step on, "throw" throws.
class TrajectoryProbe : public Controller {
 public:
  void Init(const Params& params) override {
    speed_ = params.GetDouble("speed", 0.05);
    give_ = params.GetString("give", "");
    steering_ = &GetActuator<DifferentialSteering>("differential_steering");
  }
  void ControlStep() override {
    ++steps_;
    steering_->SetLinearVelocity(speed_, speed_);
  }
  void RecordValues(RobotValues& values) const override {
    if (give_ == "throw") throw std::runtime_error("no values today");
    values.Set("steps", steps_);
    values.SetLabel("state", steps_ % 2 ? "odd" : "even, \"quoted\"");
    if (id() == "r1") values.Set("battery", 1.0 - 0.01 * steps_);
    if (give_ == "own") values.Set("x", 1);
    if (give_ == "twice") values.Set("steps", 2);
    if (give_ == "late" && steps_ >= 3) values.Set("late", 1);
  }

 private:
  double speed_ = 0;
  std::string give_;
  int steps_ = 0;
  DifferentialSteering* steering_ = nullptr;
};
COLONY_REGISTER_CONTROLLER(TrajectoryProbe, "trajectory_probe",
                           "test only: drives straight and gives per-robot values");

// Gives each robot's distance from the origin; params give="state" also
// gives a "state" label (which the controller gives too).
class TrajectoryColumns : public LoopFunctions {
 public:
  void Init(const Params& params) override {
    give_ = params.GetString("give", "");
    spawn_ = params.GetString("spawn", "");
  }
  void PostStep() override {
    if (sim().tick() != 2 || spawn_.empty()) return;
    sim().AddEntity("<marxbot id=\"" + spawn_ +
                    "\"><body position=\"0,-1,0\"/><controller config=\"p\"/></marxbot>");
  }
  void RecordRobotValues(EntityHandle robot, RobotValues& values) override {
    values.Set("distance", sim().space().pose(robot.index).position.head<2>().norm());
    if (give_ == "state") values.SetLabel("state", "from the loop functions");
  }

 private:
  std::string give_, spawn_;
};
COLONY_REGISTER_LOOP_FUNCTIONS(TrajectoryColumns, "trajectory_columns",
                               "test only: a per-robot distance column",
                               {{"give", "state", "", "also a 'state' label"},
                                {"spawn", "an id", "", "adds a robot with this id at tick 2"}});

// Three marxbots facing +y at x = -1, 0, 1, driving for 2 s (20 ticks).
std::string ThreeRobots(const std::string& output, const std::string& give = "",
                        const std::string& loop_give = "", const std::string& spawn = "") {
  std::string robots;
  for (int i = 0; i < 3; ++i) {
    robots += "<marxbot id=\"r" + std::to_string(i) + "\"><body position=\"" +
              std::to_string(i - 1) +
              ",0,0\" orientation=\"90,0,0\"/><controller config=\"p\"/></marxbot>";
  }
  return "<colony><framework><experiment length=\"2\" ticks_per_second=\"10\" "
         "random_seed=\"3\"/></framework><controllers><trajectory_probe id=\"p\"><actuators>"
         "<differential_steering/></actuators><params speed=\"0.05\" give=\"" +
         give +
         "\"/></trajectory_probe></controllers>"
         "<loop_functions label=\"trajectory_columns\"><params give=\"" +
         loop_give + "\" spawn=\"" + spawn +
         "\"/></loop_functions>"
         "<arena size=\"4,4,1\" center=\"0,0,0.5\">" +
         robots + "</arena><physics_engines><kinematics2d id=\"k2d\"/></physics_engines>" + output +
         "</colony>";
}

fs::path TempDir(const std::string& name) {
  return testing::FreshTempDir("colony_trajectories_test", name);
}

struct Finished {
  std::unique_ptr<Simulation> sim;
  RunSummary summary;
};

// Loads `xml` and runs it to the end with its output in `dir`.
Finished RunInto(const std::string& xml, const fs::path& dir) {
  ExperimentOptions options;
  options.text = xml;
  options.run_folder = dir.string();
  Finished run;
  run.sim = Simulation::Load(options);
  RunOutput output(dir.string(), *run.sim);
  run.summary = RunToEnd(*run.sim, &output, 0, {});
  return run;
}

// RFC 4180 CSV: rows of fields, read with colony sweep's reader
// (apps/colony/sweep.h).
std::vector<std::vector<std::string>> ParseCsv(const std::string& text) {
  return sweep::ParseCsv(text, "trajectories.csv").records;
}

const std::vector<std::string> kHeader = {"tick", "time", "id",    "type",  "x",        "y",
                                          "z",    "yaw",  "steps", "state", "distance", "battery"};

TEST(Trajectories, CsvHasARowPerRobotEveryKTicksFromTickZero) {
  const fs::path dir = TempDir("csv");
  const Finished run = RunInto(ThreeRobots("<output trajectories_every=\"5\"/>"), dir);
  const auto rows = ParseCsv(ReadFile(dir / "trajectories.csv"));
  ASSERT_EQ(rows.size(), 1u + 5 * 3);  // header, ticks 0, 5, 10, 15, 20
  EXPECT_EQ(rows[0], kHeader);
  for (size_t r = 1; r < rows.size(); ++r) {
    const auto& row = rows[r];
    ASSERT_EQ(row.size(), kHeader.size()) << r;
    const int record = static_cast<int>(r - 1) / 3, robot = static_cast<int>(r - 1) % 3;
    EXPECT_EQ(row[0], std::to_string(5 * record));
    EXPECT_EQ(std::stod(row[1]), 0.5 * record);
    EXPECT_EQ(row[2], "r" + std::to_string(robot));
    EXPECT_EQ(row[3], "marxbot");
    EXPECT_EQ(row[8], std::to_string(5 * record));
    EXPECT_EQ(row[9], record % 2 ? "odd" : "even, \"quoted\"");
    EXPECT_NEAR(std::stod(row[7]), M_PI / 2, 1e-9);
    // Only r1 has a battery: the others' cells are empty.
    if (robot == 1) {
      EXPECT_NEAR(std::stod(row[11]), 1.0 - 0.05 * record, 1e-12);
    } else {
      EXPECT_EQ(row[11], "");
    }
  }
  // Tick 0: where the file put them; they drive along +y at 5 cm/s.
  EXPECT_EQ(rows[1][4], "-1");
  EXPECT_EQ(rows[1][5], "0");
  EXPECT_EQ(rows[1][10], "1");
  EXPECT_NEAR(std::stod(rows[13][5]), 0.1, 0.01);
  // The last record holds the final poses exactly (numbers read back as the same doubles).
  const Space& space = run.sim->space();
  for (int robot = 0; robot < 3; ++robot) {
    const auto& row = rows[13 + robot];
    const Vec3& p = space.pose(space.Find(row[2]).index).position;
    EXPECT_EQ(std::stod(row[4]), p.x());
    EXPECT_EQ(std::stod(row[5]), p.y());
    EXPECT_EQ(std::stod(row[10]), p.head<2>().norm());
  }
  fs::remove_all(dir);
}

// The HDF5 dataset's rows, as strings (numbers in the shortest form that
// reads back the same, NaN as ""), read with the C API.
std::vector<std::vector<std::string>> ReadHdf5(const fs::path& file, std::string& problem) {
  std::vector<std::vector<std::string>> rows;
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) {
    problem = "cannot open " + file.string();
    return rows;
  }
  const hid_t d = H5Dopen2(f, "trajectories", H5P_DEFAULT);
  const hid_t type = H5Dget_type(d);
  const hid_t space = H5Dget_space(d);
  hsize_t n = 0;
  H5Sget_simple_extent_dims(space, &n, nullptr);
  const int members = H5Tget_nmembers(type);
  std::vector<std::string> header;
  std::vector<H5T_class_t> classes;
  for (int m = 0; m < members; ++m) {
    char* name = H5Tget_member_name(type, m);
    header.push_back(name);
    H5free_memory(name);
    classes.push_back(H5Tget_member_class(type, m));
  }
  rows.push_back(header);
  // One field at a time, in a memory type of its own.
  std::vector<std::vector<std::string>> columns(members);
  for (int m = 0; m < members; ++m) {
    hid_t memory = H5Tcreate(H5T_COMPOUND, 8);
    hid_t string_type = -1;
    if (classes[m] == H5T_STRING) {
      string_type = H5Tcopy(H5T_C_S1);
      H5Tset_size(string_type, H5T_VARIABLE);
      H5Tset_cset(string_type, H5T_CSET_UTF8);
    }
    // Fixed-width strings are read in their own type.
    const hid_t member = H5Tget_member_type(type, m);
    const size_t width =
        classes[m] == H5T_STRING && !H5Tis_variable_str(member) ? H5Tget_size(member) : 0;
    if (width > 0) {
      H5Tclose(memory);
      H5Tclose(string_type);
      memory = H5Tcreate(H5T_COMPOUND, width);
      string_type = H5Tcopy(member);
    }
    H5Tclose(member);
    H5Tinsert(memory, header[m].c_str(), 0,
              classes[m] == H5T_INTEGER ? H5T_NATIVE_INT64
              : classes[m] == H5T_FLOAT ? H5T_NATIVE_DOUBLE
                                        : string_type);
    const size_t cell_size = width > 0 ? width : 8;
    std::vector<char> cells(n * cell_size);
    if (H5Dread(d, memory, H5S_ALL, H5S_ALL, H5P_DEFAULT, cells.data()) < 0)
      problem = "cannot read " + header[m];
    for (hsize_t r = 0; r < n; ++r) {
      const char* cell = cells.data() + r * cell_size;
      std::string text;
      if (classes[m] == H5T_INTEGER) {
        int64_t v;
        std::memcpy(&v, cell, 8);
        text = std::to_string(v);
      } else if (classes[m] == H5T_FLOAT) {
        double v;
        std::memcpy(&v, cell, 8);
        if (!std::isnan(v)) AppendNumber(text, v);
      } else if (width > 0) {
        text.assign(cell, strnlen(cell, width));
      } else {
        char* s;
        std::memcpy(&s, cell, 8);
        text = s ? s : "";
        std::free(s);
      }
      columns[m].push_back(text);
    }
    if (string_type >= 0) H5Tclose(string_type);
    H5Tclose(memory);
  }
  for (hsize_t r = 0; r < n; ++r) {
    std::vector<std::string> row;
    for (int m = 0; m < members; ++m) row.push_back(columns[m][r]);
    rows.push_back(row);
  }
  H5Sclose(space);
  H5Tclose(type);
  H5Dclose(d);
  H5Fclose(f);
  return rows;
}

TEST(Trajectories, Hdf5HoldsTheSameRowsAsCsv) {
  const fs::path csv = TempDir("same_csv"), hdf5 = TempDir("same_hdf5"),
                 deflated = TempDir("same_deflated");
  RunInto(ThreeRobots("<output trajectories_every=\"5\"/>"), csv);
  RunInto(ThreeRobots("<output trajectories_every=\"5\" format=\"hdf5\"/>"), hdf5);
  RunInto(ThreeRobots("<output trajectories_every=\"5\" format=\"hdf5\" compress=\"gzip\"/>"),
          deflated);
  EXPECT_FALSE(fs::exists(hdf5 / "trajectories.csv"));
  auto expected = ParseCsv(ReadFile(csv / "trajectories.csv"));
  // CSV writes the time with 15 digits; HDF5 stores tick x dt exactly.
  for (size_t r = 1; r < expected.size(); ++r) {
    std::string exact;
    AppendNumber(exact, std::stoll(expected[r][0]) * 0.1);
    expected[r][1] = exact;
  }
  for (const fs::path& dir : {hdf5, deflated}) {
    std::string problem;
    const auto rows = ReadHdf5(dir / "trajectories.h5", problem);
    EXPECT_EQ(problem, "");
    EXPECT_EQ(rows, expected) << dir;
  }
  // The types: tick an integer, numbers doubles, labels strings.
  const hid_t f = H5Fopen((hdf5 / "trajectories.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, "trajectories", H5P_DEFAULT);
  const hid_t type = H5Dget_type(d);
  EXPECT_EQ(H5Tget_member_class(type, 0), H5T_INTEGER);
  EXPECT_EQ(H5Tget_member_class(type, 4), H5T_FLOAT);
  EXPECT_EQ(H5Tget_member_class(type, 2), H5T_STRING);
  EXPECT_EQ(H5Tget_member_class(type, 9), H5T_STRING);
  // ids and types in fixed-width strings (the longest id, 2 bytes, plus 8,
  // rounded up to 8 bytes); labels of any length.
  const hid_t id = H5Tget_member_type(type, 2), label = H5Tget_member_type(type, 9);
  EXPECT_FALSE(H5Tis_variable_str(id));
  EXPECT_EQ(H5Tget_size(id), 16u);
  EXPECT_TRUE(H5Tis_variable_str(label));
  H5Tclose(id);
  H5Tclose(label);
  H5Tclose(type);
  H5Dclose(d);
  H5Fclose(f);
  for (const auto& dir : {csv, hdf5, deflated}) fs::remove_all(dir);
}

// The whole content of a gzip file (every member), read with zlib.
std::string Gunzip(const fs::path& file) {
  gzFile f = gzopen(file.c_str(), "rb");
  std::string text;
  char buffer[1 << 14];
  for (int n; f && (n = gzread(f, buffer, sizeof buffer)) > 0;) text.append(buffer, n);
  if (f) gzclose(f);
  return text;
}

TEST(Trajectories, GzipRoundTrip) {
  const fs::path plain = TempDir("plain"), gzip = TempDir("gzip");
  RunInto(ThreeRobots("<output trajectories_every=\"1\"/>"), plain);
  RunInto(ThreeRobots("<output trajectories_every=\"1\" compress=\"gzip\"/>"), gzip);
  EXPECT_FALSE(fs::exists(gzip / "trajectories.csv"));
  const std::string text = ReadFile(plain / "trajectories.csv");
  EXPECT_EQ(ParseCsv(text).size(), 1u + 21 * 3);
  EXPECT_EQ(Gunzip(gzip / "trajectories.csv.gz"), text);
  // Python's gzip module reads it too.
  const auto r = testing::RunCommand(
      "/usr/bin/python3 -c \"import gzip,sys; sys.stdout.write(gzip.open(sys.argv[1], "
      "'rt', newline='').read())\" " +
      (gzip / "trajectories.csv.gz").string());
  if (r.status == 0) {
    EXPECT_EQ(r.output, text);
  }
  fs::remove_all(plain);
  fs::remove_all(gzip);
}

TEST(Trajectories, OffWritesNothingAndRecordingLeavesTheHashAlone) {
  const fs::path off = TempDir("off"), csv = TempDir("on_csv"), hdf5 = TempDir("on_hdf5");
  const Finished a = RunInto(ThreeRobots(""), off);
  const Finished b = RunInto(ThreeRobots("<output trajectories_every=\"1\"/>"), csv);
  const Finished c =
      RunInto(ThreeRobots("<output trajectories_every=\"3\" format=\"hdf5\"/>"), hdf5);
  for (const char* name : {"trajectories.csv", "trajectories.csv.gz", "trajectories.h5"})
    EXPECT_FALSE(fs::exists(off / name)) << name;
  EXPECT_TRUE(fs::exists(csv / "trajectories.csv"));
  EXPECT_TRUE(fs::exists(hdf5 / "trajectories.h5"));
  EXPECT_EQ(a.summary.final_state_hash, b.summary.final_state_hash);
  EXPECT_EQ(a.summary.final_state_hash, c.summary.final_state_hash);
  for (const auto& dir : {off, csv, hdf5}) fs::remove_all(dir);
}

// What loading and starting the output of `xml` throws ("" if nothing).
std::string OutputError(const std::string& xml, bool& config_error) {
  const fs::path dir = TempDir("error");
  config_error = false;
  std::string message;
  try {
    RunInto(xml, dir);
  } catch (const ConfigError& e) {
    config_error = true;
    message = e.what();
  } catch (const std::exception& e) {
    message = e.what();
  }
  fs::remove_all(dir);
  return message;
}

TEST(Trajectories, ValueNamesThatCannotBeColumnsAreRefused) {
  const std::string output = "<output trajectories_every=\"1\"/>";
  bool config = false;
  std::string e = OutputError(ThreeRobots(output, "own"), config);
  EXPECT_TRUE(config) << e;
  EXPECT_NE(e.find("controller 'trajectory_probe' gives the value 'x', the name of one of the "
                   "trajectories table's own columns"),
            std::string::npos)
      << e;
  e = OutputError(ThreeRobots(output, "", "state"), config);
  EXPECT_TRUE(config) << e;
  EXPECT_NE(e.find("loop functions 'trajectory_columns' gives robot 'r0' the value 'state' twice "
                   "(controller 'trajectory_probe' gave it first)"),
            std::string::npos)
      << e;
  e = OutputError(ThreeRobots(output, "twice"), config);
  EXPECT_NE(e.find("the value 'steps' twice"), std::string::npos) << e;
  // A new name after the first record: the run fails, naming it and the tick.
  e = OutputError(ThreeRobots(output, "late"), config);
  EXPECT_FALSE(config) << e;
  EXPECT_NE(e.find("gives robot 'r0' the value 'late', which is not a column"), std::string::npos)
      << e;
  EXPECT_NE(e.find("(at tick 3)"), std::string::npos) << e;
  e = OutputError(ThreeRobots(output, "throw"), config);
  EXPECT_NE(e.find("controller 'trajectory_probe' failed in RecordValues for robot 'r0' at tick "
                   "0: no values today"),
            std::string::npos)
      << e;
  // A robot added while running: a row from its first record on; in HDF5,
  // an id longer than the id column's width ends the run.
  const fs::path dir = TempDir("spawn");
  RunInto(ThreeRobots(output, "", "", "newcomer"), dir);
  const auto rows = ParseCsv(ReadFile(dir / "trajectories.csv"));
  EXPECT_EQ(rows.size(), 1u + 3 * 2 + 4 * 19);  // it is there from tick 2 on
  EXPECT_EQ(rows[10][2], "newcomer");
  fs::remove_all(dir);
  e = OutputError(ThreeRobots("<output trajectories_every=\"1\" format=\"hdf5\"/>", "", "",
                              "a_robot_with_a_long_id"),
                  config);
  EXPECT_NE(e.find("robot 'a_robot_with_a_long_id' has an id of 22 bytes, more than the 16 of "),
            std::string::npos)
      << e;
  // With trajectories off nobody is asked.
  EXPECT_EQ(OutputError(ThreeRobots("", "throw"), config), "");
}

TEST(Trajectories, BadOutputAttributesAreNamed) {
  for (const auto& [output, expected] : std::vector<std::pair<std::string, std::string>>{
           {"trajectories_every=\"-1\"", "trajectories_every"},
           {"trajectories_every=\"1\" format=\"parquet\"", "'parquet'"},
           {"trajectories_every=\"1\" compress=\"zip\"", "'zip'"},
           {"trajectories=\"1\"", "trajectories"}}) {
    const std::string e = testing::LoadError(ThreeRobots("<output " + output + "/>"));
    EXPECT_NE(e.find("<output>"), std::string::npos) << e;
    EXPECT_NE(e.find(expected), std::string::npos) << e;
  }
  EXPECT_NE(testing::LoadError(ThreeRobots("<output format=\"parquet\"/>")).find("csv, hdf5"),
            std::string::npos);
}

TEST(Trajectories, RunsIn3DEnginesHavePitchAndRoll) {
  if (!testing::HaveEngine("dynamics3d")) GTEST_SKIP() << "built without dynamics3d";
  const fs::path dir = TempDir("3d");
  std::string xml = ThreeRobots("<output trajectories_every=\"10\"/>");
  xml.replace(xml.find("<kinematics2d id=\"k2d\"/>"), 24, "<dynamics3d id=\"d3\"/>");
  RunInto(xml, dir);
  const auto rows = ParseCsv(ReadFile(dir / "trajectories.csv"));
  ASSERT_EQ(rows.size(), 1u + 3 * 3);
  const std::vector<std::string> first(rows[0].begin(), rows[0].begin() + 10);
  EXPECT_EQ(first, (std::vector<std::string>{"tick", "time", "id", "type", "x", "y", "z", "yaw",
                                             "pitch", "roll"}));
  // Standing level on the floor.
  for (size_t r = 1; r < rows.size(); ++r) {
    EXPECT_NEAR(std::stod(rows[r][8]), 0, 0.05) << r;
    EXPECT_NEAR(std::stod(rows[r][9]), 0, 0.05) << r;
  }
  fs::remove_all(dir);
}

// The layout docs/data-output.md shows, read with h5py and pandas.
TEST(Trajectories, PandasReadsTheHdf5Table) {
  if (testing::RunCommand("/usr/bin/python3 -c 'import h5py, pandas'").status != 0)
    GTEST_SKIP() << "needs python3-h5py and python3-pandas";
  const fs::path dir = TempDir("pandas");
  RunInto(ThreeRobots("<output trajectories_every=\"10\" format=\"hdf5\"/>"), dir);
  const std::string script =
      "import h5py, pandas as pd\n"
      "with h5py.File('" +
      (dir / "trajectories.h5").string() +
      "') as f:\n"
      "    df = pd.DataFrame(f['trajectories'][:])\n"
      "for c in df.select_dtypes(object): df[c] = df[c].str.decode('utf-8')\n"
      "print(df.shape, ','.join(df.columns))\n"
      "print(df.id.tolist(), df.state.tolist()[0], df.battery.isna().tolist())\n"
      "print(df[df.tick == 20].y.round(2).tolist())\n";
  std::ofstream(dir / "read.py") << script;
  const auto r = testing::RunCommand("/usr/bin/python3 " + (dir / "read.py").string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output,
            "(9, 12) tick,time,id,type,x,y,z,yaw,steps,state,distance,battery\n"
            "['r0', 'r1', 'r2', 'r0', 'r1', 'r2', 'r0', 'r1', 'r2'] even, \"quoted\" "
            "[True, False, True, True, False, True, True, False, True]\n"
            "[0.1, 0.1, 0.1]\n");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace colony
