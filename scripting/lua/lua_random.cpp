// robot.random (ARGoS 3.0.0-beta59's names, arguments and ranges) and a
// per-robot math.random. Both draw from streams the controller owns, seeded
// from the experiment seed and the robot's id, so a script's draws depend on
// the seed only, never on the thread count.
#include <cmath>
#include <cstring>

#include "scripting/lua/lua_host.h"

namespace colony::lua {
namespace {

RandomStream& Stream(lua_State* L) {
  return *static_cast<RandomStream*>(lua_touserdata(L, lua_upvalueindex(1)));
}

// uniform(): [0, 1); uniform(max): [0, max); uniform(min, max): [min, max).
int Uniform(lua_State* L) {
  switch (lua_gettop(L)) {
    case 0:
      lua_pushnumber(L, Stream(L).Uniform());
      return 1;
    case 1:
      lua_pushnumber(L, Stream(L).Uniform(0, luaL_checknumber(L, 1)));
      return 1;
    case 2:
      lua_pushnumber(L, Stream(L).Uniform(luaL_checknumber(L, 1), luaL_checknumber(L, 2)));
      return 1;
    default:
      return luaL_error(L, "robot.random.uniform() expects 0, 1 or 2 arguments");
  }
}

// uniform_int(max): an integer in [0, floor(max)); uniform_int(min, max): in
// [floor(min), floor(max)).
int UniformInt(lua_State* L) {
  const int n = lua_gettop(L);
  if (n != 1 && n != 2) return luaL_error(L, "robot.random.uniform_int() expects 1 or 2 arguments");
  const double min = n == 2 ? std::floor(luaL_checknumber(L, 1)) : 0;
  const double max = std::floor(luaL_checknumber(L, n));
  if (!(max > min) || max - min > 9e15) {
    return luaL_error(L, "robot.random.uniform_int(): the range [%f, %f) holds no integer", min,
                      max);
  }
  const uint64_t span = static_cast<uint64_t>(max - min);
  lua_pushinteger(
      L, static_cast<lua_Integer>(min) + static_cast<lua_Integer>(Stream(L).UniformInt(span)));
  return 1;
}

// gaussian(std_dev) or gaussian(std_dev, mean): ARGoS's order.
int Gaussian(lua_State* L) {
  const int n = lua_gettop(L);
  if (n != 1 && n != 2) return luaL_error(L, "robot.random.gaussian() expects 1 or 2 arguments");
  const double std_dev = luaL_checknumber(L, 1);
  const double mean = n == 2 ? luaL_checknumber(L, 2) : 0.0;
  lua_pushnumber(L, Stream(L).Gaussian(mean, std_dev));
  return 1;
}

int Exponential(lua_State* L) {
  if (lua_gettop(L) != 1) return luaL_error(L, "robot.random.exponential() expects 1 argument");
  const double mean = luaL_checknumber(L, 1);
  lua_pushnumber(L, -std::log(1.0 - Stream(L).Uniform()) * mean);
  return 1;
}

// Knuth's multiplication method for small means; for larger ones Hormann's
// transformed rejection (PTRS, 1993), which stays exact and fast.
lua_Integer PoissonDraw(RandomStream& rng, double mean) {
  if (mean < 10) {
    const double limit = std::exp(-mean);
    lua_Integer k = 0;
    for (double p = rng.Uniform(); p > limit; p *= rng.Uniform()) ++k;
    return k;
  }
  const double slam = std::sqrt(mean), loglam = std::log(mean);
  const double b = 0.931 + 2.53 * slam, a = -0.059 + 0.02483 * b;
  const double inv_alpha = 1.1239 + 1.1328 / (b - 3.4), vr = 0.9277 - 3.6224 / (b - 2);
  for (;;) {
    const double u = rng.Uniform() - 0.5, v = rng.Uniform();
    const double us = 0.5 - std::abs(u);
    const double k = std::floor((2 * a / us + b) * u + mean + 0.43);
    if (us >= 0.07 && v <= vr) return static_cast<lua_Integer>(k);
    if (k < 0 || (us < 0.013 && v > us)) continue;
    if (std::log(v) + std::log(inv_alpha) - std::log(a / (us * us) + b) <=
        -mean + k * loglam - std::lgamma(k + 1)) {
      return static_cast<lua_Integer>(k);
    }
  }
}

int Poisson(lua_State* L) {
  if (lua_gettop(L) != 1) return luaL_error(L, "robot.random.poisson() expects 1 argument");
  const double mean = luaL_checknumber(L, 1);
  if (!(mean >= 0) || mean > 1e9) {
    return luaL_error(L, "robot.random.poisson(): the mean must be in [0, 1e9], not %f", mean);
  }
  lua_pushinteger(L, PoissonDraw(Stream(L), mean));
  return 1;
}

// bernoulli() is true with probability 0.5, bernoulli(p) with p.
int Bernoulli(lua_State* L) {
  if (lua_gettop(L) > 1) return luaL_error(L, "robot.random.bernoulli() expects 0 or 1 arguments");
  const double p = lua_gettop(L) == 1 ? luaL_checknumber(L, 1) : 0.5;
  lua_pushboolean(L, Stream(L).Bernoulli(p));
  return 1;
}

// math.random with Lua 5.3's contract, from this robot's stream.
int MathRandom(lua_State* L) {
  RandomStream& rng = Stream(L);
  lua_Integer low = 1, up = 0;
  switch (lua_gettop(L)) {
    case 0:
      lua_pushnumber(L, rng.Uniform());
      return 1;
    case 1:
      up = luaL_checkinteger(L, 1);
      break;
    case 2:
      low = luaL_checkinteger(L, 1);
      up = luaL_checkinteger(L, 2);
      break;
    default:
      return luaL_error(L, "wrong number of arguments");
  }
  luaL_argcheck(L, low <= up, lua_gettop(L), "interval is empty");
  const uint64_t span = static_cast<uint64_t>(up) - static_cast<uint64_t>(low);
  const uint64_t draw = span == UINT64_MAX ? rng.NextU64() : rng.UniformInt(span + 1);
  lua_pushinteger(L, static_cast<lua_Integer>(static_cast<uint64_t>(low) + draw));
  return 1;
}

// math.randomseed(x): this robot's stream restarts from x and its id, so
// robots seeded alike still draw different numbers (as they would from
// ARGoS's one shared generator).
int MathRandomSeed(lua_State* L) {
  const lua_Number seed = luaL_checknumber(L, 1);
  size_t id_size = 0;
  const char* id = lua_tolstring(L, lua_upvalueindex(2), &id_size);
  uint64_t h = HashBytes(&seed, sizeof seed);
  h = HashBytes(id, id_size, h);
  Stream(L) = RandomStream(h);
  return 0;
}

}  // namespace

void RegisterRobotRandom(lua_State* L, RandomStream* stream) {
  static const luaL_Reg kFunctions[] = {{"uniform", Uniform},   {"uniform_int", UniformInt},
                                        {"gaussian", Gaussian}, {"exponential", Exponential},
                                        {"poisson", Poisson},   {"bernoulli", Bernoulli},
                                        {nullptr, nullptr}};
  lua_createtable(L, 0, 6);
  lua_pushlightuserdata(L, stream);
  luaL_setfuncs(L, kFunctions, 1);
  lua_setfield(L, -2, "random");
}

void ReplaceMathRandom(lua_State* L, int env, RandomStream* stream, const std::string& robot_id) {
  lua_getfield(L, env, "math");
  lua_pushlightuserdata(L, stream);
  lua_pushcclosure(L, MathRandom, 1);
  lua_setfield(L, -2, "random");
  lua_pushlightuserdata(L, stream);
  lua_pushlstring(L, robot_id.data(), robot_id.size());
  lua_pushcclosure(L, MathRandomSeed, 2);
  lua_setfield(L, -2, "randomseed");
  lua_pop(L, 1);
}

}  // namespace colony::lua
