// A layout experiment for the Lua host (scripting/lua/BENCHMARK-NOTES.md,
// "One state per robot, or one state for many"): experiments/lua/diffusion.lua's
// step() on N robots, with each robot in its own Lua state (as the host
// does) or all robots in one state, each with its own _ENV table (the script
// wrapped as `return function(_ENV, ...) <script> end`, so its globals and
// top-level locals are per robot while its code is shared). Not part of the
// build: compile and run by hand.
//
//   g++ -O2 scripting/lua/bench/state_layout.cpp -o /tmp/state_layout \
//       $(pkg-config --cflags --libs lua5.3)
//   /tmp/state_layout N MODE [arena]   # MODE 0: a state per robot, 1: one state
//
// `arena`: every state bump-allocates from its own 1 MB chunks (nothing is
// freed: the script allocates nothing per step), like the host's arenas.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <lua.hpp>
#include <sstream>
#include <string>
#include <vector>
static int SetVel(lua_State* L) {
  double* d = (double*)lua_touserdata(L, lua_upvalueindex(1));
  d[0] = lua_tonumber(L, 1);
  d[1] = lua_tonumber(L, 2);
  return 0;
}
static double g_vel[2];
struct Arena {
  char* p;
  size_t left;
};
static void* ArenaAlloc(void* ud, void* ptr, size_t osize, size_t nsize) {
  Arena* a = (Arena*)ud;
  if (nsize == 0) return nullptr;
  if (ptr && nsize <= osize) return ptr;
  size_t n = (nsize + 15) & ~size_t(15);
  if (n > a->left) {
    size_t c = 1 << 20;
    a->p = (char*)aligned_alloc(64, c);
    a->left = c;
  }
  void* r = a->p;
  a->p += n;
  a->left -= n;
  if (ptr) memcpy(r, ptr, osize < nsize ? osize : nsize);
  return r;
}
static lua_State* NewState(bool arena) {
  if (!arena) return luaL_newstate();
  Arena* a = new Arena{nullptr, 0};
  lua_State* L = lua_newstate(ArenaAlloc, a);
  return L;
}
// robot table onto stack
static void PushRobot(lua_State* L) {
  lua_createtable(L, 0, 4);
  lua_createtable(L, 0, 0);  // robot.params: none, the script's defaults
  lua_setfield(L, -2, "params");
  lua_createtable(L, 24, 0);
  for (int i = 0; i < 24; ++i) {
    lua_createtable(L, 0, 2);
    lua_pushnumber(L, (i + 0.5) * 2 * 3.14159265 / 24);
    lua_setfield(L, -2, "angle");
    lua_pushnumber(L, (i % 7 == 0) ? 0.2 : 0.0);
    lua_setfield(L, -2, "value");
    lua_rawseti(L, -2, i + 1);
  }
  lua_setfield(L, -2, "proximity");
  lua_createtable(L, 0, 2);
  lua_pushlightuserdata(L, g_vel);
  lua_pushcclosure(L, SetVel, 1);
  lua_setfield(L, -2, "set_velocity");
  lua_setfield(L, -2, "wheels");
}
int main(int argc, char** argv) {
  if (argc < 3) {
    fprintf(stderr, "usage: state_layout N MODE [arena]  (run from the project's root)\n");
    return 2;
  }
  int n = atoi(argv[1]);
  int mode = atoi(argv[2]);
  bool arena = argc > 3;
  std::ifstream file("experiments/lua/diffusion.lua");
  if (!file) {
    fprintf(stderr, "experiments/lua/diffusion.lua not found: run from the project's root\n");
    return 2;
  }
  std::stringstream text;
  text << file.rdbuf();
  const std::string script = text.str();
  const char* kScript = script.c_str();
  int ticks = 200;
  std::vector<lua_State*> states;
  std::vector<int> refs;
  lua_State* shared = nullptr;
  if (mode == 0) {
    for (int r = 0; r < n; ++r) {
      lua_State* L = NewState(arena);
      luaL_openlibs(L);
      PushRobot(L);
      lua_setglobal(L, "robot");
      if (luaL_loadstring(L, kScript) || lua_pcall(L, 0, 0, 0)) {
        fprintf(stderr, "%s\n", lua_tostring(L, -1));
        return 1;
      }
      lua_getglobal(L, "init");
      lua_call(L, 0, 0);
      states.push_back(L);
    }
  } else {
    shared = NewState(arena);
    luaL_openlibs(shared);
    lua_State* L = shared;
    std::string wrapped = std::string("return function(_ENV, ...) ") + kScript + "\nend";
    if (luaL_loadstring(L, wrapped.c_str()) || lua_pcall(L, 0, 1, 0)) {
      fprintf(stderr, "%s\n", lua_tostring(L, -1));
      return 1;
    }
    int factory = lua_gettop(L);
    for (int r = 0; r < n; ++r) {
      lua_createtable(L, 0, 8);  // env
      lua_createtable(L, 0, 1);
      lua_pushglobaltable(L);
      lua_setfield(L, -2, "__index");
      lua_setmetatable(L, -2);
      PushRobot(L);
      lua_setfield(L, -2, "robot");
      lua_pushvalue(L, factory);
      lua_pushvalue(L, -2);
      lua_call(L, 1, 0);
      lua_getfield(L, -1, "init");
      lua_call(L, 0, 0);
      lua_getfield(L, -1, "step");
      refs.push_back(luaL_ref(L, LUA_REGISTRYINDEX));
      lua_pop(L, 1);
    }
  }
  auto t0 = std::chrono::steady_clock::now();
  for (int t = 0; t < ticks; ++t) {
    if (mode == 0) {
      for (lua_State* L : states) {
        lua_getglobal(L, "step");
        lua_pcall(L, 0, 0, 0);
      }
    } else {
      for (int ref : refs) {
        lua_rawgeti(shared, LUA_REGISTRYINDEX, ref);
        lua_pcall(shared, 0, 0, 0);
      }
    }
  }
  double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  printf("arena=%d n=%d mode=%s ns/step=%.0f\n", (int)arena, n, mode ? "shared" : "per-robot",
         s / ticks / n * 1e9);
}
