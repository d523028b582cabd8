// The Lua controller host: <lua_controller> with <params script="x.lua"/>,
// ARGoS 3.0.0-beta59's Lua API on Lua 5.3 (scripting/lua/README.md).
//
// One Lua state per robot, so robots share nothing and each thread steps its
// own robots' states. As in ARGoS, the script's top level runs once, then its
// init(); step() every tick after the sensors are read and written into the
// robot table; reset() on reset; destroy() at the end.
//
// Errors. A script that cannot start (missing file: a load error at its
// <params>; a syntax error, an error in its top level or in init(), no step()
// function) stops the run at its first tick, with exit status 1, naming the
// script, the line and the robot. ARGoS stops too. An error in step(),
// reset() or destroy() stops the run by default; with
// <params on_error="continue"/> it is logged and that robot's script stops
// (its actuators keep their last commands), as ARGoS does.
#include <sys/stat.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "core/log.h"
#include "core/registry.h"
#include "scripting/lua/lua_alloc.h"
#include "scripting/lua/lua_host.h"

namespace colony::lua {
namespace {

// Message handler for lua_pcall: the error with the Lua part of the stack.
int Traceback(lua_State* L) {
  const char* message = lua_tostring(L, 1);
  if (message == nullptr) {
    if (luaL_callmeta(L, 1, "__tostring") && lua_type(L, -1) == LUA_TSTRING) return 1;
    message = lua_pushfstring(L, "(error object is a %s value)", luaL_typename(L, 1));
  }
  luaL_traceback(L, L, message, 1);
  return 1;
}

// The traceback trimmed to the script's frames and indented, so that it reads
// as part of Colony's one error message.
std::string Tidy(const std::string& text) {
  std::string out;
  size_t start = 0;
  while (start <= text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(start, end - start);
    start = end + 1;
    if (out.empty()) {
      out = line;
      continue;
    }
    if (line.rfind("\t[C]:", 0) == 0 || line.find("(...tail calls...)") != std::string::npos)
      continue;
    if (line == "stack traceback:") {
      out += "\n  stack traceback:";
    } else if (!line.empty() && line[0] == '\t') {
      out += "\n    " + line.substr(1);
    } else {
      out += "\n" + line;
    }
  }
  // A traceback with no Lua frame says nothing.
  const std::string empty = "\n  stack traceback:";
  if (out.size() >= empty.size() &&
      out.compare(out.size() - empty.size(), empty.size(), empty) == 0)
    out.resize(out.size() - empty.size());
  return out;
}

// Appends what lua_dump writes to a std::string.
int AppendChunk(lua_State*, const void* data, size_t size, void* out) {
  try {
    static_cast<std::string*>(out)->append(static_cast<const char*>(data), size);
    return 0;
  } catch (const std::bad_alloc&) {
    return 1;  // lua_dump stops
  }
}

// Loads the script at `path` as luaL_loadfile does (a first line starting
// with '#' is skipped, line numbers kept), compiling it once per process and
// content: the other robots load the same bytecode, debug information
// included (errors still name the script's lines). That spares every state
// the parser's time and the garbage it leaves behind.
int LoadScript(lua_State* L, const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) return luaL_loadfile(L, path.c_str());  // says why
  static std::mutex mutex;
  static std::map<std::string, std::pair<std::string, std::string>> compiled;  // text, bytecode
  const std::string name = "@" + path;
  {
    std::lock_guard<std::mutex> lock(mutex);
    const auto it = compiled.find(path);
    if (it != compiled.end() && it->second.first == text)
      return luaL_loadbufferx(L, it->second.second.data(), it->second.second.size(), name.c_str(),
                              "b");
  }
  std::string source = text;
  if (source.compare(0, 3, "\xEF\xBB\xBF") == 0) source.erase(0, 3);  // a UTF-8 mark
  if (!source.empty() && source[0] == '#') source.erase(0, source.find('\n'));
  const int status = luaL_loadbufferx(L, source.data(), source.size(), name.c_str(), nullptr);
  if (status != LUA_OK || source.empty() || source[0] == LUA_SIGNATURE[0]) return status;
  std::string bytecode;
  if (lua_dump(L, AppendChunk, &bytecode, 0) != 0) return status;
  std::lock_guard<std::mutex> lock(mutex);
  compiled[path] = {std::move(text), std::move(bytecode)};
  return status;
}

// log(...) and logerr(...): the arguments one after the other, as ARGoS
// writes them, through Colony's log, naming the robot.
template <LogLevel kLevel>
int LogFunction(lua_State* L) {
  const int n = lua_gettop(L);
  for (int i = 1; i <= n; ++i) {
    const int type = lua_type(L, i);
    const bool plain = type == LUA_TTABLE || type == LUA_TFUNCTION || type == LUA_TUSERDATA ||
                       type == LUA_TTHREAD || type == LUA_TLIGHTUSERDATA;
    if (plain && luaL_getmetafield(L, i, "__tostring") == LUA_TNIL) {
      lua_pushstring(L, lua_typename(L, type));
    } else {
      if (plain) lua_pop(L, 1);
      luaL_tolstring(L, i, nullptr);
    }
  }
  lua_concat(L, n);
  size_t size = 0;
  const char* text = lua_tolstring(L, -1, &size);
  size_t id_size = 0;
  const char* id = lua_tolstring(L, lua_upvalueindex(1), &id_size);
  LogFor(kLevel, std::string(id, id_size), std::string(text, size));
  return 0;
}

// The Lua 5.2 compatibility functions ARGoS scripts use. Debian's Lua 5.3 is
// built with them (LUA_COMPAT_5_2); a Lua without them gets these.
int Pow(lua_State* L) {
  lua_pushnumber(L, std::pow(luaL_checknumber(L, 1), luaL_checknumber(L, 2)));
  return 1;
}
int Atan2(lua_State* L) {
  lua_pushnumber(L, std::atan2(luaL_checknumber(L, 1), luaL_checknumber(L, 2)));
  return 1;
}
int Ldexp(lua_State* L) {
  lua_pushnumber(L, std::ldexp(luaL_checknumber(L, 1), static_cast<int>(luaL_checkinteger(L, 2))));
  return 1;
}
int Frexp(lua_State* L) {
  int e = 0;
  lua_pushnumber(L, std::frexp(luaL_checknumber(L, 1), &e));
  lua_pushinteger(L, e);
  return 2;
}
int Cosh(lua_State* L) {
  lua_pushnumber(L, std::cosh(luaL_checknumber(L, 1)));
  return 1;
}
int Sinh(lua_State* L) {
  lua_pushnumber(L, std::sinh(luaL_checknumber(L, 1)));
  return 1;
}
int Tanh(lua_State* L) {
  lua_pushnumber(L, std::tanh(luaL_checknumber(L, 1)));
  return 1;
}
int Log10(lua_State* L) {
  lua_pushnumber(L, std::log10(luaL_checknumber(L, 1)));
  return 1;
}

void AddMissingCompatFunctions(lua_State* L) {
  static const luaL_Reg kCompat[] = {{"pow", Pow},     {"atan2", Atan2}, {"ldexp", Ldexp},
                                     {"frexp", Frexp}, {"cosh", Cosh},   {"sinh", Sinh},
                                     {"tanh", Tanh},   {"log10", Log10}, {nullptr, nullptr}};
  lua_getglobal(L, "math");
  for (const luaL_Reg* f = kCompat; f->name; ++f) {
    if (lua_getfield(L, -1, f->name) == LUA_TNIL) {
      lua_pushcfunction(L, f->func);
      lua_setfield(L, -3, f->name);
    }
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
}

// pairs() in an order that is the same in every run. Lua hashes strings
// with a seed drawn from the clock and the process's addresses, so the stock
// pairs() visits a table's string keys in a different order from one run to
// the next, and a script whose behaviour depends on that order would break
// Colony's determinism. This pairs() visits integer and float keys in
// ascending order (the array part as before), then strings in byte order,
// then false and true, then other keys (tables, functions...) in Lua's own
// order, whose hashes come from addresses and cannot be made stable. Lua
// leaves the order unspecified, so every order is a valid pairs(). A
// __pairs metamethod is honoured as the stock pairs() does; fields set to
// nil during the traversal are skipped. next() is Lua's own.
constexpr const char* kOrderedPairs = R"lua(
local next, type, rawget, sort, getmetatable, error = next, type, rawget, table.sort,
   debug.getmetatable, error
local rank = { number = 1, string = 2, boolean = 3 }
local function before(a, b)
   local ta, tb = type(a), type(b)
   if ta ~= tb then return (rank[ta] or 4) < (rank[tb] or 4) end
   if ta == "number" or ta == "string" then return a < b end
   if ta == "boolean" then return b and not a end
   return false
end
function pairs(t)
   local meta = getmetatable(t)
   if meta ~= nil and meta.__pairs ~= nil then
      local f, s, c = meta.__pairs(t)
      return f, s, c
   end
   if type(t) ~= "table" then
      error("bad argument #1 to 'pairs' (table expected, got " .. type(t) .. ")", 2)
   end
   local keys, n, ascending = {}, 0, true
   for k in next, t do
      n = n + 1
      keys[n] = k
      if ascending and k ~= n then ascending = false end
   end
   if not ascending then sort(keys, before) end
   local i = 0
   return function()
      while true do
         i = i + 1
         local k = keys[i]
         if k == nil then return nil end
         local v = rawget(t, k)
         if v ~= nil then return k, v end
      end
   end, t, nil
end
)lua";

void InstallOrderedPairs(lua_State* L) {
  if (luaL_loadbuffer(L, kOrderedPairs, std::strlen(kOrderedPairs), "=(colony pairs)") != LUA_OK ||
      lua_pcall(L, 0, 0, 0) != LUA_OK) {
    const std::string error = lua_tostring(L, -1);
    lua_pop(L, 1);
    throw std::runtime_error("could not set up pairs(): " + error);
  }
}

// dofile, loadfile, io.open, io.lines: a relative file name is taken from
// the experiment file's folder (upvalue 2), where ARGoS users run ARGoS from.
int FromExperimentFolder(lua_State* L) {
  const char* name = lua_tostring(L, 1);
  if (lua_type(L, 1) == LUA_TSTRING && name[0] != '/') {
    lua_pushfstring(L, "%s/%s", lua_tostring(L, lua_upvalueindex(2)), name);
    lua_replace(L, 1);
  }
  const int n = lua_gettop(L);
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_insert(L, 1);
  lua_call(L, n, LUA_MULTRET);
  return lua_gettop(L);
}

void ResolveFilesFrom(lua_State* L, const std::string& folder) {
  auto wrap = [&](const char* table, const char* name) {
    if (table) lua_getglobal(L, table);
    if (table ? lua_getfield(L, -1, name) : lua_getglobal(L, name)) {
      lua_pushlstring(L, folder.data(), folder.size());
      lua_pushcclosure(L, FromExperimentFolder, 2);
      if (table) {
        lua_setfield(L, -2, name);
      } else {
        lua_setglobal(L, name);
      }
    } else {
      lua_pop(L, 1);
    }
    if (table) lua_pop(L, 1);
  };
  wrap(nullptr, "dofile");
  wrap(nullptr, "loadfile");
  wrap("io", "open");
  wrap("io", "lines");
}

class LuaController : public Controller {
 public:
  ~LuaController() override { Close(); }

  void Init(const Params& params) override {
    const std::string script = params.GetString("script");
    const std::string on_error = params.GetString("on_error", "stop");
    if (on_error != "stop" && on_error != "continue") {
      throw ParamError("on_error", on_error,
                       "parameter 'on_error': '" + on_error +
                           "' is not accepted; accepted: stop (a Lua error in step() ends the "
                           "run; the default), continue (it is logged and that robot's script "
                           "stops, as in ARGoS)");
    }
    continue_on_error_ = on_error == "continue";
    folder_ = params.base_directory().empty() ? "." : params.base_directory();
    const std::filesystem::path path = std::filesystem::path(script).is_absolute()
                                           ? std::filesystem::path(script)
                                           : std::filesystem::path(folder_) / script;
    script_ = path.lexically_normal().string();
    struct stat info;
    if (::stat(script_.c_str(), &info) != 0 || !S_ISREG(info.st_mode)) {
      throw ParamError("script", script,
                       "Lua script '" + script_ + "' not found" +
                           (std::filesystem::path(script).is_absolute()
                                ? std::string()
                                : " (a relative script is looked for in the experiment file's "
                                  "folder)"));
    }
    // robot.params: every attribute of <params>, as in ARGoS. Each key is
    // read, so none is reported as unknown.
    for (const auto& key : params.Unread()) params.GetString(key, "");
    const std::vector<std::string> keys = params.Asked();
    for (const auto& key : keys) {
      if (params.Has(key)) params_.emplace_back(key, params.GetString(key, ""));
    }
    // math.random's own stream, drawn from the controller's first.
    math_rng_ = RandomStream(rng().NextU64());
    Start();
  }

  void ControlStep() override {
    if (state_ != State::kRunning) {
      if (state_ == State::kFailedToStart) throw std::runtime_error(start_error_);
      return;
    }
    robot_->Update(L_);
    if (lua_getglobal(L_, "step") != LUA_TFUNCTION) {
      lua_pop(L_, 1);
      Failed("step()", "the global 'step' is no longer a function");
      return;
    }
    if (lua_pcall(L_, 0, 0, kTraceback) != LUA_OK) Failed("step()", PopError());
  }

  // An event of a watch the script asked for (robot.watch): the global
  // on_event(event) is called with it. The robot table is not refreshed
  // (that would read the ring: a poll, in bus accounting).
  void OnEvent(const SensorEvent& event) override {
    if (state_ != State::kRunning) return;
    if (lua_getglobal(L_, "on_event") != LUA_TFUNCTION) {
      lua_pop(L_, 1);
      Failed("on_event()",
             "the script watches a sensor (robot.watch) but defines no global function "
             "on_event(event)");
      return;
    }
    if (!robot_->PushEvent(L_, event)) {
      lua_pop(L_, 1);
      return;
    }
    if (lua_pcall(L_, 1, 0, kTraceback) != LUA_OK) Failed("on_event()", PopError());
  }

  void Reset() override {
    if (state_ == State::kRunning) {
      CallIfDefined("reset");
    } else if (state_ == State::kDisabled) {
      // As ARGoS: a script stopped by an error starts again.
      Close();
      Start();
    }
  }

  void Destroy() override {
    if (state_ == State::kRunning) {
      try {
        CallIfDefined("destroy");
      } catch (const std::exception& e) {
        // Destroy runs while the simulation is torn down: it cannot fail the run.
        Log(LogLevel::kError, "robot '" + id() + "': " + e.what());
      }
    }
    Close();
  }

 private:
  enum class State { kClosed, kRunning, kFailedToStart, kDisabled };
  static constexpr int kTraceback = 1;  // stack slot of the message handler

  // A fresh Lua state with the script loaded and init() run.
  void Start() {
    L_ = NewArenaState();
    if (L_ == nullptr) throw std::runtime_error("could not create a Lua state (out of memory)");
    lua_pushcfunction(L_, Traceback);  // stays at kTraceback
    luaL_openlibs(L_);
    AddMissingCompatFunctions(L_);
    InstallOrderedPairs(L_);
    ReplaceMathRandom(L_, &math_rng_, id());
    lua_pushstring(L_, id().c_str());
    lua_pushcclosure(L_, LogFunction<LogLevel::kInfo>, 1);
    lua_setglobal(L_, "log");
    lua_pushstring(L_, id().c_str());
    lua_pushcclosure(L_, LogFunction<LogLevel::kError>, 1);
    lua_setglobal(L_, "logerr");
    RegisterMathTypes(L_);
    ResolveFilesFrom(L_, folder_);
    SetPackagePath();
    robot_ = std::make_unique<RobotTable>();
    robot_->Build(L_, devices(), &rng(), params_);
    state_ = State::kFailedToStart;
    if (LoadScript(L_, script_) != LUA_OK) {
      start_error_ = "Lua script " + script_ + " could not be loaded: " + PopError();
      return;
    }
    if (lua_pcall(L_, 0, 0, kTraceback) != LUA_OK) {
      start_error_ = "Lua script " + script_ + " failed while loading: " + PopError();
      return;
    }
    if (lua_getglobal(L_, "step") != LUA_TFUNCTION) {
      lua_pop(L_, 1);
      start_error_ = "Lua script " + script_ + " defines no function step()";
      return;
    }
    lua_pop(L_, 1);
    state_ = State::kRunning;
    if (lua_getglobal(L_, "init") == LUA_TNIL) {
      lua_pop(L_, 1);
      return;
    }
    if (lua_pcall(L_, 0, 0, kTraceback) != LUA_OK) {
      state_ = State::kFailedToStart;
      start_error_ = "Lua script " + script_ + " failed in init(): " + PopError();
      return;
    }
    // What loading left behind (the parser's data) is freed now, so the next
    // robot's state reuses that memory.
    lua_gc(L_, LUA_GCCOLLECT, 0);
  }

  // package.path starts with the script's folder, then the experiment
  // file's, so `require "helper"` finds helper.lua beside either.
  void SetPackagePath() {
    std::string dir = std::filesystem::path(script_).parent_path().string();
    if (dir.empty()) dir = ".";
    std::string path = dir + "/?.lua;" + dir + "/?/init.lua;";
    if (folder_ != dir) path += folder_ + "/?.lua;" + folder_ + "/?/init.lua;";
    lua_getglobal(L_, "package");
    lua_getfield(L_, -1, "path");
    path += lua_tostring(L_, -1);
    lua_pop(L_, 1);
    lua_pushlstring(L_, path.data(), path.size());
    lua_setfield(L_, -2, "path");
    lua_pop(L_, 1);
  }

  void CallIfDefined(const char* function) {
    if (lua_getglobal(L_, function) == LUA_TNIL) {
      lua_pop(L_, 1);
      return;
    }
    if (lua_pcall(L_, 0, 0, kTraceback) != LUA_OK) Failed(std::string(function) + "()", PopError());
  }

  // An error in `where` while running: the run stops, or, with
  // on_error="continue", this robot's script does.
  void Failed(const std::string& where, const std::string& error) {
    const std::string message = "Lua error in " + where + ": " + error;
    if (!continue_on_error_) throw std::runtime_error(message);
    state_ = State::kDisabled;
    Log(LogLevel::kError, "robot '" + id() + "': " + message +
                              "\n  (on_error=\"continue\": this robot's script is stopped; its "
                              "actuators keep their last commands)");
  }

  std::string PopError() {
    size_t size = 0;
    const char* text = lua_tolstring(L_, -1, &size);
    std::string error = text ? Tidy(std::string(text, size)) : "(an error that is not a string)";
    lua_pop(L_, 1);
    return error;
  }

  void Close() {
    if (L_) CloseArenaState(L_);
    L_ = nullptr;
    robot_.reset();
    state_ = State::kClosed;
  }

  lua_State* L_ = nullptr;
  State state_ = State::kClosed;
  std::string script_;  // the script's path, resolved
  std::string folder_;  // the experiment file's folder
  bool continue_on_error_ = false;
  std::vector<std::pair<std::string, std::string>> params_;
  std::unique_ptr<RobotTable> robot_;
  RandomStream math_rng_;
  std::string start_error_;
};

COLONY_REGISTER_CONTROLLER(
    LuaController, "lua_controller",
    "runs a Lua script with ARGoS's robot API, one Lua state per robot",
    {{"script", "a .lua file (relative: beside the experiment file)", "",
      "the script, with ARGoS's init, step, reset and destroy functions"},
     {"on_error", "stop, continue", "stop",
      "a Lua error ends the run (stop), or is logged and stops that robot's script (continue)"},
     {"*", "any other name", "", "reaches the script as robot.params"}});

}  // namespace
}  // namespace colony::lua
