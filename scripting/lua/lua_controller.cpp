// The Lua controller host: <lua_controller> with <params script="x.lua"/>,
// ARGoS 3.0.0-beta59's Lua API on Lua 5.3 (scripting/lua/README.md).
//
// Every robot has globals of its own (an environment: its own _G, copies of
// the standard library tables, its own package.loaded), as if it had a Lua
// state of its own as in ARGoS; the robots of one controller configuration
// share a Lua state 64 at a time (StateGroup below), which holds the code and
// the libraries' functions once for them all, or each has its own with
// <params lua_state="own"/>. As in ARGoS, the script's top level runs once
// per robot, then its init(); step() every tick after the sensors are read
// and written into the robot table; reset() on reset; destroy() at the end.
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

constexpr int kTraceback = 1;  // the stack slot of Traceback in every state

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
// with '#' is skipped, line numbers kept), wrapped as `return function(_ENV,
// ...) <script> end`: calling the loaded chunk gives the script as a function
// of a robot's environment, so the robots sharing a Lua state share its code.
// The wrapper begins on the script's first line, so every line keeps its
// number; a syntax error is reported as for the script alone. The wrapped
// script is compiled once per process and content, and every other group
// loads its bytecode, debug information included (errors still name the
// script's lines). A precompiled (binary) script is loaded as it is and
// `*wrapped` is false: its first upvalue is its _ENV.
int LoadScript(lua_State* L, const std::string& path, bool* wrapped) {
  *wrapped = false;
  std::ifstream in(path, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) return luaL_loadfile(L, path.c_str());  // says why
  static std::mutex mutex;
  static std::map<std::string, std::pair<std::string, std::string>> compiled;  // text, bytecode
  const std::string name = "@" + path;
  {
    std::lock_guard<std::mutex> lock(mutex);
    const auto it = compiled.find(path);
    if (it != compiled.end() && it->second.first == text) {
      *wrapped = true;
      return luaL_loadbufferx(L, it->second.second.data(), it->second.second.size(), name.c_str(),
                              "b");
    }
  }
  std::string source = text;
  if (source.compare(0, 3, "\xEF\xBB\xBF") == 0) source.erase(0, 3);  // a UTF-8 mark
  if (!source.empty() && source[0] == '#') source.erase(0, source.find('\n'));
  if (!source.empty() && source[0] == LUA_SIGNATURE[0])
    return luaL_loadbufferx(L, source.data(), source.size(), name.c_str(), "b");
  int status = luaL_loadbufferx(L, source.data(), source.size(), name.c_str(), "t");
  if (status != LUA_OK) return status;
  lua_pop(L, 1);
  source = "return function(_ENV, ...) " + source + "\nend";
  status = luaL_loadbufferx(L, source.data(), source.size(), name.c_str(), "t");
  if (status != LUA_OK) return status;
  *wrapped = true;
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

// What every robot's environment is made from, run once in each state with
// the state's standard globals as `template` (scripting/lua/README.md, "Lua
// states"): a table of globals of the robot's own, with its own copy of each
// standard library table, `_G` itself, and require, load, loadfile, dofile,
// io.open and io.lines that work in it. Relative file names given to
// dofile, loadfile, io.open and io.lines are taken from the experiment
// file's folder, where ARGoS users run ARGoS from; `require` searches the
// robot's own package.path and keeps modules in its own package.loaded.
constexpr const char* kMakeEnvironment = R"lua(
local next, type, select, error, ipairs, tostring = next, type, select, error, ipairs, tostring
local base_load, base_loadfile = load, loadfile
local searchpath, loadlib = package.searchpath, package.loadlib
local format, gsub, sub = string.format, string.gsub, string.sub
local libraries = { "bit32", "coroutine", "debug", "io", "math", "os", "package", "string",
                    "table", "utf8" }
local copied = {}
for _, name in ipairs(libraries) do copied[name] = true end
return function(template, folder, path)
   local env = {}
   for k, v in next, template do
      if copied[k] and type(v) == "table" then
         local c = {}
         for kk, vv in next, v do c[kk] = vv end
         env[k] = c
      else
         env[k] = v
      end
   end
   env._G = env
   local function resolve(name)
      if type(name) == "string" and sub(name, 1, 1) ~= "/" then return folder .. "/" .. name end
      return name
   end
   env.load = function(chunk, name, mode, ...)
      if select("#", ...) == 0 then return base_load(chunk, name, mode, env) end
      return base_load(chunk, name, mode, ...)
   end
   env.loadfile = function(name, mode, ...)
      if select("#", ...) == 0 then return base_loadfile(resolve(name), mode, env) end
      return base_loadfile(resolve(name), mode, ...)
   end
   env.dofile = function(name)
      local f, message = base_loadfile(resolve(name), "bt", env)
      if f == nil then error(message, 0) end
      return f()
   end
   local io_open, io_lines = env.io.open, env.io.lines
   env.io.open = function(name, ...) return io_open(resolve(name), ...) end
   env.io.lines = function(...)
      if select("#", ...) == 0 then return io_lines() end
      return io_lines(resolve((...)), select(2, ...))
   end
   local package = env.package
   package.path = path
   package.preload = {}
   package.loaded = { _G = env }
   for _, name in ipairs(libraries) do package.loaded[name] = env[name] end
   package.searchers = {
      function(name)
         local f = package.preload[name]
         if f == nil then return format("\n\tno field package.preload['%s']", name) end
         return f, ":preload:"
      end,
      function(name)
         local file, message = searchpath(name, package.path)
         if file == nil then return message end
         local f, problem = base_loadfile(file, "bt", env)
         if f == nil then
            error(format("error loading module '%s' from file '%s':\n\t%s", name, file, problem), 0)
         end
         return f, file
      end,
      function(name)
         local file, message = searchpath(name, package.cpath)
         if file == nil then return message end
         local f, problem = loadlib(file, "luaopen_" .. gsub(name, "%.", "_"))
         if f == nil then
            error(format("error loading module '%s' from file '%s':\n\t%s", name, file, problem), 0)
         end
         return f, file
      end,
   }
   env.require = function(name)
      if type(name) ~= "string" and type(name) ~= "number" then
         error(format("bad argument #1 to 'require' (string expected, got %s)", type(name)), 2)
      end
      name = tostring(name)
      local loaded = package.loaded
      if loaded[name] then return loaded[name] end
      local message = ""
      for _, searcher in ipairs(package.searchers) do
         local loader, extra = searcher(name)
         if type(loader) == "function" then
            local result = loader(name, extra)
            if result ~= nil then loaded[name] = result end
            if loaded[name] == nil then loaded[name] = true end
            return loaded[name]
         elseif type(loader) == "string" then
            message = message .. loader
         end
      end
      error(format("module '%s' not found:%s", name, message), 2)
   end
   return env
end
)lua";

// A robot alone in its state (lua_state="own") has the state's globals. Its
// dofile, loadfile, io.open, io.lines take a relative file name from the
// experiment file's folder (upvalue 2), where ARGoS users run ARGoS from.
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

// Loads kMakeEnvironment, compiled once per process.
int LoadMakeEnvironment(lua_State* L) {
  static std::mutex mutex;
  static std::string bytecode;
  std::lock_guard<std::mutex> lock(mutex);
  if (!bytecode.empty())
    return luaL_loadbufferx(L, bytecode.data(), bytecode.size(), "=(colony environment)", "b");
  const int status = luaL_loadbufferx(L, kMakeEnvironment, std::strlen(kMakeEnvironment),
                                      "=(colony environment)", "t");
  if (status == LUA_OK && lua_dump(L, AppendChunk, &bytecode, 0) != 0) bytecode.clear();
  return status;
}

// Strings' methods (s:upper()) come from the string library of the robot
// whose code runs (upvalue 1 holds it at [1]), as if each robot had a state
// of its own.
int StringIndex(lua_State* L) {
  lua_rawgeti(L, lua_upvalueindex(1), 1);
  lua_pushvalue(L, 2);
  lua_gettable(L, -2);
  return 1;
}

// How many robots of one controller configuration share a Lua state. The
// thread pool hands out robots in chunks of whole multiples of 64 (the
// min_chunk of sensing and control), so with 64 the robots of one state are
// always stepped by one thread, in their order.
constexpr int kRobotsPerState = 64;

// A Lua state and the robots in it (scripting/lua/README.md, "Lua states"):
// the robots of one controller configuration, kRobotsPerState of them in
// the order they were made, or each robot alone (lua_state="own"). Each
// robot has its own environment; the state holds the standard library
// functions, the script's code and the registry once for them all. Only one
// thread at a time may run code in a state: the controllers lock mutex().
class StateGroup {
 public:
  // The group the next robot of configuration `key` joins.
  static StateGroup* Join(const void* key, bool own, int* slot) {
    std::lock_guard<std::mutex> lock(Groups());
    auto& open = OpenGroups();
    StateGroup* group = nullptr;
    if (!own) {
      const auto it = open.find(key);
      if (it != open.end()) group = it->second;
    }
    if (group == nullptr) {
      group = new StateGroup(own ? 1 : kRobotsPerState);  // throws when out of memory
      if (!own) open[key] = group;
      group->key_ = key;
    }
    ++group->members_;
    *slot = group->assigned_;
    group->hot_.emplace_back();
    if (++group->assigned_ == group->capacity_ && !own) open.erase(key);
    return group;
  }

  // A robot leaves for good; the last one closes the state.
  void Leave() {
    std::lock_guard<std::mutex> lock(Groups());
    if (--members_ > 0) return;
    auto& open = OpenGroups();
    const auto it = open.find(key_);
    if (it != open.end() && it->second == this) open.erase(it);
    delete this;
  }

  lua_State* L() const { return L_; }
  std::mutex& mutex() { return mutex_; }
  bool full() const { return assigned_ == capacity_; }
  int capacity() const { return capacity_; }

  // Pushes a new environment for a robot (kMakeEnvironment).
  void PushNewEnvironment(const std::string& folder, const std::string& package_path) {
    if (capacity_ == 1) {
      // The state's own globals, as ARGoS's: the stock require and load.
      ResolveFilesFrom(L_, folder);
      lua_getglobal(L_, "package");
      lua_pushlstring(L_, package_path.data(), package_path.size());
      lua_setfield(L_, -2, "path");
      lua_pop(L_, 1);
      lua_pushglobaltable(L_);
      return;
    }
    lua_rawgeti(L_, LUA_REGISTRYINDEX, make_environment_);
    lua_pushglobaltable(L_);
    lua_pushlstring(L_, folder.data(), folder.size());
    lua_pushlstring(L_, package_path.data(), package_path.size());
    if (lua_pcall(L_, 3, 1, kTraceback) != LUA_OK) {
      const std::string error = lua_tostring(L_, -1);
      lua_pop(L_, 1);
      throw std::runtime_error("could not make a Lua environment: " + error);
    }
  }

  // Pushes the script at `path` as a function of a robot's environment
  // (LoadScript; loaded once per state), or, for a precompiled script, its
  // main chunk (`*wrapped` false: set its first upvalue to the environment);
  // on an error pushes the message and returns Lua's status.
  int PushScript(const std::string& path, bool* wrapped) {
    *wrapped = true;
    lua_rawgeti(L_, LUA_REGISTRYINDEX, scripts_);
    if (lua_getfield(L_, -1, path.c_str()) == LUA_TFUNCTION) {
      lua_remove(L_, -2);
      return LUA_OK;
    }
    lua_pop(L_, 1);
    int status = LoadScript(L_, path, wrapped);
    if (status == LUA_OK && *wrapped) {
      status = lua_pcall(L_, 0, 1, kTraceback);
      if (status == LUA_OK) {
        lua_pushvalue(L_, -1);
        lua_setfield(L_, -3, path.c_str());
      }
    }
    lua_remove(L_, -2);
    return status;
  }

  // The objects robot `slot`'s step reads first (its environment, its step
  // function and that function's upvalues, its rings' entries): the robot
  // stepped before it asks for them to be fetched into the cache meanwhile.
  std::vector<const void*>& hot(int slot) { return hot_[slot]; }
  void PrefetchFor(int slot) const {
    if (slot >= static_cast<int>(hot_.size())) return;
    for (const void* p : hot_[slot]) {
      __builtin_prefetch(p);
      __builtin_prefetch(static_cast<const char*>(p) + 64);
    }
  }

  // Makes string methods those of the robot whose string library is the
  // registry's `string_ref`: called before running a robot's code.
  void Enter(int string_ref) {
    if (current_ == LUA_NOREF) return;  // a state of one robot
    lua_rawgeti(L_, LUA_REGISTRYINDEX, current_);
    lua_rawgeti(L_, LUA_REGISTRYINDEX, string_ref);
    lua_rawseti(L_, -2, 1);
    lua_pop(L_, 1);
  }

 private:
  static std::mutex& Groups() {
    static std::mutex* mutex = new std::mutex;  // never destroyed: states may close at exit
    return *mutex;
  }
  static std::map<const void*, StateGroup*>& OpenGroups() {
    static auto* open = new std::map<const void*, StateGroup*>;
    return *open;
  }

  explicit StateGroup(int capacity) : capacity_(capacity) {
    L_ = NewArenaState();
    if (L_ == nullptr) throw std::runtime_error("could not create a Lua state (out of memory)");
    try {
      lua_pushcfunction(L_, Traceback);  // stays at kTraceback
      luaL_openlibs(L_);
      AddMissingCompatFunctions(L_);
      InstallOrderedPairs(L_);
      RegisterMathTypes(L_);
      if (capacity_ > 1) {
        // String methods through the running robot's string library.
        lua_createtable(L_, 1, 0);
        lua_getglobal(L_, "string");
        lua_rawseti(L_, -2, 1);
        lua_pushvalue(L_, -1);
        current_ = luaL_ref(L_, LUA_REGISTRYINDEX);
        lua_pushliteral(L_, "");
        lua_getmetatable(L_, -1);
        lua_pushvalue(L_, -3);
        lua_pushcclosure(L_, StringIndex, 1);
        lua_setfield(L_, -2, "__index");
        lua_pop(L_, 3);
        if (LoadMakeEnvironment(L_) != LUA_OK || lua_pcall(L_, 0, 1, kTraceback) != LUA_OK) {
          throw std::runtime_error(std::string("could not set up a Lua state: ") +
                                   lua_tostring(L_, -1));
        }
        make_environment_ = luaL_ref(L_, LUA_REGISTRYINDEX);
      }
      lua_newtable(L_);
      scripts_ = luaL_ref(L_, LUA_REGISTRYINDEX);
    } catch (...) {
      CloseArenaState(L_);
      throw;
    }
  }
  ~StateGroup() { CloseArenaState(L_); }

  lua_State* L_ = nullptr;
  std::mutex mutex_;
  const void* key_ = nullptr;
  int capacity_;
  int assigned_ = 0;  // robots that joined
  int members_ = 0;   // robots still in it
  int make_environment_ = LUA_NOREF;
  int scripts_ = LUA_NOREF;  // a table: script path -> the script as a function
  int current_ = LUA_NOREF;  // a table whose [1] is the running robot's string library
  std::vector<std::vector<const void*>> hot_;  // by slot
};

// The value of parameter `key`, one of `accepted` ({value, what it means},
// the first the default); any other value is a ParamError listing them.
std::string ChoiceParam(const Params& params, const std::string& key,
                        const std::vector<std::pair<std::string, std::string>>& accepted) {
  const std::string value = params.GetString(key, accepted.front().first);
  std::string list;
  for (const auto& [choice, meaning] : accepted) {
    if (choice == value) return value;
    list += (list.empty() ? "" : ", ") + choice + " (" + meaning + ")";
  }
  throw ParamError(key, value,
                   "parameter '" + key + "': '" + value + "' is not accepted; accepted: " + list);
}

class LuaController : public Controller {
 public:
  ~LuaController() override { Close(); }

  void Init(const Params& params) override {
    const std::string script = params.GetString("script");
    const std::string on_error =
        ChoiceParam(params, "on_error",
                    {{"stop", "a Lua error in step() ends the run; the default"},
                     {"continue", "it is logged and that robot's script stops, as in ARGoS"}});
    continue_on_error_ = on_error == "continue";
    const std::string lua_state = ChoiceParam(
        params, "lua_state",
        {{"shared",
          "robots of this controller share Lua states, each with globals of its own; the "
          "default"},
         {"own", "a Lua state per robot, as ARGoS"}});
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
    group_ = StateGroup::Join(&params, lua_state == "own", &slot_);
    std::lock_guard<std::mutex> lock(group_->mutex());
    Start();
  }

  void ControlStep() override {
    if (state_ != State::kRunning) {
      if (state_ == State::kFailedToStart) throw std::runtime_error(start_error_);
      return;
    }
    std::lock_guard<std::mutex> lock(group_->mutex());
    lua_State* L = group_->L();
    group_->PrefetchFor(slot_ + 1);
    group_->Enter(string_ref_);
    robot_->Update(L);
    if (!PushGlobal(L, "step")) {
      Failed("step()", "the global 'step' is no longer a function");
      return;
    }
    if (lua_pcall(L, 0, 0, kTraceback) != LUA_OK) Failed("step()", PopError(L));
  }

  // An event of a watch the script asked for (robot.watch): the global
  // on_event(event) is called with it. The robot table is not refreshed
  // (that would read the ring: a poll, in bus accounting).
  void OnEvent(const SensorEvent& event) override {
    if (state_ != State::kRunning) return;
    std::lock_guard<std::mutex> lock(group_->mutex());
    lua_State* L = group_->L();
    group_->Enter(string_ref_);
    if (!PushGlobal(L, "on_event")) {
      Failed("on_event()",
             "the script watches a sensor (robot.watch) but defines no global function "
             "on_event(event)");
      return;
    }
    if (!robot_->PushEvent(L, event)) {
      lua_pop(L, 1);
      return;
    }
    if (lua_pcall(L, 1, 0, kTraceback) != LUA_OK) Failed("on_event()", PopError(L));
  }

  void Reset() override {
    if (group_ == nullptr) return;
    std::lock_guard<std::mutex> lock(group_->mutex());
    if (state_ == State::kRunning) {
      CallIfDefined("reset");
    } else if (state_ == State::kDisabled) {
      // As ARGoS: a script stopped by an error starts again, in a fresh
      // environment.
      Release();
      Start();
    }
  }

  void Destroy() override {
    if (state_ == State::kRunning) {
      std::lock_guard<std::mutex> lock(group_->mutex());
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

  // The robot's environment made, the script loaded and init() run; the
  // caller holds the group's lock.
  void Start() {
    lua_State* L = group_->L();
    // In a shared state, the robot's copies of the libraries go apart
    // (cold), and its tables, closures and the script's own objects are laid
    // in order in new memory (fresh), so that the objects the robots' steps
    // read lie together, robot after robot. A state of its own keeps one run
    // and reuses freed blocks: it would only take more memory.
    const bool shared = group_->capacity() > 1;
    SetColdAllocation(L, shared);
    try {
      group_->PushNewEnvironment(folder_, PackagePath());
    } catch (...) {
      SetColdAllocation(L, false);
      throw;
    }
    SetColdAllocation(L, false);
    struct Fresh {
      lua_State* L;
      Fresh(lua_State* state, bool fresh) : L(state) { SetFreshAllocation(L, fresh); }
      ~Fresh() { SetFreshAllocation(L, false); }
    } fresh(L, shared);
    const int env = lua_gettop(L);
    lua_getfield(L, env, "string");
    string_ref_ = luaL_ref(L, LUA_REGISTRYINDEX);
    group_->Enter(string_ref_);
    ReplaceMathRandom(L, env, &math_rng_, id());
    lua_pushstring(L, id().c_str());
    lua_pushcclosure(L, LogFunction<LogLevel::kInfo>, 1);
    lua_setfield(L, env, "log");
    lua_pushstring(L, id().c_str());
    lua_pushcclosure(L, LogFunction<LogLevel::kError>, 1);
    lua_setfield(L, env, "logerr");
    robot_ = std::make_unique<RobotTable>();
    try {
      robot_->Build(L, env, devices(), &rng(), params_);
    } catch (...) {
      lua_settop(L, kTraceback);
      throw;
    }
    env_ref_ = luaL_ref(L, LUA_REGISTRYINDEX);
    state_ = State::kFailedToStart;
    bool wrapped = true;
    if (group_->PushScript(script_, &wrapped) != LUA_OK) {
      start_error_ = "Lua script " + script_ + " could not be loaded: " + PopError(L);
      return;
    }
    lua_rawgeti(L, LUA_REGISTRYINDEX, env_ref_);
    if (!wrapped) lua_setupvalue(L, -2, 1);  // a precompiled script's _ENV
    if (lua_pcall(L, wrapped ? 1 : 0, 0, kTraceback) != LUA_OK) {
      start_error_ = "Lua script " + script_ + " failed while loading: " + PopError(L);
      return;
    }
    if (!PushGlobal(L, "step")) {
      start_error_ = "Lua script " + script_ + " defines no function step()";
      return;
    }
    lua_pop(L, 1);
    state_ = State::kRunning;
    lua_rawgeti(L, LUA_REGISTRYINDEX, env_ref_);
    const bool has_init = lua_getfield(L, -1, "init") != LUA_TNIL;
    lua_remove(L, -2);
    if (!has_init) {
      lua_pop(L, 1);
    } else if (lua_pcall(L, 0, 0, kTraceback) != LUA_OK) {
      state_ = State::kFailedToStart;
      start_error_ = "Lua script " + script_ + " failed in init(): " + PopError(L);
      return;
    }
    CollectHotObjects();
    // What loading left behind (the parser's data) is freed once the state
    // has all its robots, so that the next state reuses that memory.
    if (group_->full()) lua_gc(L, LUA_GCCOLLECT, 0);
  }

  void CollectHotObjects() {
    lua_State* L = group_->L();
    std::vector<const void*>& hot = group_->hot(slot_);
    hot.clear();
    lua_rawgeti(L, LUA_REGISTRYINDEX, env_ref_);
    hot.push_back(lua_topointer(L, -1));
    if (lua_getfield(L, -1, "step") == LUA_TFUNCTION) {
      hot.push_back(lua_topointer(L, -1));
      for (int n = 1; lua_getupvalue(L, -1, n) != nullptr; ++n) {
        hot.push_back(lua_upvalueid(L, -2, n));
        if (lua_type(L, -1) == LUA_TTABLE) hot.push_back(lua_topointer(L, -1));
        lua_pop(L, 1);
      }
    }
    lua_pop(L, 2);
    robot_->HotObjects(L, hot);
  }

  // Pushes the robot's global `name` and returns true when it is a
  // function; otherwise pushes nothing and returns false.
  bool PushGlobal(lua_State* L, const char* name) {
    lua_rawgeti(L, LUA_REGISTRYINDEX, env_ref_);
    const bool function = lua_getfield(L, -1, name) == LUA_TFUNCTION;
    lua_remove(L, -2);
    if (!function) lua_pop(L, 1);
    return function;
  }

  // package.path starts with the script's folder, then the experiment
  // file's, so `require "helper"` finds helper.lua beside either.
  std::string PackagePath() {
    std::string dir = std::filesystem::path(script_).parent_path().string();
    if (dir.empty()) dir = ".";
    std::string path = dir + "/?.lua;" + dir + "/?/init.lua;";
    if (folder_ != dir) path += folder_ + "/?.lua;" + folder_ + "/?/init.lua;";
    lua_State* L = group_->L();
    lua_getglobal(L, "package");
    lua_getfield(L, -1, "path");
    path += lua_tostring(L, -1);
    lua_pop(L, 2);
    return path;
  }

  void CallIfDefined(const char* function) {
    lua_State* L = group_->L();
    group_->Enter(string_ref_);
    lua_rawgeti(L, LUA_REGISTRYINDEX, env_ref_);
    const bool defined = lua_getfield(L, -1, function) != LUA_TNIL;
    lua_remove(L, -2);
    if (!defined) {
      lua_pop(L, 1);
      return;
    }
    if (lua_pcall(L, 0, 0, kTraceback) != LUA_OK) Failed(std::string(function) + "()", PopError(L));
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

  static std::string PopError(lua_State* L) {
    size_t size = 0;
    const char* text = lua_tolstring(L, -1, &size);
    std::string error = text ? Tidy(std::string(text, size)) : "(an error that is not a string)";
    lua_pop(L, 1);
    return error;
  }

  // Drops this robot's environment and robot table from the state (the
  // caller holds the group's lock).
  void Release() {
    lua_State* L = group_->L();
    group_->hot(slot_).clear();
    if (robot_) robot_->Release(L);
    robot_.reset();
    luaL_unref(L, LUA_REGISTRYINDEX, env_ref_);
    luaL_unref(L, LUA_REGISTRYINDEX, string_ref_);
    env_ref_ = string_ref_ = LUA_NOREF;
    state_ = State::kClosed;
  }

  void Close() {
    if (group_ == nullptr) return;
    {
      std::lock_guard<std::mutex> lock(group_->mutex());
      Release();
    }
    group_->Leave();
    group_ = nullptr;
  }

  StateGroup* group_ = nullptr;
  int slot_ = 0;                // its place in the group
  int env_ref_ = LUA_NOREF;     // the robot's globals
  int string_ref_ = LUA_NOREF;  // its string library
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
    "runs a Lua script with ARGoS's robot API, each robot with globals of its own",
    {{"script", "a .lua file (relative: beside the experiment file)", "",
      "the script, with ARGoS's init, step, reset and destroy functions"},
     {"on_error", "stop, continue", "stop",
      "a Lua error ends the run (stop), or is logged and stops that robot's script (continue)"},
     {"lua_state", "shared, own", "shared",
      "robots share Lua states, each with globals of its own (shared), or each has a state of "
      "its own, as in ARGoS (own)"},
     {"*", "any other name", "", "reaches the script as robot.params"}});

}  // namespace
}  // namespace colony::lua
