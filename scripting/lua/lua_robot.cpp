// The `robot` table: ARGoS 3.0.0-beta59's Lua names, shapes and units over
// Colony's devices (scripting/lua/README.md lists them). Colony is SI; ARGoS's
// Lua API gives distances in cm and wheel speeds in cm/s, angles in radians.
//
// Fixed-size readings (the proximity, light and ground rings, the wheel
// encoders, the turret, the battery) are written into the tables built at
// Init, in place: no allocation per step, and a script may keep references to
// them, add fields or set metatables. The rings are written through registry
// references and a pre-interned key, so a reading costs no string lookup.
// Lists that change length (camera blobs, range-and-bearing messages, the
// distance scanner's readings) get fresh entry tables every step, as in
// ARGoS: a script that keeps last step's message keeps its values.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string_view>

#include "actuators/differential_steering/differential_steering.h"
#include "actuators/gripper/gripper.h"
#include "actuators/leds/leds.h"
#include "actuators/range_and_bearing/range_and_bearing.h"
#include "scripting/lua/lua_host.h"
#include "sensors/battery/battery.h"
#include "sensors/distance_scanner/distance_scanner.h"
#include "sensors/gripper/gripper.h"
#include "sensors/ground/ground.h"
#include "sensors/light/light.h"
#include "sensors/omnidirectional_camera/omnidirectional_camera.h"
#include "sensors/positioning/positioning.h"
#include "sensors/proximity/proximity.h"
#include "sensors/range_and_bearing/range_and_bearing.h"
#include "sensors/wheel_encoders/wheel_encoders.h"

namespace colony::lua {

namespace {

constexpr double kCm = 100;  // cm per m
// Distance of the marXbot's ground sensors from its axis (sensors/ground/README.md);
// the control interface gives their angles only.
constexpr double kGroundRadiusCm = 6.5;
// ARGoS's distance scanner reading for "nothing in range".
constexpr double kScannerNothing = -2;

// The device an upvalue-carrying closure acts on.
template <class T>
T* Device(lua_State* L) {
  return static_cast<T*>(lua_touserdata(L, lua_upvalueindex(1)));
}

// robot[name], created empty (room for `array` entries) if absent, pushed;
// returns its stack index.
int OpenTable(lua_State* L, int robot, const char* name, int array = 0) {
  if (lua_getfield(L, robot, name) != LUA_TTABLE) {
    lua_pop(L, 1);
    lua_createtable(L, array, 0);
    lua_pushvalue(L, -1);
    lua_setfield(L, robot, name);
  }
  return lua_gettop(L);
}

void SetFunction(lua_State* L, int table, const char* name, lua_CFunction f, void* device) {
  lua_pushlightuserdata(L, device);
  lua_pushcclosure(L, f, 1);
  lua_setfield(L, table, name);
}

void SetNumber(lua_State* L, int table, const char* name, double value) {
  lua_pushnumber(L, value);
  lua_setfield(L, table, name);
}

// --- wheels --------------------------------------------------------------------------------------

// robot.wheels.set_velocity(left, right), cm/s.
int SetVelocity(lua_State* L) {
  if (lua_gettop(L) != 2) return luaL_error(L, "robot.wheels.set_velocity() expects 2 arguments");
  const double left = luaL_checknumber(L, 1), right = luaL_checknumber(L, 2);
  Device<DifferentialSteering>(L)->SetLinearVelocity(left / kCm, right / kCm);
  return 0;
}

// --- leds ----------------------------------------------------------------------------------------

// ARGoS's colour names and values (CColor), e.g. gray50 = 127,127,127.
std::optional<Color> NamedColor(std::string_view name) {
  struct Named {
    const char* name;
    Color color;
  };
  static const Named kNamed[] = {
      {"black", {0, 0, 0, 255}},        {"white", {255, 255, 255, 255}},
      {"red", {255, 0, 0, 255}},        {"green", {0, 255, 0, 255}},
      {"blue", {0, 0, 255, 255}},       {"magenta", {255, 0, 255, 255}},
      {"cyan", {0, 255, 255, 255}},     {"yellow", {255, 255, 0, 255}},
      {"orange", {255, 140, 0, 255}},   {"brown", {165, 42, 42, 255}},
      {"purple", {160, 32, 240, 255}},  {"gray10", {26, 26, 26, 255}},
      {"gray20", {51, 51, 51, 255}},    {"gray30", {77, 77, 77, 255}},
      {"gray40", {102, 102, 102, 255}}, {"gray50", {127, 127, 127, 255}},
      {"gray60", {153, 153, 153, 255}}, {"gray70", {179, 179, 179, 255}},
      {"gray80", {204, 204, 204, 255}}, {"gray90", {229, 229, 229, 255}},
  };
  for (const auto& n : kNamed) {
    if (name == n.name) return n.color;
  }
  return std::nullopt;
}

// A colour from the arguments at `first`: one string (a name or
// "r,g,b[,a]") or three numbers 0..255.
Color ColorArgument(lua_State* L, int first, const char* function) {
  if (lua_gettop(L) == first) {
    size_t size = 0;
    const char* text = luaL_checklstring(L, first, &size);
    if (auto named = NamedColor({text, size})) return *named;
    if (auto parsed = ParseColor({text, size})) return *parsed;
    luaL_error(L,
               "%s: unknown colour '%s'; accepted: black, white, red, green, blue, magenta, "
               "cyan, yellow, orange, brown, purple, gray10..gray90, \"r,g,b\" or \"r,g,b,a\" "
               "(0..255), or three numbers r, g, b",
               function, text);
    return Color{};
  }
  uint8_t c[3];
  for (int k = 0; k < 3; ++k) {
    const double v = luaL_checknumber(L, first + k);
    if (!(v >= 0 && v < 256)) {
      luaL_error(L, "%s: colour component %f is outside 0..255", function, v);
      return Color{};
    }
    c[k] = static_cast<uint8_t>(v);
  }
  return Color{c[0], c[1], c[2], 255};
}

// robot.leds.set_all_colors(colour) / (r, g, b).
int SetAllColors(lua_State* L) {
  const int n = lua_gettop(L);
  if (n != 1 && n != 3)
    return luaL_error(L, "robot.leds.set_all_colors() expects 1 or 3 arguments");
  Device<Leds>(L)->SetAllColors(ColorArgument(L, 1, "robot.leds.set_all_colors()"));
  return 0;
}

// robot.leds.set_single_color(i, colour) / (i, r, g, b), i from 1.
int SetSingleColor(lua_State* L) {
  const int n = lua_gettop(L);
  if (n != 2 && n != 4) {
    return luaL_error(L, "robot.leds.set_single_color() expects 2 or 4 arguments");
  }
  Leds* leds = Device<Leds>(L);
  const lua_Integer i = luaL_checkinteger(L, 1);
  if (i < 1 || i > static_cast<lua_Integer>(leds->count())) {
    return luaL_error(L, "robot.leds.set_single_color(): LED %d is out of bounds [1,%d]",
                      static_cast<int>(i), static_cast<int>(leds->count()));
  }
  leds->SetSingleColor(static_cast<size_t>(i - 1),
                       ColorArgument(L, 2, "robot.leds.set_single_color()"));
  return 0;
}

// --- range and bearing ---------------------------------------------------------------------------

uint8_t ByteArgument(lua_State* L, int index, const char* what, lua_Integer element) {
  const double v = luaL_checknumber(L, index);
  if (!(v >= 0 && v < 256)) {
    luaL_error(L, "%s: element %d is %f, outside 0..255 (a byte)", what, static_cast<int>(element),
               v);
    return 0;
  }
  return static_cast<uint8_t>(v);
}

// set_data(table of size() numbers) or set_data(i, value), i from 1.
int SetData(lua_State* L) {
  auto* rab = Device<RangeAndBearingActuator>(L);
  const auto size = static_cast<lua_Integer>(rab->size());
  if (lua_gettop(L) == 2) {
    const lua_Integer i = luaL_checkinteger(L, 1);
    if (i < 1 || i > size) {
      return luaL_error(L, "robot.range_and_bearing.set_data(): index %d out of bounds [1,%d]",
                        static_cast<int>(i), static_cast<int>(size));
    }
    rab->SetByte(static_cast<size_t>(i - 1),
                 ByteArgument(L, 2, "robot.range_and_bearing.set_data()", i));
    return 0;
  }
  if (lua_gettop(L) != 1) {
    return luaL_error(L, "robot.range_and_bearing.set_data() expects either one or two arguments");
  }
  luaL_checktype(L, 1, LUA_TTABLE);
  if (static_cast<lua_Integer>(lua_rawlen(L, 1)) != size) {
    return luaL_error(L,
                      "robot.range_and_bearing.set_data(array) expects an array of %d numbers "
                      "(the actuator's data_size), not %d",
                      static_cast<int>(size), static_cast<int>(lua_rawlen(L, 1)));
  }
  for (lua_Integer i = 1; i <= size; ++i) {
    lua_rawgeti(L, 1, i);
    if (lua_type(L, -1) != LUA_TNUMBER) {
      return luaL_error(L, "robot.range_and_bearing.set_data(): element #%d is not a number",
                        static_cast<int>(i));
    }
    rab->SetByte(static_cast<size_t>(i - 1),
                 ByteArgument(L, -1, "robot.range_and_bearing.set_data()", i));
    lua_pop(L, 1);
  }
  return 0;
}

// clear_data(): ARGoS zeroes the payload (and keeps sending it).
int ClearData(lua_State* L) {
  if (lua_gettop(L) != 0) {
    return luaL_error(L, "robot.range_and_bearing.clear_data() expects no arguments");
  }
  Device<RangeAndBearingActuator>(L)->SetData({});
  return 0;
}

// --- gripper and turret --------------------------------------------------------------------------

int Grip(lua_State* L) {
  if (lua_gettop(L) != 0) return luaL_error(L, "robot.gripper: locking expects no arguments");
  Device<GripperActuator>(L)->Grip();
  return 0;
}
int Unlock(lua_State* L) {
  if (lua_gettop(L) != 0) return luaL_error(L, "robot.gripper.unlock() expects no arguments");
  Device<GripperActuator>(L)->Release();
  return 0;
}
int SetTurretRotation(lua_State* L) {
  if (lua_gettop(L) != 1) return luaL_error(L, "robot.turret.set_rotation() expects 1 argument");
  Device<GripperActuator>(L)->SetTurretAngle(luaL_checknumber(L, 1));
  return 0;
}
// Colony's turret is always position-controlled: asking for it changes nothing.
int PositionControlMode(lua_State* L) {
  if (lua_gettop(L) != 0) {
    return luaL_error(L, "robot.turret.set_position_control_mode() expects no arguments");
  }
  return 0;
}

// --- distance scanner ----------------------------------------------------------------------------

// Colony's scanner always turns (at the sensor's scans_per_second): enabling
// it changes nothing.
int EnableScanner(lua_State* L) {
  if (lua_gettop(L) != 0) {
    return luaL_error(L, "robot.distance_scanner.enable() expects no arguments");
  }
  return 0;
}

// --- camera --------------------------------------------------------------------------------------

int EnableCamera(lua_State* L) {
  *static_cast<bool*>(lua_touserdata(L, lua_upvalueindex(1))) = true;
  return 0;
}
int DisableCamera(lua_State* L) {
  *static_cast<bool*>(lua_touserdata(L, lua_upvalueindex(1))) = false;
  return 0;
}

// --- not available -------------------------------------------------------------------------------

int RaiseUpvalue(lua_State* L) { return luaL_error(L, "%s", lua_tostring(L, lua_upvalueindex(1))); }

// robot[label] for a declared device the host has no binding for: any use
// of it raises an error that says so.
void SetUnbound(lua_State* L, int robot, const std::string& label, const char* kind) {
  lua_newtable(L);
  lua_createtable(L, 0, 1);
  const std::string message = "robot." + label +
                              " is not available in Colony: the Lua host has no binding for the " +
                              label + " " + kind + "; use it from a C++ controller";
  lua_pushlstring(L, message.data(), message.size());
  lua_pushcclosure(L, RaiseUpvalue, 1);
  lua_setfield(L, -2, "__index");
  lua_setmetatable(L, -2);
  lua_setfield(L, robot, label.c_str());
}

int UnavailableIndex(lua_State* L) {
  lua_settop(L, 2);
  lua_pushvalue(L, 2);
  if (lua_rawget(L, lua_upvalueindex(1)) == LUA_TSTRING) {
    return luaL_error(L, "%s", lua_tostring(L, -1));
  }
  lua_pushnil(L);
  return 1;
}

// Writes a ring's readings into its entry tables' "value" fields (`key`
// is that string, interned). A value is written only when it differs from
// the one written last (`written`): most readings of a swarm stay 0 from tick
// to tick, and a write costs far more than the comparison. (So a script that
// stores its own number in a reading's value keeps it until the sensor's
// reading changes; README.md says so.)
template <class Readings>
void WriteRing(lua_State* L, int table, int key, const Readings& readings,
               const std::vector<uint8_t>& source, bool threshold, std::vector<float>& written) {
  const size_t n = written.size();
  bool pushed = false;
  for (size_t j = 0; j < n; ++j) {
    const size_t k = source.empty() ? j : source[j];
    if (k >= readings.size()) continue;
    float v = readings[k].value;
    if (threshold) v = v < 0.5f ? 0.0f : 1.0f;
    if (v == written[j]) continue;
    written[j] = v;
    if (!pushed) {
      lua_rawgeti(L, LUA_REGISTRYINDEX, table);
      lua_rawgeti(L, LUA_REGISTRYINDEX, key);
      pushed = true;
    }
    if (lua_rawgeti(L, -2, static_cast<lua_Integer>(j + 1)) == LUA_TTABLE) {
      lua_pushvalue(L, -2);
      lua_pushnumber(L, v);
      lua_rawset(L, -3);
    }
    lua_pop(L, 1);
  }
  if (pushed) lua_pop(L, 2);
}

// The keys of the list entries made every step, interned once per state
// (RobotTable::PushKeys pushes them in this order) so that filling an entry
// costs no string lookup.
enum Key {
  kDistance,
  kAngle,
  kColor,
  kRed,
  kGreen,
  kBlue,
  kRange,
  kHorizontalBearing,
  kVerticalBearing,
  kData,
  kKeyCount
};
constexpr const char* kKeyNames[kKeyCount] = {
    "distance",         "angle", "color", "red", "green", "blue", "range", "horizontal_bearing",
    "vertical_bearing", "data"};

// t[key] = value, t and key stack slots.
void RawSet(lua_State* L, int t, int key, double value) {
  lua_pushvalue(L, key);
  lua_pushnumber(L, value);
  lua_rawset(L, t);
}
void RawSetInteger(lua_State* L, int t, int key, lua_Integer value) {
  lua_pushvalue(L, key);
  lua_pushinteger(L, value);
  lua_rawset(L, t);
}

// Index of the reading whose angle is nearest `angle` (rad).
template <class Reading>
uint8_t NearestAngle(const std::vector<Reading>& readings, double angle) {
  size_t best = 0;
  double best_gap = 1e9;
  for (size_t i = 0; i < readings.size(); ++i) {
    const double gap = std::abs(std::remainder(readings[i].angle - angle, 2 * M_PI));
    if (gap < best_gap) {
      best_gap = gap;
      best = i;
    }
  }
  return static_cast<uint8_t>(best);
}

}  // namespace

void PushUnavailable(lua_State* L, const std::string& what, const std::string& why) {
  const std::string message = what + " is not available in Colony: " + why;
  lua_pushlstring(L, message.data(), message.size());
  lua_pushcclosure(L, RaiseUpvalue, 1);
}

void MarkUnavailableFields(lua_State* L, const std::string& table_name,
                           const std::vector<std::pair<std::string, std::string>>& fields) {
  lua_createtable(L, 0, 1);  // the metatable
  lua_createtable(L, 0, static_cast<int>(fields.size()));
  for (const auto& [name, why] : fields) {
    const std::string message = table_name + "." + name + " is not available in Colony: " + why;
    lua_pushlstring(L, message.data(), message.size());
    lua_setfield(L, -2, name.c_str());
  }
  lua_pushcclosure(L, UnavailableIndex, 1);
  lua_setfield(L, -2, "__index");
  lua_setmetatable(L, -2);
}

// One sensor whose readings go into the robot table every step.
struct RobotTable::Binding {
  enum class Kind {
    kProximity,
    kLight,
    kGround,
    kCamera,
    kRangeAndBearing,
    kPositioning,
    kEncoders,
    kScanner,
    kTurret,
    kBattery
  };
  Kind kind;
  const Sensor* sensor = nullptr;
  int table = LUA_NOREF;        // registry reference to the table it fills
  std::vector<uint8_t> source;  // rings: the reading behind entry j (empty: reading j)
  std::vector<float> written;   // rings: the value last written into entry j
  bool threshold = false;       // base ground: 0 below 0.5, else 1 (as ARGoS's)
  // The distance scanner's readings of one tick, sorted by angle (reused).
  std::vector<std::pair<float, float>> sorted;
  // Sensors that emit events (robot.watch): the sensor, and its name there.
  Sensor* events = nullptr;
  const char* name = nullptr;
};

RobotTable::RobotTable() = default;
RobotTable::~RobotTable() = default;

void RobotTable::Build(lua_State* L, int env, const DeviceTable& devices, RandomStream* rng,
                       const std::vector<std::pair<std::string, std::string>>& params) {
  env = lua_absindex(L, env);
  lua_createtable(L, 0, 16);
  const int robot = lua_gettop(L);
  lua_pushstring(L, devices.robot_id->c_str());
  lua_setfield(L, robot, "id");
  // robot.params: every attribute of <params>, as strings (ARGoS's).
  lua_createtable(L, 0, static_cast<int>(params.size()));
  for (const auto& [key, value] : params) {
    lua_pushlstring(L, value.data(), value.size());
    lua_setfield(L, -2, key.c_str());
  }
  lua_setfield(L, robot, "params");
  RegisterRobotRandom(L, rng);
  lua_pushliteral(L, "value");
  value_key_ = luaL_ref(L, LUA_REGISTRYINDEX);
  lua_createtable(L, kKeyCount, 0);
  for (int k = 0; k < kKeyCount; ++k) {
    lua_pushstring(L, kKeyNames[k]);
    lua_rawseti(L, -2, k + 1);
  }
  keys_ = luaL_ref(L, LUA_REGISTRYINDEX);
  // Actuators first, then sensors, as ARGoS does: both may fill one table
  // (robot.wheels, robot.range_and_bearing, robot.turret).
  // Each entry is filled by one device: two would overwrite each other.
  std::vector<std::pair<std::string, std::string>> filled;  // entry, device label
  auto claim = [&](const std::vector<std::string>& entries, const std::string& label,
                   const char* kind) {
    for (const auto& entry : entries) {
      for (const auto& [other, other_label] : filled) {
        if (other != entry) continue;
        throw std::runtime_error("the " + std::string(kind) + "s '" + other_label + "' and '" +
                                 label + "' would both fill " + entry +
                                 " of the Lua robot table; declare only one of them");
      }
      filled.emplace_back(entry, label);
    }
  };
  for (size_t i = 0; i < devices.labels->actuator_labels->size(); ++i) {
    const std::string& label = (*devices.labels->actuator_labels)[i];
    claim(BindActuator(L, robot, label, devices.actuators[i]), label, "actuator");
  }
  for (size_t i = 0; i < devices.labels->sensor_labels->size(); ++i) {
    const std::string& label = (*devices.labels->sensor_labels)[i];
    claim(BindSensor(L, robot, label, devices.sensors[i]), label, "sensor");
  }
  // robot.watch (Colony's, not ARGoS's): events from sensors (docs/events.md).
  lua_pushlightuserdata(L, this);
  lua_pushcclosure(L, WatchFunction, 1);
  lua_setfield(L, robot, "watch");
  lua_setfield(L, env, "robot");
}

void RobotTable::HotObjects(lua_State* L, std::vector<const void*>& out) const {
  out.push_back(this);
  out.push_back(bindings_.data());
  for (const Binding& b : bindings_) {
    if (!b.written.empty()) out.push_back(b.written.data());
  }
  for (const Binding& b : bindings_) {
    if (b.written.empty()) continue;  // not a ring
    lua_rawgeti(L, LUA_REGISTRYINDEX, b.table);
    for (size_t j = 0; j < b.written.size(); ++j) {
      lua_rawgeti(L, -1, static_cast<lua_Integer>(j + 1));
      out.push_back(lua_topointer(L, -1));
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
  }
}

void RobotTable::Release(lua_State* L) {
  for (Binding& b : bindings_) {
    luaL_unref(L, LUA_REGISTRYINDEX, b.table);
    b.table = LUA_NOREF;
  }
  luaL_unref(L, LUA_REGISTRYINDEX, value_key_);
  luaL_unref(L, LUA_REGISTRYINDEX, keys_);
  value_key_ = keys_ = LUA_NOREF;
}

std::vector<std::string> RobotTable::BindActuator(lua_State* L, int robot, const std::string& label,
                                                  Actuator* actuator) {
  const int top = lua_gettop(L);
  std::vector<std::string> claims;
  if (auto* wheels = dynamic_cast<DifferentialSteering*>(actuator)) {
    claims = {"robot.wheels.set_velocity"};
    const int t = OpenTable(L, robot, "wheels");
    SetFunction(L, t, "set_velocity", SetVelocity, wheels);
  } else if (auto* leds = dynamic_cast<Leds*>(actuator)) {
    claims = {"robot.leds"};
    const int t = OpenTable(L, robot, "leds");
    SetFunction(L, t, "set_all_colors", SetAllColors, leds);
    SetFunction(L, t, "set_single_color", SetSingleColor, leds);
  } else if (auto* rab = dynamic_cast<RangeAndBearingActuator*>(actuator)) {
    claims = {"robot.range_and_bearing.set_data"};
    const int t = OpenTable(L, robot, "range_and_bearing");
    SetFunction(L, t, "set_data", SetData, rab);
    SetFunction(L, t, "clear_data", ClearData, rab);
  } else if (auto* gripper = dynamic_cast<GripperActuator*>(actuator)) {
    // Colony's gripper actuator is ARGoS's footbot_gripper and footbot_turret
    // in one; an ARGoS name fills only its own table.
    if (label != "footbot_turret") {
      claims.push_back("robot.gripper");
      const int t = OpenTable(L, robot, "gripper");
      SetFunction(L, t, "lock_positive", Grip, gripper);
      SetFunction(L, t, "lock_negative", Grip, gripper);
      SetFunction(L, t, "unlock", Unlock, gripper);
      lua_settop(L, top);
    }
    if (label != "footbot_gripper") {
      claims.push_back("robot.turret.set_rotation");
      const int t = OpenTable(L, robot, "turret");
      SetFunction(L, t, "set_rotation", SetTurretRotation, gripper);
      SetFunction(L, t, "set_position_control_mode", PositionControlMode, gripper);
      const char* why =
          "Colony's turret always turns to the angle given to set_rotation, at its own speed";
      for (const char* name :
           {"set_rotation_speed", "set_speed_control_mode", "set_passive_mode"}) {
        PushUnavailable(L, std::string("robot.turret.") + name + "()", why);
        lua_setfield(L, t, name);
      }
    }
  } else {
    SetUnbound(L, robot, label, "actuator");
  }
  lua_settop(L, top);
  return claims;
}

std::vector<std::string> RobotTable::BindSensor(lua_State* L, int robot, const std::string& label,
                                                Sensor* sensor) {
  const int top = lua_gettop(L);
  Binding b;
  std::string claim;
  b.sensor = sensor;
  // Ring entries {value, angle} (proximity, light) or {value, offset}
  // (ground), from `readings`, the entries listed in b.source.
  auto ring = [&](const char* name, const auto& readings, bool offsets) {
    const size_t n = b.source.empty() ? readings.size() : b.source.size();
    const int t = OpenTable(L, robot, name, static_cast<int>(n));
    for (size_t j = 0; j < n; ++j) {
      const auto& r = readings[b.source.empty() ? j : b.source[j]];
      lua_createtable(L, 0, 2);
      if (offsets) {
        PushVector2(L, kGroundRadiusCm * std::cos(r.angle), kGroundRadiusCm * std::sin(r.angle));
        lua_setfield(L, -2, "offset");
      } else {
        SetNumber(L, lua_gettop(L), "angle", r.angle);
      }
      float v = r.value;
      if (b.threshold) v = v < 0.5f ? 0.0f : 1.0f;
      b.written.push_back(v);
      SetNumber(L, lua_gettop(L), "value", v);
      lua_rawseti(L, t, static_cast<lua_Integer>(j + 1));
    }
    lua_pushvalue(L, t);
    b.table = luaL_ref(L, LUA_REGISTRYINDEX);
  };
  if (auto* proximity = dynamic_cast<ProximitySensor*>(sensor)) {
    b.kind = Binding::Kind::kProximity;
    claim = "robot.proximity";
    ring("proximity", proximity->readings(), false);
    b.events = proximity;
    b.name = "proximity";
  } else if (auto* light = dynamic_cast<LightSensor*>(sensor)) {
    b.kind = Binding::Kind::kLight;
    claim = "robot.light";
    ring("light", light->readings(), false);
  } else if (auto* ground = dynamic_cast<GroundSensor*>(sensor)) {
    b.kind = Binding::Kind::kGround;
    const auto& readings = ground->readings();
    if (label == "footbot_motor_ground") {
      // ARGoS's 4 motor ground sensors (front-left, back-left, back-right,
      // front-right) read from the ring's sensors nearest those quadrants.
      for (double deg : {45.0, 135.0, -135.0, -45.0})
        b.source.push_back(NearestAngle(readings, deg * M_PI / 180));
      claim = "robot.motor_ground";
      ring("motor_ground", readings, true);
    } else if (label == "footbot_base_ground") {
      b.threshold = true;
      claim = "robot.base_ground";
      ring("base_ground", readings, true);
    } else {
      claim = "robot.ground";
      ring("ground", readings, true);
    }
  } else if (dynamic_cast<OmnidirectionalCamera*>(sensor)) {
    b.kind = Binding::Kind::kCamera;
    claim = "robot.colored_blob_omnidirectional_camera";
    const int t = OpenTable(L, robot, "colored_blob_omnidirectional_camera");
    SetFunction(L, t, "enable", EnableCamera, &camera_enabled_);
    SetFunction(L, t, "disable", DisableCamera, &camera_enabled_);
    b.table = luaL_ref(L, LUA_REGISTRYINDEX);
  } else if (dynamic_cast<RangeAndBearingSensor*>(sensor)) {
    b.kind = Binding::Kind::kRangeAndBearing;
    claim = "robot.range_and_bearing (readings)";
    OpenTable(L, robot, "range_and_bearing");
    b.table = luaL_ref(L, LUA_REGISTRYINDEX);
  } else if (auto* positioning = dynamic_cast<PositioningSensor*>(sensor)) {
    b.kind = Binding::Kind::kPositioning;
    claim = "robot.positioning";
    lua_createtable(L, 0, 2);
    PushVector3(L, positioning->x(), positioning->y(), positioning->z());
    lua_setfield(L, -2, "position");
    PushYawQuaternion(L, positioning->yaw());
    lua_setfield(L, -2, "orientation");
    lua_pushvalue(L, -1);
    lua_setfield(L, robot, "positioning");
    b.table = luaL_ref(L, LUA_REGISTRYINDEX);
  } else if (auto* encoders = dynamic_cast<WheelEncoders*>(sensor)) {
    b.kind = Binding::Kind::kEncoders;
    const int wheels = OpenTable(L, robot, "wheels");
    // ARGoS's footbot_encoder fills robot.wheels.encoder; its
    // differential_steering sensor (and Colony's wheel_encoders) robot.wheels.
    const bool nested = label == "footbot_encoder";
    claim = nested ? "robot.wheels.encoder" : "robot.wheels.distance_left";
    int t = wheels;
    if (nested) {
      lua_newtable(L);
      lua_pushvalue(L, -1);
      lua_setfield(L, wheels, "encoder");
      t = lua_gettop(L);
    }
    SetNumber(L, t, "distance_left", encoders->distance_left() * kCm);
    SetNumber(L, t, "distance_right", encoders->distance_right() * kCm);
    SetNumber(L, t, "axis_length", encoders->wheel_base() * kCm);
    if (!nested) {
      const std::string why =
          "Colony's wheel encoders give the distance each wheel moved during the last tick "
          "(robot.wheels.distance_left/right, cm); divide it by the tick length (1 / "
          "ticks_per_second) for cm/s";
      lua_pushvalue(L, t);
      MarkUnavailableFields(L, "robot.wheels", {{"velocity_left", why}, {"velocity_right", why}});
      lua_pop(L, 1);
    }
    lua_pushvalue(L, t);
    b.table = luaL_ref(L, LUA_REGISTRYINDEX);
  } else if (dynamic_cast<DistanceScanner*>(sensor)) {
    b.kind = Binding::Kind::kScanner;
    claim = "robot.distance_scanner";
    const int t = OpenTable(L, robot, "distance_scanner");
    lua_newtable(L);
    lua_setfield(L, t, "short_range");
    lua_newtable(L);
    lua_setfield(L, t, "long_range");
    SetFunction(L, t, "enable", EnableScanner, nullptr);
    const char* why =
        "Colony's distance scanner always turns, at the scans_per_second given to the sensor in "
        "the experiment file";
    for (const char* name : {"disable", "set_angle", "set_rpm"}) {
      PushUnavailable(L, std::string("robot.distance_scanner.") + name + "()", why);
      lua_setfield(L, t, name);
    }
    lua_pushvalue(L, t);
    b.table = luaL_ref(L, LUA_REGISTRYINDEX);
  } else if (auto* gripper = dynamic_cast<GripperSensor*>(sensor)) {
    b.kind = Binding::Kind::kTurret;
    claim = "robot.turret.rotation";
    const int t = OpenTable(L, robot, "turret");
    SetNumber(L, t, "rotation", gripper->turret_angle());
    b.table = luaL_ref(L, LUA_REGISTRYINDEX);
  } else if (auto* battery = dynamic_cast<Battery*>(sensor)) {
    b.kind = Binding::Kind::kBattery;
    claim = "robot.battery";
    const int t = OpenTable(L, robot, "battery");
    SetNumber(L, t, "available_charge", battery->level());
    MarkUnavailableFields(L, "robot.battery",
                          {{"time_left",
                            "Colony's battery gives its charge (robot.battery.available_charge, "
                            "0..1), not an estimate of the time left"}});
    b.table = luaL_ref(L, LUA_REGISTRYINDEX);
  } else {
    SetUnbound(L, robot, label, "sensor");
    lua_settop(L, top);
    return {};
  }
  lua_settop(L, top);
  bindings_.push_back(std::move(b));
  return {claim};
}

// --- events: robot.watch and on_event
// -------------------------------------------------------------

std::string RobotTable::AddWatch(const std::string& name, ThresholdWatch spec, bool each,
                                 long long lua_reading, int* number) {
  const Binding* binding = nullptr;
  for (const Binding& b : bindings_) {
    if (b.events && name == b.name) binding = &b;
  }
  if (binding == nullptr) {
    bool declared = false;
    for (const Binding& b : bindings_) declared = declared || b.events != nullptr;
    return "robot.watch: '" + name + "' emits no events; sensors that do: proximity" +
           (declared ? std::string()
                     : std::string(" (not declared for this robot: add footbot_proximity or "
                                   "proximity to the controller's <sensors>)"));
  }
  const int count = static_cast<int>(binding->written.size());  // the entries Lua sees
  if (!each && (lua_reading < 1 || lua_reading > count)) {
    return "robot.watch: reading " + std::to_string(lua_reading) + " does not exist; robot." +
           name + " has readings 1.." + std::to_string(count) + " (or leave reading out: each)";
  }
  const int n = ++watch_count_;
  try {
    if (binding->source.empty() || !each) {
      if (!each) {
        spec.reading = binding->source.empty() ? lua_reading - 1 : binding->source[lua_reading - 1];
      }
      watches_.push_back({binding->sensor, binding->events->Watch(spec), n});
    } else {
      for (uint8_t reading : binding->source) {
        spec.reading = reading;
        watches_.push_back({binding->sensor, binding->events->Watch(spec), n});
      }
    }
  } catch (const std::invalid_argument& e) {
    --watch_count_;
    std::string message = e.what();
    if (message.rfind("Watch: ", 0) == 0) message.erase(0, 7);
    return "robot.watch: " + message;
  }
  *number = n;
  return {};
}

// robot.watch(sensor, {reading = i, threshold = t, crossing = "rising" |
// "falling" | "both", hysteresis = h}): returns the watch's number (1, 2, ...).
int RobotTable::WatchFunction(lua_State* L) {
  auto* self = static_cast<RobotTable*>(lua_touserdata(L, lua_upvalueindex(1)));
  const char* name = luaL_checkstring(L, 1);
  luaL_checktype(L, 2, LUA_TTABLE);
  lua_pushnil(L);
  while (lua_next(L, 2) != 0) {
    lua_pop(L, 1);
    const char* key = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : nullptr;
    bool known = false;
    for (const char* k : {"reading", "threshold", "crossing", "hysteresis"}) {
      known = known || (key && std::strcmp(key, k) == 0);
    }
    if (!known) {
      return luaL_error(L,
                        "robot.watch: unknown field %s in the watch; accepted: reading, "
                        "threshold, crossing, hysteresis",
                        key ? key : luaL_typename(L, -1));
    }
  }
  ThresholdWatch spec;
  bool each = true;
  long long lua_reading = 0;
  if (lua_getfield(L, 2, "reading") != LUA_TNIL) {
    int exact = 0;
    lua_reading = lua_tointegerx(L, -1, &exact);
    if (!exact) return luaL_error(L, "robot.watch: reading must be a whole number (1-based)");
    each = false;
  }
  if (lua_getfield(L, 2, "threshold") != LUA_TNUMBER) {
    return luaL_error(L, "robot.watch: the watch needs a threshold (a number)");
  }
  spec.threshold = lua_tonumber(L, -1);
  switch (lua_getfield(L, 2, "hysteresis")) {
    case LUA_TNIL:
      break;
    case LUA_TNUMBER:
      spec.hysteresis = lua_tonumber(L, -1);
      break;
    default:
      return luaL_error(L, "robot.watch: hysteresis must be a number >= 0");
  }
  if (lua_getfield(L, 2, "crossing") != LUA_TNIL) {
    const char* c = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : "";
    if (std::strcmp(c, "rising") == 0) {
      spec.crossing = Crossing::kRising;
    } else if (std::strcmp(c, "falling") == 0) {
      spec.crossing = Crossing::kFalling;
    } else if (std::strcmp(c, "both") != 0) {
      return luaL_error(L,
                        "robot.watch: crossing '%s' is not accepted; accepted: rising, "
                        "falling, both",
                        lua_type(L, -1) == LUA_TSTRING ? c : luaL_typename(L, -1));
    }
  }
  int number = 0;
  bool failed = false;
  {
    const std::string error = self->AddWatch(name, spec, each, lua_reading, &number);
    failed = !error.empty();
    if (failed) lua_pushlstring(L, error.data(), error.size());
  }
  if (failed) return lua_error(L);  // no C++ object alive from here
  lua_pushinteger(L, number);
  return 1;
}

bool RobotTable::PushEvent(lua_State* L, const SensorEvent& event) const {
  const WatchRecord* record = nullptr;
  for (const WatchRecord& w : watches_) {
    if (w.sensor == event.sensor && w.sensor_watch == event.watch) record = &w;
  }
  if (record == nullptr) return false;
  const Binding* binding = nullptr;
  for (const Binding& b : bindings_) {
    if (b.sensor == event.sensor) binding = &b;
  }
  if (binding == nullptr) return false;
  int reading = event.reading + 1;
  if (!binding->source.empty()) {
    const auto at = std::find(binding->source.begin(), binding->source.end(), event.reading);
    if (at == binding->source.end()) return false;
    reading = static_cast<int>(at - binding->source.begin()) + 1;
  }
  lua_createtable(L, 0, 5);
  lua_pushstring(L, binding->name);
  lua_setfield(L, -2, "sensor");
  lua_pushinteger(L, record->number);
  lua_setfield(L, -2, "watch");
  lua_pushinteger(L, reading);
  lua_setfield(L, -2, "reading");
  // As the ring's entries hold it (a float), so it equals robot.proximity[i].value.
  lua_pushnumber(L, static_cast<float>(event.value));
  lua_setfield(L, -2, "value");
  lua_pushboolean(L, event.rising);
  lua_setfield(L, -2, "rising");
  return true;
}

int RobotTable::PushKeys(lua_State* L) const {
  const int first = lua_gettop(L) + 1;
  lua_rawgeti(L, LUA_REGISTRYINDEX, keys_);
  for (int k = 0; k < kKeyCount; ++k) lua_rawgeti(L, first, k + 1);
  lua_remove(L, first);
  return first;
}

// Refills the list at stack index `list` with one fresh table of `fields`
// fields per item, as ARGoS makes these lists anew each step (a script
// keeping an old entry keeps its values): fill(entry, key, item) sets an
// entry's fields, `key` the stack index of the interned keys (PushKeys).
// Entries beyond the new count are cleared; the stack is left below `list`.
template <class Items, class Fill>
void RefillList(lua_State* L, int list, int key, const Items& items, int fields, Fill fill) {
  const lua_Integer old = static_cast<lua_Integer>(lua_rawlen(L, list));
  lua_Integer i = 0;
  for (const auto& item : items) {
    lua_createtable(L, 0, fields);
    fill(lua_gettop(L), key, item);
    lua_rawseti(L, list, ++i);
  }
  for (lua_Integer k = i + 1; k <= old; ++k) {
    lua_pushnil(L);
    lua_rawseti(L, list, k);
  }
  lua_settop(L, list - 1);
}

void RobotTable::Update(lua_State* L) {
  for (Binding& b : bindings_) {
    switch (b.kind) {
      case Binding::Kind::kProximity:
        WriteRing(L, b.table, value_key_, static_cast<const ProximitySensor*>(b.sensor)->readings(),
                  b.source, false, b.written);
        break;
      case Binding::Kind::kLight:
        WriteRing(L, b.table, value_key_, static_cast<const LightSensor*>(b.sensor)->readings(),
                  b.source, false, b.written);
        break;
      case Binding::Kind::kGround:
        WriteRing(L, b.table, value_key_, static_cast<const GroundSensor*>(b.sensor)->readings(),
                  b.source, b.threshold, b.written);
        break;
      case Binding::Kind::kCamera: {
        if (!camera_enabled_) break;  // as ARGoS: a disabled camera keeps its last blobs
        lua_rawgeti(L, LUA_REGISTRYINDEX, b.table);
        const int list = lua_gettop(L);
        RefillList(L, list, PushKeys(L),
                   static_cast<const OmnidirectionalCamera*>(b.sensor)->blobs(), 3,
                   [L](int entry, int key, const auto& blob) {
                     RawSet(L, entry, key + kDistance, blob.distance * kCm);
                     RawSet(L, entry, key + kAngle, blob.bearing);
                     lua_pushvalue(L, key + kColor);
                     lua_createtable(L, 0, 3);
                     RawSetInteger(L, entry + 2, key + kRed, blob.red);
                     RawSetInteger(L, entry + 2, key + kGreen, blob.green);
                     RawSetInteger(L, entry + 2, key + kBlue, blob.blue);
                     lua_rawset(L, entry);
                   });
        break;
      }
      case Binding::Kind::kRangeAndBearing: {
        lua_rawgeti(L, LUA_REGISTRYINDEX, b.table);
        const int list = lua_gettop(L);
        RefillList(L, list, PushKeys(L),
                   static_cast<const RangeAndBearingSensor*>(b.sensor)->packets(), 4,
                   [L](int entry, int key, const auto& p) {
                     RawSet(L, entry, key + kRange, p.range * kCm);
                     RawSet(L, entry, key + kHorizontalBearing, p.bearing);
                     RawSet(L, entry, key + kVerticalBearing, p.elevation);
                     lua_pushvalue(L, key + kData);
                     lua_createtable(L, static_cast<int>(p.data.size()), 0);
                     for (size_t k = 0; k < p.data.size(); ++k) {
                       lua_pushinteger(L, p.data[k]);
                       lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
                     }
                     lua_rawset(L, entry);
                   });
        break;
      }
      case Binding::Kind::kPositioning: {
        const auto* p = static_cast<const PositioningSensor*>(b.sensor);
        lua_rawgeti(L, LUA_REGISTRYINDEX, b.table);
        PushVector3(L, p->x(), p->y(), p->z());
        lua_setfield(L, -2, "position");
        PushYawQuaternion(L, p->yaw());
        lua_setfield(L, -2, "orientation");
        lua_pop(L, 1);
        break;
      }
      case Binding::Kind::kEncoders: {
        const auto* e = static_cast<const WheelEncoders*>(b.sensor);
        lua_rawgeti(L, LUA_REGISTRYINDEX, b.table);
        SetNumber(L, lua_gettop(L), "distance_left", e->distance_left() * kCm);
        SetNumber(L, lua_gettop(L), "distance_right", e->distance_right() * kCm);
        SetNumber(L, lua_gettop(L), "axis_length", e->wheel_base() * kCm);
        lua_pop(L, 1);
        break;
      }
      case Binding::Kind::kScanner: {
        const auto* s = static_cast<const DistanceScanner*>(b.sensor);
        lua_rawgeti(L, LUA_REGISTRYINDEX, b.table);
        for (auto type : {DistanceScanner::kShortRange, DistanceScanner::kLongRange}) {
          b.sorted.clear();
          for (const auto& r : s->readings()) {
            if (r.type == type) b.sorted.emplace_back(r.angle, r.distance);
          }
          std::sort(b.sorted.begin(), b.sorted.end());
          lua_createtable(L, static_cast<int>(b.sorted.size()), 0);
          for (size_t k = 0; k < b.sorted.size(); ++k) {
            lua_createtable(L, 0, 2);
            SetNumber(L, lua_gettop(L), "angle", b.sorted[k].first);
            const float d = b.sorted[k].second;
            SetNumber(L, lua_gettop(L), "distance",
                      d == DistanceScanner::kNoReading ? kScannerNothing : d * kCm);
            lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
          }
          lua_setfield(L, -2, type == DistanceScanner::kShortRange ? "short_range" : "long_range");
        }
        lua_pop(L, 1);
        break;
      }
      case Binding::Kind::kTurret:
        lua_rawgeti(L, LUA_REGISTRYINDEX, b.table);
        SetNumber(L, lua_gettop(L), "rotation",
                  static_cast<const GripperSensor*>(b.sensor)->turret_angle());
        lua_pop(L, 1);
        break;
      case Binding::Kind::kBattery:
        lua_rawgeti(L, LUA_REGISTRYINDEX, b.table);
        SetNumber(L, lua_gettop(L), "available_charge",
                  static_cast<const Battery*>(b.sensor)->level());
        lua_pop(L, 1);
        break;
    }
  }
}

}  // namespace colony::lua
