// The Lua controller host as an ARGoS user meets it (scripting/lua/README.md):
// the example scripts of experiments/lua/ behave as their C++ twins; the robot
// table has ARGoS's names, shapes, units and exact readings; script errors
// stop the run naming the script, the line and the robot (or, with
// on_error="continue", stop only that robot's script); results and random
// draws depend on the seed only; require and relative files resolve beside
// the script and the experiment file.
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "actuators/gripper/gripper_state.h"
#include "core/space.h"
#include "tests/test_util.h"

namespace colony {
namespace {

namespace fs = std::filesystem;
using testing::Metric;

const std::string kLua = COLONY_SOURCE_DIR "/experiments/lua/";

using Result = colony::testing::CommandResult;

// Runs the colony program as a user does.
Result Colony(const std::string& args) {
  return colony::testing::RunCommand(std::string(COLONY_EXE) + " " + args);
}

std::unique_ptr<Simulation> Load(const std::string& file, std::vector<std::string> overrides = {},
                                 std::optional<int> threads = std::nullopt,
                                 std::optional<uint64_t> seed = std::nullopt) {
  ExperimentOptions options;
  options.file = file;
  options.overrides = std::move(overrides);
  options.threads = threads;
  options.seed = seed;
  return Simulation::Load(options);
}

std::vector<uint32_t> Robots(const Space& space) {
  std::vector<uint32_t> robots;
  for (uint32_t s = 0; s < space.slots(); ++s) {
    if (space.alive(s) && (space.flags(s) & kRobot)) robots.push_back(s);
  }
  return robots;
}

double MeanDistanceTo(const Space& space, const Vec2& target) {
  double sum = 0;
  const auto robots = Robots(space);
  for (uint32_t s : robots) sum += (Vec2(space.pose(s).position.head<2>()) - target).norm();
  return sum / static_cast<double>(robots.size());
}

// A fresh folder holding `files` (relative name -> text).
fs::path WriteFiles(const std::string& name, const std::map<std::string, std::string>& files) {
  const fs::path dir = testing::FreshTempDir("colony_lua_test", name);
  for (const auto& [file, text] : files) {
    fs::create_directories((dir / file).parent_path());
    std::ofstream(dir / file) << text;
  }
  return dir;
}

// An ARGoS file: `robots` foot-bots in a row along x (0.5 m apart, facing +x)
// in a walled 4 x 4 m arena, running <lua_controller> with `params`.
std::string ArgosFile(const std::string& params, int robots = 3,
                      const std::string& sensors = "<footbot_proximity/>",
                      const std::string& actuators = "<differential_steering/>") {
  std::string bots;
  for (int i = 0; i < robots; ++i) {
    bots += "<foot-bot id=\"fb" + std::to_string(i) + "\"><body position=\"" +
            std::to_string(-1 + 0.5 * i) +
            ",0,0\" orientation=\"0,0,0\"/><controller config=\"lua\"/></foot-bot>\n";
  }
  return "<?xml version=\"1.0\" ?>\n<argos-configuration>\n"
         "<framework><experiment length=\"5\" ticks_per_second=\"10\" random_seed=\"1\"/>"
         "</framework>\n"
         "<controllers><lua_controller id=\"lua\">\n"
         "<actuators>" +
         actuators + "</actuators>\n<sensors>" + sensors + "</sensors>\n<params " + params +
         "/>\n"
         "</lua_controller></controllers>\n"
         "<arena size=\"4,4,1\" center=\"0,0,0.5\">\n" +
         bots +
         "</arena>\n"
         "<physics_engines><kinematics2d id=\"k2d\"/></physics_engines>\n"
         "</argos-configuration>\n";
}

// --- the examples behave as their C++ twins ------------------------------------------------------

// The same arena, robots and placements as experiments/diffusion.xml, which
// runs the C++ controller: over three seeds the Lua robots drive as far and
// spread as much (within the noise between seeds), and none ever touches a
// wall.
TEST(LuaExamples, DiffusionBehavesAsTheCppDiffusion) {
  double lua_spread = 0, cpp_spread = 0, lua_path = 0, cpp_path = 0;
  const std::vector<std::string> shorter = {"framework.experiment.length=30"};
  for (uint64_t seed : {1, 2, 3}) {
    auto lua = Load(kLua + "diffusion.argos", shorter, std::nullopt, seed);
    auto cpp = Load(COLONY_SOURCE_DIR "/experiments/diffusion.xml", shorter, std::nullopt, seed);
    ASSERT_EQ(lua->robot_count(), 120u);
    const auto robots = Robots(lua->space());
    while (!lua->Done()) {
      lua->Step();
      cpp->Step();
      // The walls' inner faces are at +-3.9 m; a foot-bot's radius is 8.5 cm.
      for (uint32_t s : robots) {
        const Vec3 p = lua->space().pose(s).position;
        ASSERT_LT(std::max(std::abs(p.x()), std::abs(p.y())), 3.9 - 0.085)
            << lua->space().id(s) << " touches a wall at tick " << lua->tick() << ", seed " << seed;
      }
    }
    lua_spread += Metric(*lua, "mean_displacement");
    cpp_spread += Metric(*cpp, "mean_displacement");
    lua_path += Metric(*lua, "mean_path_length");
    cpp_path += Metric(*cpp, "mean_path_length");
  }
  // 30 s at 5 cm/s is 1.5 m of driving, less the turns.
  EXPECT_GT(lua_path / 3, 1.2);
  EXPECT_NEAR(lua_path / cpp_path, 1, 0.05);
  EXPECT_NEAR(lua_spread / cpp_spread, 1, 0.15);
}

TEST(LuaExamples, PhototaxisRobotsEndNearTheLight) {
  auto sim = Load(kLua + "phototaxis.argos");
  const Vec2 light(2, 2);
  const double start = MeanDistanceTo(sim->space(), light);
  while (!sim->Done()) sim->Step();
  const double end = MeanDistanceTo(sim->space(), light);
  EXPECT_GT(start, 3.5);
  EXPECT_LT(end, 1.0) << "from " << start;
  // Every robot got there, none stuck behind the box.
  for (uint32_t s : Robots(sim->space())) {
    EXPECT_LT((Vec2(sim->space().pose(s).position.head<2>()) - light).norm(), 2.0)
        << sim->space().id(s);
  }
}

// experiments/flocking.xml's test (tests/swarm_experiments_test.cpp) on the
// Lua twin: a small flock orders itself and stays one group.
TEST(LuaExamples, FlockingOrdersAndStaysTogetherAsTheCppFlocking) {
  const std::vector<std::string> small = {
      "arena.distribute.entity.quantity=16", "arena.distribute.position.min=-0.9,-0.9,0",
      "arena.distribute.position.max=0.9,0.9,0", "framework.experiment.length=30"};
  auto lua = Load(kLua + "flocking.argos", small);
  auto cpp = Load(COLONY_SOURCE_DIR "/experiments/flocking.xml", small);
  ASSERT_EQ(lua->robot_count(), 16u);
  EXPECT_LT(Metric(*lua, "polarisation"), 0.5) << "random headings should not start aligned";
  while (!lua->Done()) lua->Step();
  while (!cpp->Done()) cpp->Step();
  EXPECT_GT(Metric(*lua, "polarisation"), 0.9);
  EXPECT_EQ(Metric(*lua, "groups"), 1);
  EXPECT_EQ(Metric(*lua, "largest_group_fraction"), 1);
  EXPECT_NEAR(Metric(*lua, "mean_nn_distance"), Metric(*cpp, "mean_nn_distance"), 0.1);
  // The flock moved away from where it started.
  double cx = 0, cy = 0;
  const auto robots = Robots(lua->space());
  for (uint32_t s : robots) {
    cx += lua->space().pose(s).position.x() / static_cast<double>(robots.size());
    cy += lua->space().pose(s).position.y() / static_cast<double>(robots.size());
  }
  EXPECT_GT(std::hypot(cx, cy), 1.0);
}

// The camera task: robots search, see the green landmark (or a robot already
// there, lit red) and stop around it.
TEST(LuaExamples, RobotsGatherAtTheLandmarkTheirCamerasSee) {
  auto sim = Load(kLua + "landmark.argos");
  const Vec2 landmark(1.2, 1.2);
  const auto robots = Robots(sim->space());
  auto where = [&](uint32_t s) { return Vec2(sim->space().pose(s).position.head<2>()); };
  size_t near_at_start = 0;
  for (uint32_t s : robots) near_at_start += (where(s) - landmark).norm() < 1.5;
  while (!sim->Done()) sim->Step();
  std::vector<Vec2> end;
  for (uint32_t s : robots) end.push_back(where(s));
  // Another 10 s: those that gathered stay where they stopped.
  for (int t = 0; t < 100; ++t) sim->Step();
  size_t gathered = 0;
  for (size_t i = 0; i < robots.size(); ++i) {
    gathered += (end[i] - landmark).norm() < 1.5 && (where(robots[i]) - end[i]).norm() < 1e-9;
  }
  EXPECT_EQ(near_at_start, 0u);
  EXPECT_GE(gathered, robots.size() * 3 / 4) << "of " << robots.size();
}

// --- the robot table -----------------------------------------------------------------------------

// What a script sees, checked by the script itself (an error fails the run):
// ARGoS's names, 1-based arrays, cm and cm/s, exact 0 and 1 readings, the
// quaternion and vector types, plain tables, nil for undeclared devices and
// clear errors for what Colony lacks.
const char* kShapesScript = R"lua(
local function check(condition, what)
   if not condition then error("check failed: " .. what, 2) end
end
local function near(a, b, tolerance) return math.abs(a - b) <= (tolerance or 1e-6) end

ticks = 0

function init()
   check(type(robot.id) == "string", "robot.id")
   check(#robot.proximity == 24, "24 proximity readings")
   check(near(robot.proximity[1].angle, math.rad(7.5), 1e-6), "proximity[1].angle 7.5 degrees")
   check(near(robot.proximity[24].angle, -math.rad(7.5), 1e-6), "proximity[24].angle -7.5 degrees")
   check(robot.proximity[1].value == 0, "readings are 0 before the first tick")
   check(#robot.light == 24, "24 light readings")
   check(#robot.base_ground == 8 and #robot.motor_ground == 4, "8 base and 4 motor ground sensors")
   check(near(robot.base_ground[1].offset.x, 6.5) and near(robot.base_ground[1].offset.y, 0),
         "base_ground[1].offset in cm")
   check(robot.motor_ground[1].offset.x > 0 and robot.motor_ground[1].offset.y > 0,
         "motor_ground[1] front left")
   check(type(robot.wheels.set_velocity) == "function", "robot.wheels.set_velocity")
   check(robot.gripper == nil and robot.turret == nil and robot.distance_scanner == nil,
         "undeclared devices are nil")
   check(math.pow(2, 10) == 1024 and near(math.atan2(1, 1), math.pi / 4)
         and near(math.atan(1, -1), 3 * math.pi / 4) and math.ldexp(1, 3) == 8,
         "Lua 5.2 compatibility functions")
   -- Sensor tables are plain tables: fields, metatables and pairs() work.
   robot.proximity.mine = 1
   setmetatable(robot.light, {})
   local n = 0
   for _, _ in pairs(robot.base_ground) do n = n + 1 end
   check(n == 8, "pairs over robot.base_ground")
   -- What Colony lacks is an error that says so, not a nil.
   local ok, message = pcall(function() return robot.wheels.velocity_left end)
   check(not ok and message:find("robot.wheels.velocity_left is not available in Colony", 1, true),
         "velocity_left is unavailable: " .. tostring(message))
   ok, message = pcall(function() return robot.footbot_imu.angular_velocity end)
   check(not ok and message:find("robot.footbot_imu is not available in Colony", 1, true),
         "a declared device with no Lua binding: " .. tostring(message))
   ok, message = pcall(robot.leds.set_all_colors, "mauve")
   check(not ok and message:find("unknown colour 'mauve'", 1, true), "bad colour name")
   -- Math types.
   local v = vector3(1, 2, 3) + vector3(1, 1, 1) * 2
   check(v.x == 3 and v.y == 4 and v.z == 5 and near(v:length(), math.sqrt(50)), "vector3")
   check(tostring(vector2(1.5, 2)) == "1.5,2", "vector2 tostring")
   local q = quaternion(math.pi / 2, vector3(0, 0, 1))
   local r = vector3(1, 0, 0):rotate(q)
   check(near(r.x, 0) and near(r.y, 1), "vector3:rotate")
   robot.leds.set_all_colors("red")
   robot.leds.set_single_color(13, "0,255,0")
   robot.leds.set_single_color(12, 0, 0, 255)
   robot.range_and_bearing.set_data({1, 2, 3, 4})
   robot.range_and_bearing.set_data(4, 255)
end

function step()
   ticks = ticks + 1
   local position = robot.positioning.position
   local angle, axis = robot.positioning.orientation:toangleaxis()
   local yaw = robot.positioning.orientation:toeulerangles()
   if robot.id == "fb0" then
      -- At (-1, 0), facing +x; fb1 0.5 m ahead (driving away), fb2 0.6 m to the left.
      check(near(position.x, -1, 1e-3) and near(position.y, 0, 1e-3), "position in m")
      check(near(angle, 0, 1e-6) and near(yaw, 0, 1e-6), "orientation: no rotation")
      for i = 1, 24 do
         check(robot.proximity[i].value == 0, "proximity exactly 0 with nothing in range")
      end
      -- Black floor: every ground sensor reads exactly 0.
      for i = 1, 8 do check(robot.base_ground[i].value == 0, "base_ground 0 on black") end
      for i = 1, 4 do check(robot.motor_ground[i].value == 0, "motor_ground 0 on black") end
      if ticks >= 2 then
         -- Two messages (fb1, fb2), ranges in cm, bearings in rad, data 1-based.
         check(#robot.range_and_bearing == 2, "2 messages, not " .. #robot.range_and_bearing)
         local ahead, left = robot.range_and_bearing[1], robot.range_and_bearing[2]
         if ahead.horizontal_bearing > 0.1 then ahead, left = left, ahead end
         check(ahead.range > 50 and ahead.range < 56, "range ahead in cm, not " .. ahead.range)
         check(near(ahead.horizontal_bearing, 0, 1e-3) and ahead.vertical_bearing == 0, "bearing")
         check(near(left.range, 60, 0.01), "range to the left 60 cm, not " .. left.range)
         check(near(left.horizontal_bearing, math.pi / 2, 1e-3), "bearing to the left")
         check(left.data[1] == 1 and left.data[2] == 2 and left.data[3] == 3
               and left.data[4] == 255 and left.data[5] == nil, "data[1..4]")
         -- The camera, enabled at tick 1, sees the others' LEDs from tick 2 on.
         local red, green = 0, 0
         for _, blob in ipairs(robot.colored_blob_omnidirectional_camera) do
            if blob.color.red == 255 and blob.color.green == 0 then red = red + 1 end
            if blob.color.green == 255 then
               green = green + 1
               check(blob.distance > 45 and blob.distance < 65, "blob distance in cm")
            end
         end
         check(red == 2 * 11 and green == 2, "11 red LEDs and the green beacon of 2 robots, saw "
               .. red .. " and " .. green)
      else
         check(#robot.colored_blob_omnidirectional_camera == 0, "the camera starts disabled")
         robot.colored_blob_omnidirectional_camera.enable()
      end
      robot.wheels.set_velocity(0, 0)
   elseif robot.id == "fb2" then
      -- 0.5 cm from the east wall, facing it: its front sensors read exactly 1.
      if ticks >= 1 then
         check(robot.proximity[1].value == 1 and robot.proximity[24].value == 1,
               "proximity exactly 1 on contact, not " .. robot.proximity[1].value)
      end
      robot.wheels.set_velocity(0, 0)
   else
      -- fb1 drives at 10 cm/s: 1 cm a tick on each wheel's encoder.
      check(near(robot.wheels.axis_length, 14), "robot.wheels.axis_length 14 cm")
      if ticks >= 3 then
         check(near(robot.wheels.distance_left, 1, 1e-6) and
               near(robot.wheels.distance_right, 1, 1e-6),
               "encoder distances in cm: " .. robot.wheels.distance_left)
      end
      robot.wheels.set_velocity(10, 10)
   end
end
)lua";

TEST(LuaRobotTable, ArgosNamesShapesUnitsAndExactReadings) {
  const std::string xml = R"(<?xml version="1.0" ?>
<colony>
  <framework><experiment length="1" ticks_per_second="10" random_seed="1"/></framework>
  <controllers>
    <lua_controller id="lua">
      <actuators>
        <differential_steering/>
        <leds/>
        <range_and_bearing data_size="4"/>
      </actuators>
      <sensors>
        <footbot_proximity/>
        <footbot_light/>
        <footbot_base_ground/>
        <footbot_motor_ground/>
        <colored_blob_omnidirectional_camera/>
        <range_and_bearing/>
        <positioning/>
        <differential_steering/>
        <footbot_imu/>
      </sensors>
      <params script="shapes.lua"/>
    </lua_controller>
  </controllers>
  <arena size="6,6,1" center="0,0,0.5">
    <floor color="black"/>
    <box id="wall" size="0.1,0.5,0.5" movable="false"><body position="-0.86,0.6,0"/></box>
    <foot-bot id="fb0"><body position="-1,0,0" orientation="0,0,0"/><controller config="lua"/></foot-bot>
    <foot-bot id="fb1"><body position="-0.5,0,0" orientation="0,0,0"/><controller config="lua"/></foot-bot>
    <foot-bot id="fb2"><body position="-1,0.6,0" orientation="0,0,0"/><controller config="lua"/></foot-bot>
  </arena>
  <physics_engines><kinematics2d id="k2d"/></physics_engines>
</colony>
)";
  // fb2's front (x = -0.915) is 0.5 cm from the wall's face (x = -0.91).
  const fs::path dir = WriteFiles("shapes", {{"shapes.argos", xml}, {"shapes.lua", kShapesScript}});
  auto sim = Load((dir / "shapes.argos").string());
  for (int t = 0; t < 5; ++t) ASSERT_NO_THROW(sim->Step()) << "tick " << t + 1;
  fs::remove_all(dir);
}

// The foot-bot's gripper, turret encoder and distance scanner (dynamics2d
// simulates the gripper): ARGoS's tables and functions, distances in cm, -2
// with nothing in range, and the scanner's controls Colony lacks as errors.
TEST(LuaRobotTable, GripperTurretAndDistanceScanner) {
  if (!testing::HaveEngine("dynamics2d")) GTEST_SKIP() << "built without dynamics2d";
  const std::string script = R"lua(
local function check(condition, what) if not condition then error("check failed: " .. what, 2) end end
local nearest = math.huge
ticks = 0
function init()
   check(type(robot.gripper.lock_positive) == "function" and type(robot.gripper.unlock) == "function",
         "robot.gripper")
   check(robot.turret.rotation == 0 and robot.turret.set_rotation == nil,
         "robot.turret.rotation only: no footbot_turret actuator declared")
   robot.distance_scanner.enable()
   local ok, message = pcall(robot.distance_scanner.set_rpm, 60)
   check(not ok and message:find("robot.distance_scanner.set_rpm() is not available in Colony", 1, true),
         "set_rpm: " .. tostring(message))
end
function step()
   ticks = ticks + 1
   local previous = -math.huge
   for _, r in ipairs(robot.distance_scanner.short_range) do
      check(r.angle >= previous, "readings in angle order")
      previous = r.angle
      check(r.distance == -2 or r.distance > 0, "distance in cm or -2: " .. r.distance)
      if r.distance > 0 and r.distance < nearest then nearest = r.distance end
   end
   if ticks == 20 then
      -- The wall's face is 25 cm ahead of the robot's axis.
      check(math.abs(nearest - 25) < 1.5, "nearest short-range reading 25 cm, not " .. nearest)
   end
   robot.gripper.unlock()
end
)lua";
  const std::string xml =
      ArgosFile("script=\"dev.lua\"", 1, "<footbot_distance_scanner/><footbot_turret_encoder/>",
                "<differential_steering/><footbot_gripper/>");
  std::string text = xml;
  text.replace(text.find("<kinematics2d id=\"k2d\"/>"), 24, "<dynamics2d id=\"d2d\"/>");
  text.replace(text.find("</arena>"), 8,
               "<box id=\"wall\" size=\"0.1,1,0.5\" movable=\"false\">"
               "<body position=\"-0.7,0,0\"/></box></arena>");
  const fs::path dir = WriteFiles("devices", {{"exp.argos", text}, {"dev.lua", script}});
  auto sim = Load((dir / "exp.argos").string(), {"framework.experiment.length=2"});
  while (!sim->Done()) ASSERT_NO_THROW(sim->Step()) << "tick " << sim->tick() + 1;
  fs::remove_all(dir);
}

// ARGoS's footbot_turret and footbot_gripper are two devices, Colony's
// gripper actuator one: declared under both names, the turret turns to the
// angle set_rotation gives while the gripper keeps its own command, and
// footbot_encoder fills robot.wheels.encoder (cm per tick) as in ARGoS.
TEST(LuaRobotTable, TurretAndGripperDeclaredApartAndTheEncoderName) {
  if (!testing::HaveEngine("dynamics2d")) GTEST_SKIP() << "built without dynamics2d";
  const std::string script = R"lua(
local function check(condition, what) if not condition then error("check failed: " .. what, 2) end end
ticks = 0
function init()
   check(type(robot.turret.set_rotation) == "function", "robot.turret.set_rotation")
   check(type(robot.gripper.lock_positive) == "function", "robot.gripper")
   check(robot.wheels.encoder ~= nil and robot.wheels.encoder.distance_left == 0, "robot.wheels.encoder")
end
function step()
   ticks = ticks + 1
   robot.wheels.set_velocity(5, 5)
   robot.turret.set_rotation(math.pi / 2)
   robot.gripper.lock_positive()
   if ticks == 60 then
      check(math.abs(robot.turret.rotation - math.pi / 2) < 1e-6,
            "the turret reached pi/2, not " .. robot.turret.rotation)
      -- 5 cm/s for one tick of 0.1 s.
      check(math.abs(robot.wheels.encoder.distance_left - 0.5) < 0.05,
            "0.5 cm per tick on the left wheel, not " .. robot.wheels.encoder.distance_left)
   end
end
)lua";
  std::string text =
      ArgosFile("script=\"turret.lua\"", 1, "<footbot_encoder/><footbot_turret_encoder/>",
                "<differential_steering/><footbot_turret/><footbot_gripper/>");
  text.replace(text.find("<kinematics2d id=\"k2d\"/>"), 24, "<dynamics2d id=\"d2d\"/>");
  const fs::path dir = WriteFiles("turret", {{"exp.argos", text}, {"turret.lua", script}});
  auto sim = Load((dir / "exp.argos").string(), {"framework.experiment.length=6"});
  while (!sim->Done()) ASSERT_NO_THROW(sim->Step()) << "tick " << sim->tick() + 1;
  EXPECT_EQ(sim->tick(), 60);
  // The turret's half (which never grips) did not overwrite the gripper's.
  const EntityHandle robot = sim->space().Find("fb0");
  ASSERT_TRUE(robot.valid());
  EXPECT_TRUE(sim->space().Get<GripperState>(robot.index)->want_grip);
  fs::remove_all(dir);
}

// --- errors --------------------------------------------------------------------------------------

// Runs `script` (as bad.lua) on three robots; returns what `colony run` says.
Result RunScript(const std::string& name, const std::string& script,
                 const std::string& params = "script=\"bad.lua\"",
                 const std::string& sensors = "<footbot_proximity/>") {
  const fs::path dir =
      WriteFiles(name, {{"exp.argos", ArgosFile(params, 3, sensors)}, {"bad.lua", script}});
  Result r = Colony("run " + (dir / "exp.argos").string() + " --out " + (dir / "out").string());
  fs::remove_all(dir);
  return r;
}

TEST(LuaErrors, SyntaxErrorStopsTheRunNamingScriptLineAndRobot) {
  const Result r = RunScript("syntax", "function step()\n  local x = = 1\nend\n");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(testing::Mentions(r.output, {"robot 'fb0'", "bad.lua:2:", "could not be loaded"}));
}

TEST(LuaErrors, RuntimeErrorStopsTheRunNamingScriptLineAndRobot) {
  const Result r = RunScript("runtime",
                             "ticks = 0\n"
                             "function step()\n"
                             "  ticks = ticks + 1\n"
                             "  if ticks == 5 and robot.id == 'fb1' then\n"
                             "    local t = nil\n"
                             "    return t.field\n"
                             "  end\n"
                             "end\n");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(testing::Mentions(r.output, {"robot 'fb1'", "tick 5", "Lua error in step()",
                                           "bad.lua:6: attempt to index a nil value (local 't')"}));
}

TEST(LuaErrors, UnsupportedApiStopsTheRunNamingScriptLineAndRobot) {
  const Result r = RunScript("unsupported",
                             "function step()\n"
                             "  robot.wheels.set_velocity(5, 5)\n"
                             "  local v = robot.wheels.velocity_left\n"
                             "end\n",
                             "script=\"bad.lua\"", "<differential_steering/>");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(testing::Mentions(
      r.output, {"robot 'fb0'",
                 "bad.lua:3:", "robot.wheels.velocity_left is not available in Colony", "tick 1"}));
}

TEST(LuaErrors, ErrorInInitStopsTheRun) {
  const Result r = RunScript("init",
                             "function init()\n  error('no config')\nend\n"
                             "function step() end\n");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(testing::Mentions(r.output, {"robot 'fb0'", "bad.lua:2: no config", "init()"}));
}

TEST(LuaErrors, MissingScriptIsALoadErrorNamingTheFileAndLine) {
  const fs::path dir = WriteFiles("missing", {{"exp.argos", ArgosFile("script=\"nothere.lua\"")}});
  std::string message;
  try {
    Load((dir / "exp.argos").string());
  } catch (const ConfigError& e) {
    message = e.what();
  }
  // <params> is on line 7 of the file.
  EXPECT_TRUE(testing::Mentions(message, {"exp.argos:7", "script", "nothere.lua", "not found"}));
  const Result r = Colony("run " + (dir / "exp.argos").string());
  EXPECT_EQ(r.status, 2) << r.output;
  fs::remove_all(dir);
}

// The load error of an experiment whose <params> (line 7) are `params`.
std::string LoadErrorWith(const std::string& name, const std::string& params) {
  const fs::path dir = WriteFiles(name, {{"exp.argos", ArgosFile("script=\"ok.lua\" " + params)},
                                         {"ok.lua", "function step() end\n"}});
  std::string message;
  try {
    Load((dir / "exp.argos").string());
  } catch (const ConfigError& e) {
    message = e.what();
  }
  fs::remove_all(dir);
  return message;
}

TEST(LuaErrors, UnknownOnErrorValueIsALoadError) {
  EXPECT_TRUE(testing::Mentions(LoadErrorWith("onerror", "on_error=\"ignore\""),
                                {"exp.argos:7", "on_error", "ignore", "continue"}));
}

TEST(LuaErrors, UnknownLuaStateValueIsALoadError) {
  EXPECT_TRUE(testing::Mentions(LoadErrorWith("luastate", "lua_state=\"one\""),
                                {"exp.argos:7", "lua_state", "'one'", "shared", "own"}));
}

// on_error="continue": as in ARGoS, the error is logged and that robot's
// script stops (its wheels keep their last command); the others go on.
TEST(LuaErrors, ContinueOnErrorStopsOnlyThatRobotsScript) {
  const std::string script =
      "ticks = 0\n"
      "function step()\n"
      "  ticks = ticks + 1\n"
      "  if ticks == 5 and robot.id == 'fb1' then error('lost') end\n"
      "  if ticks < 10 then robot.wheels.set_velocity(5, 5)\n"
      "  else robot.wheels.set_velocity(-5, 5) end\n"  // everyone turns from tick 10 on
      "end\n";
  const fs::path dir = WriteFiles(
      "continue",
      {{"exp.argos", ArgosFile("script=\"s.lua\" on_error=\"continue\"")}, {"s.lua", script}});
  const Result r = Colony("run " + (dir / "exp.argos").string() + " --out " +
                          (dir / "out").string() + " --set framework.experiment.length=3");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(testing::Mentions(r.output, {"robot 'fb1'", "s.lua:4: lost", "script is stopped"}));

  auto sim = Load((dir / "exp.argos").string(), {"framework.experiment.length=3"});
  while (!sim->Done()) sim->Step();
  const Space& space = sim->space();
  for (const char* id : {"fb0", "fb1", "fb2"}) {
    const double yaw = YawOf(space.pose(space.Find(id).index).orientation);
    if (std::string(id) == "fb1") {
      EXPECT_NEAR(yaw, 0, 1e-9) << "its script stopped before the turn";
    } else {
      EXPECT_GT(std::abs(yaw), 0.3) << id << " should have turned";
    }
  }
  fs::remove_all(dir);
}

// --- events (docs/events.md) ---------------------------------------------------------------------

// Seed 000's latency experiment in Lua: a marXbot drives at 15 cm/s at a wall
// and asks its ring (robot.watch) for an event when a front reading rises to
// 1/3 (30 mm). on_event gets each crossing once, between the 10 Hz steps,
// and the robot stops as the C++ wall_stop does. Bus accounting counts 7 B
// per event and 61 B per step (the host refreshes robot.proximity before
// every step: a poll), none for the event calls.
// `controller`: the element's name and attributes, e.g. lua_controller id="c".
std::string WallFile(const std::string& params, const std::string& controller = "lua_controller") {
  const std::string name = controller.substr(0, controller.find(' '));
  return R"(<?xml version="1.0"?>
<colony>
  <framework><experiment length="3" ticks_per_second="200" random_seed="1"/></framework>
  <controllers>
    <)" + (controller == "lua_controller" ? controller + " id=\"c\"" : controller) +
         R"( rate="10">
      <actuators><differential_steering/></actuators>
      <sensors><proximity period="0.015" bus="true"/><light/></sensors>
      <params )" +
         params + "/>\n    </" + name + R"(>
  </controllers>
  <arena size="1.2,1.2,0.5" center="0,0,0.25">
    <box id="wall" size="0.1,1,0.2"><body position="0.385,0,0"/></box>
    <marxbot id="mb"><body position="0,0,0"/><controller config="c"/></marxbot>
  </arena>
  <physics_engines><kinematics2d id="k2d"/></physics_engines>
</colony>
)";
}

const char* kWallStopScript = R"lua(
events, stopped = 0, false
function init()
  first = robot.watch("proximity", {reading = 1, threshold = 1 / 3, crossing = "rising"})
  last = robot.watch("proximity", {reading = 24, threshold = 1 / 3, crossing = "rising"})
  assert(first == 1 and last == 2, "watch numbers " .. first .. ", " .. last)
  robot.wheels.set_velocity(15, 15)
end
function on_event(e)
  events = events + 1
  assert(e.sensor == "proximity" and e.rising == true, "a rising proximity event")
  assert((e.watch == 1 and e.reading == 1) or (e.watch == 2 and e.reading == 24),
         "watch " .. e.watch .. " reading " .. e.reading)
  assert(e.value >= 1 / 3, "value " .. e.value)
  assert(events <= 2, "event " .. events .. ": each crossing once")
  stopped = true
  robot.wheels.set_velocity(0, 0)
end
function step()
  if not stopped then robot.wheels.set_velocity(15, 15) end
end
)lua";

TEST(LuaEvents, OnEventGetsEachCrossingOnceBetweenStepsAndTheRobotStops) {
  const fs::path dir = WriteFiles(
      "events", {{"wall.xml", WallFile("script=\"stop.lua\"")}, {"stop.lua", kWallStopScript}});
  auto sim = Load((dir / "wall.xml").string());
  double x_at_2s = 0;
  while (!sim->Done()) {
    sim->Step();
    if (sim->tick() == 400) x_at_2s = sim->space().pose(sim->space().Find("mb").index).position.x();
  }
  const double x = sim->space().pose(sim->space().Find("mb").index).position.x();
  EXPECT_EQ(x, x_at_2s) << "the robot stands still once stopped";
  // Where the C++ wall_stop (controllers/e4) stops with events on the same
  // samples: 30 mm from the wall, less what it drove before the sample and
  // while slowing down.
  auto cpp = testing::LoadXml(WallFile("mode=\"events\" speed=\"0.15\" distance=\"0.03\"",
                                       "wall_stop id=\"c\" library=\"e4\""));
  while (!cpp->Done()) cpp->Step();
  EXPECT_EQ(x, cpp->space().pose(cpp->space().Find("mb").index).position.x());
  const double gap = 0.335 - x - 0.085;  // the wall's face is at 0.335; the robot's radius 0.085
  EXPECT_LT(gap, 0.03);
  EXPECT_GT(gap, 0.02);
  // 30 steps at 10 Hz over 3 s, each a poll of the ring (61 B); one or two
  // events (the two front readings may cross on the same sample) of 7 B.
  const double bus = testing::Metric(*sim, "bus_bytes");
  const double event_bytes = bus - 30 * 61;
  EXPECT_TRUE(event_bytes == 7 || event_bytes == 14) << bus;
  fs::remove_all(dir);
}

TEST(LuaEvents, BadWatchesAndAMissingOnEventStopTheRunNamingWhatIsWrong) {
  struct Case {
    const char* name;
    const char* init;
    std::vector<std::string> mentions;
  };
  const std::vector<Case> cases = {
      {"light",
       "robot.watch('light', {threshold = 0.5})",
       {"stop.lua:2:", "robot.watch: 'light' emits no events", "sensors that do: proximity"}},
      {"reading",
       "robot.watch('proximity', {reading = 25, threshold = 0.5})",
       {"stop.lua:2:", "reading 25 does not exist", "readings 1..24"}},
      {"field",
       "robot.watch('proximity', {threshold = 0.5, treshold = 1})",
       {"stop.lua:2:", "unknown field treshold", "accepted: reading, threshold"}},
      {"crossing",
       "robot.watch('proximity', {threshold = 0.5, crossing = 'up'})",
       {"stop.lua:2:", "crossing 'up' is not accepted", "rising, falling, both"}},
      {"hysteresis",
       "robot.watch('proximity', {threshold = 0.5, hysteresis = -1})",
       {"stop.lua:2:", "hysteresis must be a finite number >= 0"}},
      {"threshold",
       "robot.watch('proximity', {reading = 1})",
       {"stop.lua:2:", "needs a threshold"}},
      {"no_on_event",
       "robot.watch('proximity', {threshold = 0.2}) robot.wheels.set_velocity(15, 15)",
       {"Lua error in on_event()", "defines no global function on_event(event)", "robot 'mb'"}},
  };
  for (const Case& c : cases) {
    const std::string script =
        std::string("function init()\n  ") + c.init + "\nend\nfunction step() end\n";
    const fs::path dir =
        WriteFiles(std::string("watch_") + c.name,
                   {{"wall.xml", WallFile("script=\"stop.lua\"")}, {"stop.lua", script}});
    const Result r =
        Colony("run " + (dir / "wall.xml").string() + " --out " + (dir / "out").string());
    EXPECT_EQ(r.status, 1) << c.name << "\n" << r.output;
    EXPECT_TRUE(testing::Mentions(r.output, c.mentions)) << c.name << "\n" << r.output;
    fs::remove_all(dir);
  }
}

// Each robot's Lua objects live in its own arena (lua_alloc.cpp) and every
// robot loads the script's bytecode compiled once. Objects of every size,
// grown, shrunk and collected over several ticks on three robots, keep their
// content; a first line starting with '#' is skipped with line numbers kept,
// as luaL_loadfile does, so an error on line 23 is reported as line 23 for
// every robot.
TEST(LuaMemory, ObjectsOfEverySizeKeepTheirContentAndLinesAreKept) {
  const Result r = RunScript("memory", R"lua(#!/usr/bin/env lua
local kept = {}
local ticks = 0
function step()
   ticks = ticks + 1
   local array = {}
   for i = 1, 3000 do array[i] = i * 2 end      -- grows past the small sizes
   local hash = {}
   for i = 1, 500 do hash["k" .. i] = string.rep("x", i % 97) end
   local text = ""
   for i = 1, 300 do text = text .. string.char(65 + i % 26) end
   kept[#kept + 1] = text
   local sum = 0
   for i = 1, #array do sum = sum + array[i] end
   assert(sum == 3000 * 3001, "array lost values")
   for i = 1, 500 do assert(#hash["k" .. i] == i % 97, "string lost characters") end
   for i = 1, #kept do assert(kept[i] == text, "a kept string changed") end
   for i = #array, 1, -1 do array[i] = nil end   -- shrinks
   collectgarbage("collect")
   assert(#kept == ticks, "kept strings lost")
   if ticks == 4 and robot.id == "fb2" then
      -- line 22 is this comment: the error below is on line 23
      error("planned stop")
   end
end
)lua");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(testing::Mentions(r.output, {"robot 'fb2'", "tick 4", "bad.lua:23: planned stop"}))
      << r.output;
  EXPECT_EQ(r.output.find("lost"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("changed"), std::string::npos) << r.output;
}

// --- determinism and random numbers --------------------------------------------------------------

uint64_t FinalHash(const std::string& file, int threads) {
  auto sim = Load(file, {"framework.experiment.length=20"}, threads);
  while (!sim->Done()) sim->Step();
  return sim->StateHash();
}

TEST(LuaDeterminism, SameFinalHashWhateverTheThreadCount) {
  // landmark.lua draws from robot.random; flocking.lua reads messages and poses.
  for (const char* file : {"landmark.argos", "flocking.argos"}) {
    const uint64_t reference = FinalHash(kLua + file, 0);
    for (int threads : {1, 2}) {
      EXPECT_EQ(FinalHash(kLua + file, threads), reference) << file << ", " << threads;
    }
  }
}

// Each robot logs its draws; the lines, sorted, depend on the seed only.
// Lua seeds its string hashes from the clock and the process's addresses, so
// the stock pairs() visits string keys in an order that changes from run to
// run. Colony's pairs() visits numbers ascending, then strings in byte order,
// then false and true, whatever the run; __pairs is honoured; a field
// cleared during the traversal is skipped; pairs(nil) is the usual error.
TEST(LuaDeterminism, PairsVisitsKeysInTheSameOrderInEveryRun) {
  const Result r = RunScript("pairs", R"lua(
local function order(t)
   local seen = {}
   for k in pairs(t) do seen[#seen + 1] = tostring(k) end
   return table.concat(seen, " ")
end
local function expect(got, wanted)
   if got ~= wanted then error("order " .. got .. " instead of " .. wanted) end
end
function step()
   local names = {}
   for _, k in ipairs({"kappa", "alpha", "theta", "beta", "iota", "gamma", "eta", "delta",
                       "zeta", "epsilon"}) do names[k] = true end
   expect(order(names), "alpha beta delta epsilon eta gamma iota kappa theta zeta")
   expect(order({10, 20, 30, x = 1, b = 2, [2.5] = 3, [true] = 1, [false] = 0, [-1] = 4}),
          "-1 1 2 2.5 3 b x false true")
   local ring = {}
   for i in pairs(robot.proximity) do ring[#ring + 1] = i end
   expect(table.concat(ring, ","), table.concat({1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14,
                                                 15, 16, 17, 18, 19, 20, 21, 22, 23, 24}, ","))
   local cleared = {a = 1, b = 2, c = 3}
   local visited = {}
   for k in pairs(cleared) do
      visited[#visited + 1] = k
      cleared.b = nil
   end
   expect(table.concat(visited, " "), "a c")
   local custom = setmetatable({}, {__pairs = function(t) return next, {z = 1}, nil end})
   expect(order(custom), "z")
   local ok, message = pcall(pairs, nil)
   expect(tostring(ok) .. " " .. message:match("table expected, got nil"),
          "false table expected, got nil")
   robot.wheels.set_velocity(1, 1)
end
)lua",
                             "script=\"bad.lua\"");
  EXPECT_EQ(r.status, 0) << r.output;
}

TEST(LuaDeterminism, RandomDrawsDependOnTheSeedOnly) {
  const std::string script = R"lua(
local function check(condition, what) if not condition then error(what, 2) end end
function init()
   local r = robot.random
   local draws = {
      r.uniform(), r.uniform(5), r.uniform(2, 3), r.uniform_int(10), r.uniform_int(3, 7),
      r.gaussian(1), r.gaussian(1, 10), r.exponential(2), r.poisson(4), r.poisson(50),
      math.random(), math.random(6), math.random(-3, 3)
   }
   check(draws[1] >= 0 and draws[1] < 1 and draws[2] < 5 and draws[3] >= 2, "uniform ranges")
   check(math.type(draws[4]) == "integer" and draws[4] >= 0 and draws[4] < 10, "uniform_int(10)")
   check(draws[5] >= 3 and draws[5] < 7, "uniform_int(3, 7)")
   check(math.type(draws[9]) == "integer" and draws[10] > 10, "poisson")
   check(type(r.bernoulli()) == "boolean" and type(r.bernoulli(0.3)) == "boolean", "bernoulli")
   local ok = pcall(r.uniform_int, 5, 5)
   check(not ok, "uniform_int with an empty range is an error")
   for i = 1, #draws do draws[i] = string.format("%.12g", draws[i]) end
   log("draws ", table.concat(draws, " "))
end
function step() end
)lua";
  const fs::path dir =
      WriteFiles("random", {{"exp.argos", ArgosFile("script=\"r.lua\"", 4)}, {"r.lua", script}});
  auto draws = [&](int seed, int threads) {
    const Result r =
        Colony("run " + (dir / "exp.argos").string() + " --overwrite --out " +
               (dir / "out").string() + " --set framework.experiment.length=0.1" + " --seed " +
               std::to_string(seed) + " --threads " + std::to_string(threads));
    EXPECT_EQ(r.status, 0) << r.output;
    std::vector<std::string> lines;
    std::istringstream in(r.output);
    for (std::string line; std::getline(in, line);) {
      if (line.find("] draws ") != std::string::npos) lines.push_back(line);
    }
    std::sort(lines.begin(), lines.end());
    return lines;
  };
  const auto reference = draws(3, 1);
  ASSERT_EQ(reference.size(), 4u);
  EXPECT_NE(reference[0].substr(reference[0].find("draws")),
            reference[1].substr(reference[1].find("draws")))
      << "two robots drew the same numbers";
  EXPECT_EQ(draws(3, 2), reference);
  EXPECT_EQ(draws(3, 0), reference);
  EXPECT_NE(draws(4, 1), reference);
  fs::remove_all(dir);
}

// --- Lua states ----------------------------------------------------------------------------------

// Robots sharing a Lua state (the default) each keep a world of their own,
// as with a state per robot: their globals, their copies of the standard
// libraries (a string method one robot adds is its own), their modules'
// state, and what load() sees. Each robot checks it every tick; a breach
// stops the run with the assertion's message.
TEST(LuaStates, EachRobotKeepsItsOwnGlobalsLibrariesAndModules) {
  const std::string script = R"lua(
local counter = require("counter")
function init()
   me = robot.id
   math.mine = robot.id
   function string.owner() return robot.id end
   counter.add(#robot.id)
end
function step()
   assert(me == robot.id, "a global of another robot: " .. tostring(me))
   assert(_G.me == robot.id and _ENV == _G, "_G is not the robot's own")
   assert(math.mine == robot.id, "math changed by another robot: " .. tostring(math.mine))
   assert(("x"):owner() == robot.id, "the string method of another robot")
   assert(package.loaded.counter == counter, "package.loaded is not the robot's own")
   ticks = (ticks or 0) + 1
   counter.add(1)
   assert(counter.total() == #robot.id + ticks, "a module's state shared between robots")
   assert(load("return me")() == robot.id, "load() does not see the robot's globals")
   robot.wheels.set_velocity(1, 1)
end
)lua";
  const std::string counter =
      "local total = 0\n"
      "return { add = function(n) total = total + n end, total = function() return total end }\n";
  for (const char* mode : {"shared", "own"}) {
    const fs::path dir = WriteFiles(
        std::string("world_") + mode,
        {{"exp.argos", ArgosFile("script=\"own.lua\" lua_state=\"" + std::string(mode) + "\"", 5,
                                 "<footbot_proximity/>", "<differential_steering/>")},
         {"own.lua", script},
         {"counter.lua", counter}});
    const Result r =
        Colony("run " + (dir / "exp.argos").string() + " --out " + (dir / "out").string());
    EXPECT_EQ(r.status, 0) << mode << ": " << r.output;
    fs::remove_all(dir);
  }
}

// The thread pool hands robots out in whole multiples of 64, the robots of a
// shared state: 1,000 Lua robots (16 states) end in the same state at 0, 1
// and 2 threads, and as with a Lua state per robot.
TEST(LuaStates, SharedStatesGiveTheResultsOfAStatePerRobotAtAnyThreadCount) {
  const std::string file = COLONY_SOURCE_DIR "/experiments/lua/benchmarks/diffusion_lua_1000.xml";
  auto final_hash = [&](int threads, const std::string& mode) {
    auto sim = Load(file,
                    {"framework.experiment.length=2",
                     "controllers.lua_controller[dc].params.lua_state=" + mode},
                    threads);
    while (!sim->Done()) sim->Step();
    return sim->StateHash();
  };
  const uint64_t reference = final_hash(0, "own");
  for (int threads : {0, 1, 2}) EXPECT_EQ(final_hash(threads, "shared"), reference) << threads;
}

// --- require and relative files ------------------------------------------------------------------

// The experiment file in one folder, the script in controllers/ below it:
// require finds modules beside the script and beside the experiment file,
// io.open finds data files from the experiment file's folder, whatever the
// current directory.
TEST(LuaFiles, RequireAndRelativeFilesResolveBesideScriptAndExperiment) {
  const std::string script = R"lua(
local helper = require("helper")        -- controllers/helper.lua
local shared = require("shared")        -- shared.lua, beside the experiment file
local speed
function init()
   local f = assert(io.open("data/speed.txt"))
   speed = tonumber(f:read("l")) * helper.factor * shared.factor
   f:close()
end
function step() robot.wheels.set_velocity(speed, speed) end
)lua";
  const fs::path dir =
      WriteFiles("require", {{"exp.argos", ArgosFile("script=\"controllers/walk.lua\"", 1)},
                             {"controllers/walk.lua", script},
                             {"controllers/helper.lua", "return { factor = 2 }\n"},
                             {"shared.lua", "return { factor = 5 }\n"},
                             {"data/speed.txt", "1\n"}});
  auto sim = Load((dir / "exp.argos").string(), {"framework.experiment.length=2"});
  const Vec3 start = testing::PositionOf(*sim, "fb0");
  while (!sim->Done()) sim->Step();
  // 1 x 2 x 5 = 10 cm/s for 2 s (the first tick's command acts from the second).
  EXPECT_NEAR((testing::PositionOf(*sim, "fb0") - start).norm(), 0.19, 0.011);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace colony
