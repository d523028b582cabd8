// ARGoS experiment files (root <argos-configuration>) read as they are
// (core/argos_compat.cpp, docs/coming-from-argos.md): ARGoS's device names,
// GUI-only sections and attributes, the robot's device figures, noise_level;
// a floor coloured by the loop functions; and no silent clamping of wheel
// speeds.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <string>

#include "core/experiment_spec.h"
#include "core/simulation.h"
#include "tests/test_util.h"

namespace colony {
namespace {

using Result = colony::testing::CommandResult;

Result Colony(const std::string& args) {
  return colony::testing::RunCommand(std::string(COLONY_EXE) + " " + args);
}

size_t Count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// An ARGoS-style file: ARGoS's device names and implementations, show_rays,
// noise_level, the LEDs' medium, the media's index settings, the robot's
// rab_range and camera aperture, and a Qt visualisation.
const char* kArgosFile = R"(<?xml version="1.0" ?>
<argos-configuration>
  <framework>
    <system threads="0" />
    <experiment length="20" ticks_per_second="10" random_seed="124" />
  </framework>
  <controllers>
    <diffusion id="fdc" library="diffusion">
      <actuators>
        <differential_steering implementation="default" />
        <leds implementation="default" medium="leds" />
        <range_and_bearing implementation="default" />
      </actuators>
      <sensors>
        <footbot_proximity implementation="default" show_rays="true" noise_level="0.05" />
        <footbot_light implementation="rot_z_only" show_rays="false" />
        <footbot_base_ground implementation="rot_z_only" />
        <range_and_bearing implementation="medium" medium="rab" show_rays="true" />
        <colored_blob_omnidirectional_camera implementation="rot_z_only" medium="leds" show_rays="true" />
        <positioning implementation="default" />
        <differential_steering implementation="default" />
      </sensors>
      <params alpha="7.5" delta="0.1" velocity="0.05" />
    </diffusion>
  </controllers>
  <arena size="3, 3, 1" center="0,0,0.5">
    <box id="wall_north" size="2,0.1,0.5" movable="false"><body position="0,1,0" orientation="0,0,0" /></box>
    <box id="wall_south" size="2,0.1,0.5" movable="false"><body position="0,-1,0" orientation="0,0,0" /></box>
    <box id="wall_east" size="0.1,2,0.5" movable="false"><body position="1,0,0" orientation="0,0,0" /></box>
    <box id="wall_west" size="0.1,2,0.5" movable="false"><body position="-1,0,0" orientation="0,0,0" /></box>
    <light id="light" position="0,0,0.5" orientation="0,0,0" color="yellow" intensity="3.0" medium="leds" />
    <distribute>
      <position method="uniform" min="-0.9,-0.9,0" max="0.9,0.9,0" />
      <orientation method="gaussian" mean="0,0,0" std_dev="360,0,0" />
      <entity quantity="8" max_trials="100">
        <foot-bot id="fb" rab_range="2" rab_data_size="4" omnidirectional_camera_aperture="80">
          <controller config="fdc" />
        </foot-bot>
      </entity>
    </distribute>
  </arena>
  <physics_engines>
    <kinematics2d id="k2d" />
  </physics_engines>
  <media>
    <led id="leds" grid_size="1,1,1" />
    <range_and_bearing id="rab" index="grid" grid_size="1,1,1" />
  </media>
  <visualization>
    <qt-opengl autoplay="true">
      <camera><placements><placement index="0" position="0,0,4" look_at="0,0,0" up="1,0,0" lens_focal_length="20" /></placements></camera>
    </qt-opengl>
  </visualization>
</argos-configuration>
)";

std::filesystem::path WriteArgosFile(const std::string& name, const std::string& text) {
  const auto dir = testing::FreshTempDir("colony_argos_test", name);
  std::filesystem::create_directories(dir);
  const auto file = dir / (name + ".argos");
  std::ofstream(file) << text;
  return file;
}

TEST(ArgosFiles, RunAsTheyAreWithOneNotice) {
  const auto file = WriteArgosFile("runs", kArgosFile);
  const Result r =
      Colony("run " + file.string() + " --out " + (file.parent_path() / "out").string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(Count(r.output, "an ARGoS file; ignored"), 1u) << r.output;
  EXPECT_NE(r.output.find("<qt-opengl> (line 50)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("show_rays (lines 15, 16, 18, 19)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("<media> grid_size (lines 46, 47)"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("error"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;
}

// The robots run the native diffusion controller, which finds
// <footbot_proximity> as its "proximity": they wander and never touch a wall.
TEST(ArgosFiles, ControllersFindArgosNamedDevicesByColonyName) {
  ExperimentOptions options;
  options.text = kArgosFile;
  auto sim = Simulation::Load(options);
  const Space& space = sim->space();
  std::vector<Vec3> start;
  std::vector<uint32_t> robots;
  for (uint32_t s = 0; s < space.slots(); ++s) {
    if (space.alive(s) && (space.flags(s) & kRobot)) {
      robots.push_back(s);
      start.push_back(space.pose(s).position);
    }
  }
  ASSERT_EQ(robots.size(), 8u);
  double moved = 0;
  while (!sim->Done()) {
    sim->Step();
    for (uint32_t s : robots) {
      const Vec3 p = space.pose(s).position;
      // Walls' inner faces at +-0.95; the marXbot's radius is 0.085.
      ASSERT_LT(std::max(std::abs(p.x()), std::abs(p.y())), 0.95 - 0.085 + 1e-6)
          << space.id(s) << " touches a wall at tick " << sim->tick();
    }
  }
  for (size_t i = 0; i < robots.size(); ++i)
    moved += (space.pose(robots[i]).position - start[i]).norm();
  EXPECT_GT(moved / robots.size(), 0.2);  // they drove (20 s at 5 cm/s, turning at walls)
}

// What ARGoS writes on the robot or in its own words, Colony reads on the
// device: rab_range -> the emitter's range, rab_data_size -> its data_size,
// omnidirectional_camera_aperture -> the camera's aperture; noise_level ->
// uniform noise in [-level, level]; implementation names ARGoS uses for how
// it simulates a device -> Colony's one implementation.
TEST(ArgosFiles, RobotFiguresAndNoiseLevelReachTheDevices) {
  ExperimentOptions options;
  options.text = kArgosFile;
  const ExperimentSpec spec = ReadExperimentSpec(options);
  ASSERT_EQ(spec.controllers.size(), 1u);
  const ControllerSpec& c = spec.controllers[0];
  auto node = [&](const std::vector<PluginSpec>& devices, const std::string& label) {
    for (const PluginSpec& d : devices)
      if (d.label == label) return d.node;
    ADD_FAILURE() << "no device " << label;
    return ConfigNode();
  };
  const ConfigNode rab = node(c.actuators, "range_and_bearing");
  EXPECT_EQ(rab.GetString("range", ""), "2");
  EXPECT_EQ(rab.GetString("data_size", ""), "4");
  EXPECT_EQ(node(c.sensors, "colored_blob_omnidirectional_camera").GetString("aperture", ""), "80");
  const ConfigNode proximity = node(c.sensors, "footbot_proximity");
  EXPECT_EQ(proximity.GetString("noise", ""), "uniform");
  EXPECT_EQ(proximity.GetString("noise_range", ""), "-0.05,0.05");
  EXPECT_FALSE(proximity.Has("show_rays"));
  EXPECT_FALSE(node(c.sensors, "footbot_light").Has("implementation"));
}

// ARGoS's nested parameters become dotted names on <params>; two siblings of
// one name cannot, and are an error naming both lines.
TEST(ArgosFiles, NestedParametersBecomeDottedNames) {
  std::string text = kArgosFile;
  const std::string flat = "<params alpha=\"7.5\" delta=\"0.1\" velocity=\"0.05\" />";
  text.replace(text.find(flat), flat.size(),
               "<params alpha=\"7.5\" delta=\"0.1\" velocity=\"0.05\">\n"
               "        <wheel_turning max_speed=\"10\"><limits hard=\"yes\"/></wheel_turning>\n"
               "        <flag/>\n"
               "      </params>");
  ExperimentOptions options;
  options.text = text;
  const ExperimentSpec spec = ReadExperimentSpec(options);
  const Params& p = spec.controllers.at(0).params;
  EXPECT_EQ(p.GetString("alpha", ""), "7.5");
  EXPECT_EQ(p.GetString("wheel_turning.max_speed", ""), "10");
  EXPECT_EQ(p.GetString("wheel_turning.limits.hard", ""), "yes");
  EXPECT_TRUE(p.Has("flag."));

  text.replace(text.find("<flag/>"), 7, "<wheel_turning max_speed=\"20\"/>");
  const std::string error = testing::LoadError(text);
  EXPECT_NE(error.find(":25: <wheel_turning>: a second <wheel_turning> (first at line 24)"),
            std::string::npos)
      << error;
}

// A Colony file is never rewritten: ARGoS's GUI sections and attributes there
// are errors, as any unknown element or attribute.
TEST(ArgosFiles, ColonyFilesAreNotRewritten) {
  std::string text = kArgosFile;
  text.replace(text.find("<argos-configuration>"), 21, "<colony>");
  text.replace(text.find("</argos-configuration>"), 22, "</colony>");
  const std::string error = testing::LoadError(text);
  EXPECT_NE(error.find("'show_rays': unknown attribute"), std::string::npos) << error;
}

// A device name ARGoS has and Colony does not gets the usual message.
TEST(ArgosFiles, UnknownDeviceNamesAreErrors) {
  std::string text = kArgosFile;
  text.replace(text.find("<positioning implementation=\"default\" />"), 40,
               "<footbot_turret_encoderx implementation=\"default\" />");
  const std::string error = testing::LoadError(text);
  EXPECT_NE(error.find("unknown sensor 'footbot_turret_encoderx' (did you mean "
                       "'footbot_turret_encoder'?)"),
            std::string::npos)
      << error;
}

std::string FloorExperiment(const std::string& floor, const std::string& loop_functions) {
  return "<colony><framework><experiment length=\"1\" ticks_per_second=\"10\"/></framework>"
         "<arena size=\"4,4,1\" center=\"0,0,0.5\">" +
         floor + "</arena><physics_engines><kinematics2d id=\"k\"/></physics_engines>" +
         loop_functions + "</colony>";
}

const std::string kFloorHalves = "<loop_functions library=\"" COLONY_TEST_PLUGIN_DIR
                                 "/libfloor_halves.so\" label=\"floor_halves\"/>";

// <floor source="loop_functions" pixels_per_meter="20">: what the loop
// functions' FloorColor says, sampled once; ground sensors read it.
TEST(FloorFromLoopFunctions, GroundSensorsReadWhatTheLoopFunctionsPaint) {
  auto sim = testing::LoadXml(
      FloorExperiment("<floor source=\"loop_functions\" pixels_per_meter=\"20\"/>", kFloorHalves));
  const Floor& floor = sim->space().floor();
  EXPECT_EQ(floor.GreyAt(-1, 0.3), 0.0);
  EXPECT_EQ(floor.GreyAt(1, -0.3), 1.0);
  EXPECT_NEAR(floor.GreyAt(1, 1), 128 / 255.0, 1e-9);
  EXPECT_EQ(floor.GreyAt(1.4, 1), 1.0);  // outside the disc
}

TEST(FloorFromLoopFunctions, BadFloorsAreErrors) {
  std::string e = testing::LoadError(
      FloorExperiment("<floor source=\"loop_functions\" pixels_per_meter=\"20\"/>", ""));
  EXPECT_NE(e.find("the floor is coloured by the loop functions, but none are declared"),
            std::string::npos)
      << e;
  e = testing::LoadError(FloorExperiment("<floor source=\"loop_functions\"/>", kFloorHalves));
  EXPECT_NE(e.find("pixels_per_meter"), std::string::npos) << e;
  e = testing::LoadError(
      FloorExperiment("<floor color=\"white\" pixels_per_meter=\"20\"/>", kFloorHalves));
  EXPECT_NE(e.find("only a floor with source=\"loop_functions\" takes pixels_per_meter"),
            std::string::npos)
      << e;
  e = testing::LoadError(
      FloorExperiment("<floor source=\"loop_functions\" pixels_per_meter=\"1e9\"/>", kFloorHalves));
  EXPECT_NE(e.find("pixels_per_meter"), std::string::npos) << e;
  // Loop functions that do not colour the floor.
  e = testing::LoadError(FloorExperiment(
      "<floor source=\"loop_functions\" pixels_per_meter=\"20\"/>",
      "<loop_functions library=\"diffusion_metrics\" label=\"diffusion_metrics\"/>"));
  EXPECT_NE(e.find("do not colour the floor"), std::string::npos) << e;
}

// A controller written for cm/s (ARGoS's unit) that asks for 5 "m/s" is told
// its wheels run at 0.3 m/s, once per robot.
TEST(WheelSpeeds, BeyondTheLimitIsAWarningNotASilentClamp) {
  const Result r = Colony("run " COLONY_SOURCE_DIR
                          "/experiments/diffusion.xml --set framework.experiment.length=1 "
                          "--set arena.distribute.entity.quantity=3 "
                          "--set controllers.diffusion.params.velocity=5 --out " +
                          testing::FreshTempDir("colony_argos_test", "speed").string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(Count(r.output,
                  "differential_steering wheel speed 5 m/s is beyond the wheels' limit, "
                  "0.3 m/s; the wheel runs at 0.3 m/s (said once per robot)"),
            3u)
      << r.output;
}

// A controller element without library= loads the plugin of its name. When
// that plugin is there but cannot be loaded, the error says so and why,
// rather than that the controller is unknown.
TEST(ArgosFiles, AControllerPluginThatCannotBeLoadedIsReportedWithTheReason) {
  const auto dir = testing::FreshTempDir("colony_argos_test", "unloadable");
  std::filesystem::create_directories(dir);
  const auto file = dir / "unloadable.xml";
  std::ofstream(file) << R"(<colony>
  <framework><experiment length="1" ticks_per_second="10" random_seed="1"/></framework>
  <controllers><unloadable_controller id="c"/></controllers>
  <arena size="2,2,1" center="0,0,0.5">
    <marxbot id="mb"><body position="0,0,0"/><controller config="c"/></marxbot>
  </arena>
  <physics_engines><kinematics2d id="k2d"/></physics_engines>
</colony>
)";
  const Result r = testing::RunCommand("COLONY_PLUGIN_PATH=" COLONY_TEST_PLUGIN_DIR " " +
                                       std::string(COLONY_EXE) + " run " + file.string() +
                                       " --out " + (dir / "out").string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("unloadable.xml:3"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("the plugin 'unloadable_controller' was found but could not be loaded"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("undefined symbol"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace colony
