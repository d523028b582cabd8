// Internals of the Lua controller host (scripting/lua/README.md): the pieces
// of ARGoS's Lua API that lua_controller.cpp puts into each robot's Lua
// state. Not a public header.
//
// Lua raises errors with longjmp, which skips C++ destructors: a function
// called from Lua (a lua_CFunction here) must have no live object with a
// destructor when it raises (luaL_error, luaL_check*, lua_error).
#pragma once

#include <cstdint>
#include <lua.hpp>
#include <string>
#include <vector>

#include "core/control_interface.h"

namespace colony::lua {

// --- vector2, vector3, quaternion (lua_types.cpp) ------------------------------------------------
// ARGoS's math types as userdata with its metatables: the global constructors
// vector2(), vector3(), quaternion() and their methods and operators.
void RegisterMathTypes(lua_State* L);
void PushVector2(lua_State* L, double x, double y);
void PushVector3(lua_State* L, double x, double y, double z);
void PushQuaternion(lua_State* L, double w, double x, double y, double z);
// The rotation of `yaw` (rad) about the vertical axis.
void PushYawQuaternion(lua_State* L, double yaw);

// --- random numbers (lua_random.cpp) -------------------------------------------------------------
// robot.random (into the table on top of the stack), drawing from `stream`,
// which must outlive the Lua state.
void RegisterRobotRandom(lua_State* L, RandomStream* stream);
// math.random and math.randomseed of the robot's environment at stack index
// `env` (its own copy of `math`) drawing from `stream` instead of the C
// library's process-wide generator (whose sequence would depend on how
// threads interleave). `robot_id` is mixed into math.randomseed's seeds.
void ReplaceMathRandom(lua_State* L, int env, RandomStream* stream, const std::string& robot_id);

// --- helpers -------------------------------------------------------------------------------------
// Pushes a C closure that raises "`what` is not available in Colony: `why`".
void PushUnavailable(lua_State* L, const std::string& what, const std::string& why);
// Gives the table on top of the stack a metatable whose __index raises for
// the names in `fields` ({name, why}) and returns nil for any other name.
void MarkUnavailableFields(lua_State* L, const std::string& table_name,
                           const std::vector<std::pair<std::string, std::string>>& fields);

// --- the robot table (lua_robot.cpp) -------------------------------------------------------------
// The `robot` table of one robot: built once from its declared devices,
// refreshed in place before every step.
class RobotTable {
 public:
  RobotTable();
  ~RobotTable();
  RobotTable(const RobotTable&) = delete;
  RobotTable& operator=(const RobotTable&) = delete;

  // Builds `robot` in the robot's environment (the table at stack index
  // `env`): id, params, random, then one entry per declared device. Throws
  // std::runtime_error when two devices would fill the same entry.
  void Build(lua_State* L, int env, const DeviceTable& devices, RandomStream* rng,
             const std::vector<std::pair<std::string, std::string>>& params);
  // Appends the addresses of the tables a step reads (the rings' entries),
  // for prefetching.
  void HotObjects(lua_State* L, std::vector<const void*>& out) const;
  // Drops the registry references Build made (the state lives on with other
  // robots in it).
  void Release(lua_State* L);
  // Writes this tick's sensor readings into the tables.
  void Update(lua_State* L);
  // Pushes the Lua table of `event` ({sensor, watch, reading, value,
  // rising}) and returns true; returns false, pushing nothing, when the
  // event is not from a watch this table made (robot.watch).
  bool PushEvent(lua_State* L, const SensorEvent& event) const;

 private:
  struct Binding;
  // Each fills robot entries from one device; returns the entries it fills.
  std::vector<std::string> BindSensor(lua_State* L, int robot, const std::string& label,
                                      Sensor* sensor);
  std::vector<std::string> BindActuator(lua_State* L, int robot, const std::string& label,
                                        Actuator* actuator);
  // Pushes the interned keys of list entries (kKeyNames in lua_robot.cpp);
  // returns the stack slot of the first.
  int PushKeys(lua_State* L) const;
  // robot.watch(sensor, spec) (docs/events.md): the C function and what it
  // does, without raising (returns an error message, or "" and the watch's
  // number).
  static int WatchFunction(lua_State* L);
  std::string AddWatch(const std::string& name, ThresholdWatch spec, bool each,
                       long long lua_reading, int* number);
  // One watch the sensor made for robot.watch: the sensor's number for it
  // and the Lua watch number it stands for (a watch of each reading of a
  // ring that Lua sees only part of is one sensor watch per reading).
  struct WatchRecord {
    const Sensor* sensor;
    int sensor_watch;
    int number;
  };
  std::vector<WatchRecord> watches_;
  int watch_count_ = 0;
  std::vector<Binding> bindings_;
  int value_key_ = LUA_NOREF;  // the interned string "value", for the rings
  int keys_ = LUA_NOREF;       // a table of the list entries' keys
  bool camera_enabled_ = false;
};

}  // namespace colony::lua
