// ARGoS's Lua math types (3.0.0-beta59): vector2, vector3 and quaternion as
// full userdata. Their global constructors, fields (x, y, z; w for
// quaternions), operators and methods are those ARGoS scripts use:
//   vector2(), vector2(v), vector2(x, y): + - unary- * (by a number) ==,
//     tostring "x,y" (6 significant digits, as ARGoS); v:length(), v:dot(w), v:normalize() and
//     v:rotate(angle) (both change v and return it), v:cross(w) (the number x1 y2 - y1 x2; ARGoS's
//     returns v unchanged, a bug no script can rely on);
//   vector3(), vector3(v), vector3(x, y, z): the same, tostring "x,y,z",
//     v:cross(w) (changes v to v x w and returns it), v:rotate(q) (by a
//     quaternion, changes v and returns it);
//   quaternion(), quaternion(q), quaternion(angle, axis), quaternion(w, x, y,
//     z): * (composition) ==, tostring "z,y,x" Euler angles in degrees;
//     q:normalize() (changes q and returns it), q:inverse(),
//     q:toangleaxis() -> angle, axis (angle in [0, 2 pi], the no-rotation
//     axis is +z), q:toeulerangles() -> z, y, x (rad).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "scripting/lua/lua_host.h"

namespace colony::lua {
namespace {

constexpr const char* kVector2 = "argos3.vector2";
constexpr const char* kVector3 = "argos3.vector3";
constexpr const char* kQuaternion = "argos3.quaternion";

struct V2 {
  double x, y;
};
struct V3 {
  double x, y, z;
};
struct Q {
  double w, x, y, z;
};

V2* CheckV2(lua_State* L, int i) { return static_cast<V2*>(luaL_checkudata(L, i, kVector2)); }
V3* CheckV3(lua_State* L, int i) { return static_cast<V3*>(luaL_checkudata(L, i, kVector3)); }
Q* CheckQ(lua_State* L, int i) { return static_cast<Q*>(luaL_checkudata(L, i, kQuaternion)); }

double* Field(lua_State* L, int i, const char* type, double* fields, const char* names) {
  size_t n = 0;
  const char* key = lua_tolstring(L, i, &n);
  if (key == nullptr || n != 1) return nullptr;
  for (int k = 0; names[k] != '\0'; ++k) {
    if (names[k] == key[0]) return fields + k;
  }
  luaL_error(L, "invalid key '%s' for %s", key, type);
  return nullptr;
}

// __index: a one-letter field, else a method of the metatable.
int IndexOf(lua_State* L, const char* type, double* fields, const char* names) {
  if (double* f = Field(L, 2, type, fields, names)) {
    lua_pushnumber(L, *f);
    return 1;
  }
  luaL_getmetatable(L, type);
  lua_pushvalue(L, 2);
  lua_rawget(L, -2);
  return 1;
}

int NewIndexOf(lua_State* L, const char* type, double* fields, const char* names) {
  double* f = Field(L, 2, type, fields, names);
  if (f == nullptr)
    return luaL_error(L, "%s has no field '%s'", type, luaL_tolstring(L, 2, nullptr));
  *f = luaL_checknumber(L, 3);
  return 0;
}

// --- vector2 -------------------------------------------------------------------------------------

int V2Index(lua_State* L) { return IndexOf(L, kVector2, &CheckV2(L, 1)->x, "xy"); }
int V2NewIndex(lua_State* L) { return NewIndexOf(L, kVector2, &CheckV2(L, 1)->x, "xy"); }

int V2New(lua_State* L) {
  switch (lua_gettop(L)) {
    case 0:
      PushVector2(L, 0, 0);
      return 1;
    case 1: {
      const V2 v = *CheckV2(L, 1);
      PushVector2(L, v.x, v.y);
      return 1;
    }
    case 2:
      PushVector2(L, luaL_checknumber(L, 1), luaL_checknumber(L, 2));
      return 1;
    default:
      return luaL_error(L, "vector2() expects 0, 1 (a vector2) or 2 (x, y) arguments");
  }
}

int V2Add(lua_State* L) {
  const V2 a = *CheckV2(L, 1), b = *CheckV2(L, 2);
  PushVector2(L, a.x + b.x, a.y + b.y);
  return 1;
}
int V2Sub(lua_State* L) {
  const V2 a = *CheckV2(L, 1), b = *CheckV2(L, 2);
  PushVector2(L, a.x - b.x, a.y - b.y);
  return 1;
}
int V2Unm(lua_State* L) {
  const V2 a = *CheckV2(L, 1);
  PushVector2(L, -a.x, -a.y);
  return 1;
}
int V2Mul(lua_State* L) {
  const bool first = lua_isuserdata(L, 1);
  const V2 a = *CheckV2(L, first ? 1 : 2);
  const double k = luaL_checknumber(L, first ? 2 : 1);
  PushVector2(L, a.x * k, a.y * k);
  return 1;
}
int V2Eq(lua_State* L) {
  const V2 a = *CheckV2(L, 1), b = *CheckV2(L, 2);
  lua_pushboolean(L, a.x == b.x && a.y == b.y);
  return 1;
}
// Numbers as ARGoS prints them (a C++ stream: 6 significant digits).
int V2ToString(lua_State* L) {
  const V2 a = *CheckV2(L, 1);
  char text[64];
  std::snprintf(text, sizeof text, "%g,%g", a.x, a.y);
  lua_pushstring(L, text);
  return 1;
}
int V2Length(lua_State* L) {
  const V2 a = *CheckV2(L, 1);
  lua_pushnumber(L, std::hypot(a.x, a.y));
  return 1;
}
int V2Dot(lua_State* L) {
  const V2 a = *CheckV2(L, 1), b = *CheckV2(L, 2);
  lua_pushnumber(L, a.x * b.x + a.y * b.y);
  return 1;
}
int V2Cross(lua_State* L) {
  const V2 a = *CheckV2(L, 1), b = *CheckV2(L, 2);
  lua_pushnumber(L, a.x * b.y - a.y * b.x);
  return 1;
}
int V2Normalize(lua_State* L) {
  V2* a = CheckV2(L, 1);
  const double n = std::hypot(a->x, a->y);
  a->x /= n;
  a->y /= n;
  lua_settop(L, 1);
  return 1;
}
int V2Rotate(lua_State* L) {
  V2* a = CheckV2(L, 1);
  const double angle = luaL_checknumber(L, 2), c = std::cos(angle), s = std::sin(angle);
  const V2 r{a->x * c - a->y * s, a->x * s + a->y * c};
  *a = r;
  lua_settop(L, 1);
  return 1;
}

// --- vector3 -------------------------------------------------------------------------------------

int V3Index(lua_State* L) { return IndexOf(L, kVector3, &CheckV3(L, 1)->x, "xyz"); }
int V3NewIndex(lua_State* L) { return NewIndexOf(L, kVector3, &CheckV3(L, 1)->x, "xyz"); }

int V3New(lua_State* L) {
  switch (lua_gettop(L)) {
    case 0:
      PushVector3(L, 0, 0, 0);
      return 1;
    case 1: {
      const V3 v = *CheckV3(L, 1);
      PushVector3(L, v.x, v.y, v.z);
      return 1;
    }
    case 3:
      PushVector3(L, luaL_checknumber(L, 1), luaL_checknumber(L, 2), luaL_checknumber(L, 3));
      return 1;
    default:
      return luaL_error(L, "vector3() expects 0, 1 (a vector3) or 3 (x, y, z) arguments");
  }
}

int V3Add(lua_State* L) {
  const V3 a = *CheckV3(L, 1), b = *CheckV3(L, 2);
  PushVector3(L, a.x + b.x, a.y + b.y, a.z + b.z);
  return 1;
}
int V3Sub(lua_State* L) {
  const V3 a = *CheckV3(L, 1), b = *CheckV3(L, 2);
  PushVector3(L, a.x - b.x, a.y - b.y, a.z - b.z);
  return 1;
}
int V3Unm(lua_State* L) {
  const V3 a = *CheckV3(L, 1);
  PushVector3(L, -a.x, -a.y, -a.z);
  return 1;
}
int V3Mul(lua_State* L) {
  const bool first = lua_isuserdata(L, 1);
  const V3 a = *CheckV3(L, first ? 1 : 2);
  const double k = luaL_checknumber(L, first ? 2 : 1);
  PushVector3(L, a.x * k, a.y * k, a.z * k);
  return 1;
}
int V3Eq(lua_State* L) {
  const V3 a = *CheckV3(L, 1), b = *CheckV3(L, 2);
  lua_pushboolean(L, a.x == b.x && a.y == b.y && a.z == b.z);
  return 1;
}
int V3ToString(lua_State* L) {
  const V3 a = *CheckV3(L, 1);
  char text[96];
  std::snprintf(text, sizeof text, "%g,%g,%g", a.x, a.y, a.z);
  lua_pushstring(L, text);
  return 1;
}
int V3Length(lua_State* L) {
  const V3 a = *CheckV3(L, 1);
  lua_pushnumber(L, std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z));
  return 1;
}
int V3Dot(lua_State* L) {
  const V3 a = *CheckV3(L, 1), b = *CheckV3(L, 2);
  lua_pushnumber(L, a.x * b.x + a.y * b.y + a.z * b.z);
  return 1;
}
int V3Cross(lua_State* L) {
  V3* a = CheckV3(L, 1);
  const V3 b = *CheckV3(L, 2);
  const V3 r{a->y * b.z - a->z * b.y, a->z * b.x - a->x * b.z, a->x * b.y - a->y * b.x};
  *a = r;
  lua_settop(L, 1);
  return 1;
}
int V3Normalize(lua_State* L) {
  V3* a = CheckV3(L, 1);
  const double n = std::sqrt(a->x * a->x + a->y * a->y + a->z * a->z);
  a->x /= n;
  a->y /= n;
  a->z /= n;
  lua_settop(L, 1);
  return 1;
}

Q Multiply(const Q& a, const Q& b) {
  return {
      a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
      a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

int V3Rotate(lua_State* L) {
  V3* a = CheckV3(L, 1);
  const Q q = *CheckQ(L, 2);
  // v' = q v q* (q taken as a unit quaternion).
  const Q v{0, a->x, a->y, a->z};
  const Q r = Multiply(Multiply(q, v), Q{q.w, -q.x, -q.y, -q.z});
  *a = V3{r.x, r.y, r.z};
  lua_settop(L, 1);
  return 1;
}

// --- quaternion ----------------------------------------------------------------------------------

int QIndex(lua_State* L) { return IndexOf(L, kQuaternion, &CheckQ(L, 1)->w, "wxyz"); }
int QNewIndex(lua_State* L) { return NewIndexOf(L, kQuaternion, &CheckQ(L, 1)->w, "wxyz"); }

int QNew(lua_State* L) {
  switch (lua_gettop(L)) {
    case 0:
      PushQuaternion(L, 1, 0, 0, 0);
      return 1;
    case 1: {
      const Q q = *CheckQ(L, 1);
      PushQuaternion(L, q.w, q.x, q.y, q.z);
      return 1;
    }
    case 2: {
      // Angle (rad) about an axis (a vector3, normalised here).
      const double angle = luaL_checknumber(L, 1);
      const V3 axis = *CheckV3(L, 2);
      const double n = std::sqrt(axis.x * axis.x + axis.y * axis.y + axis.z * axis.z);
      const double s = std::sin(angle / 2) / n;
      PushQuaternion(L, std::cos(angle / 2), axis.x * s, axis.y * s, axis.z * s);
      return 1;
    }
    case 4:
      PushQuaternion(L, luaL_checknumber(L, 1), luaL_checknumber(L, 2), luaL_checknumber(L, 3),
                     luaL_checknumber(L, 4));
      return 1;
    default:
      return luaL_error(L,
                        "quaternion() expects 0, 1 (a quaternion), 2 (angle, axis) or 4 (w, x, y, "
                        "z) arguments");
  }
}

int QMul(lua_State* L) {
  const Q r = Multiply(*CheckQ(L, 1), *CheckQ(L, 2));
  PushQuaternion(L, r.w, r.x, r.y, r.z);
  return 1;
}
int QEq(lua_State* L) {
  const Q a = *CheckQ(L, 1), b = *CheckQ(L, 2);
  lua_pushboolean(L, a.w == b.w && a.x == b.x && a.y == b.y && a.z == b.z);
  return 1;
}

// Z-Y-X Euler angles (yaw, pitch, roll), as ARGoS computes them (with its
// gimbal-lock threshold).
void EulerAngles(const Q& q, double& z, double& y, double& x) {
  const double test = q.x * q.z + q.w * q.y;
  if (test > 0.49999 || test < -0.49999) {
    x = 0;
    y = test > 0 ? M_PI / 2 : -M_PI / 2;
    z = std::atan2(2 * (q.x * q.y + q.w * q.z), 1 - 2 * (q.x * q.x + q.z * q.z));
    return;
  }
  const double w2 = q.w * q.w, x2 = q.x * q.x, y2 = q.y * q.y, z2 = q.z * q.z;
  x = std::atan2(2 * (q.w * q.x - q.y * q.z), w2 - x2 - y2 + z2);
  y = std::asin(2 * (q.x * q.z + q.w * q.y));
  z = std::atan2(2 * (q.w * q.z - q.x * q.y), w2 + x2 - y2 - z2);
}

int QToString(lua_State* L) {
  double z, y, x;
  EulerAngles(*CheckQ(L, 1), z, y, x);
  char text[96];
  std::snprintf(text, sizeof text, "%g,%g,%g", z * 180 / M_PI, y * 180 / M_PI, x * 180 / M_PI);
  lua_pushstring(L, text);
  return 1;
}
int QNormalize(lua_State* L) {
  Q* q = CheckQ(L, 1);
  const double n = std::sqrt(q->w * q->w + q->x * q->x + q->y * q->y + q->z * q->z);
  *q = Q{q->w / n, q->x / n, q->y / n, q->z / n};
  lua_settop(L, 1);
  return 1;
}
int QInverse(lua_State* L) {
  const Q q = *CheckQ(L, 1);
  PushQuaternion(L, q.w, -q.x, -q.y, -q.z);
  return 1;
}
int QToAngleAxis(lua_State* L) {
  const Q q = *CheckQ(L, 1);
  const double square = q.x * q.x + q.y * q.y + q.z * q.z;
  if (square > 0) {
    const double inv = 1 / std::sqrt(square);
    lua_pushnumber(L, 2 * std::acos(std::clamp(q.w, -1.0, 1.0)));
    PushVector3(L, q.x * inv, q.y * inv, q.z * inv);
  } else {
    lua_pushnumber(L, 0);
    PushVector3(L, 0, 0, 1);
  }
  return 2;
}
int QToEulerAngles(lua_State* L) {
  double z, y, x;
  EulerAngles(*CheckQ(L, 1), z, y, x);
  lua_pushnumber(L, z);
  lua_pushnumber(L, y);
  lua_pushnumber(L, x);
  return 3;
}

void Register(lua_State* L, const char* type, const char* constructor, lua_CFunction create,
              const luaL_Reg* methods) {
  lua_pushcfunction(L, create);
  lua_setglobal(L, constructor);
  luaL_newmetatable(L, type);
  luaL_setfuncs(L, methods, 0);
  lua_pop(L, 1);
}

}  // namespace

void RegisterMathTypes(lua_State* L) {
  static const luaL_Reg kV2[] = {{"__index", V2Index},
                                 {"__newindex", V2NewIndex},
                                 {"__tostring", V2ToString},
                                 {"__eq", V2Eq},
                                 {"__add", V2Add},
                                 {"__sub", V2Sub},
                                 {"__unm", V2Unm},
                                 {"__mul", V2Mul},
                                 {"normalize", V2Normalize},
                                 {"length", V2Length},
                                 {"dot", V2Dot},
                                 {"cross", V2Cross},
                                 {"rotate", V2Rotate},
                                 {nullptr, nullptr}};
  static const luaL_Reg kV3[] = {{"__index", V3Index},
                                 {"__newindex", V3NewIndex},
                                 {"__tostring", V3ToString},
                                 {"__eq", V3Eq},
                                 {"__add", V3Add},
                                 {"__sub", V3Sub},
                                 {"__unm", V3Unm},
                                 {"__mul", V3Mul},
                                 {"normalize", V3Normalize},
                                 {"length", V3Length},
                                 {"dot", V3Dot},
                                 {"cross", V3Cross},
                                 {"rotate", V3Rotate},
                                 {nullptr, nullptr}};
  static const luaL_Reg kQ[] = {{"__index", QIndex},
                                {"__newindex", QNewIndex},
                                {"__tostring", QToString},
                                {"__eq", QEq},
                                {"__mul", QMul},
                                {"normalize", QNormalize},
                                {"inverse", QInverse},
                                {"toangleaxis", QToAngleAxis},
                                {"toeulerangles", QToEulerAngles},
                                {nullptr, nullptr}};
  Register(L, kVector2, "vector2", V2New, kV2);
  Register(L, kVector3, "vector3", V3New, kV3);
  Register(L, kQuaternion, "quaternion", QNew, kQ);
}

void PushVector2(lua_State* L, double x, double y) {
  auto* v = static_cast<V2*>(lua_newuserdata(L, sizeof(V2)));
  *v = V2{x, y};
  luaL_setmetatable(L, kVector2);
}

void PushVector3(lua_State* L, double x, double y, double z) {
  auto* v = static_cast<V3*>(lua_newuserdata(L, sizeof(V3)));
  *v = V3{x, y, z};
  luaL_setmetatable(L, kVector3);
}

void PushQuaternion(lua_State* L, double w, double x, double y, double z) {
  auto* q = static_cast<Q*>(lua_newuserdata(L, sizeof(Q)));
  *q = Q{w, x, y, z};
  luaL_setmetatable(L, kQuaternion);
}

void PushYawQuaternion(lua_State* L, double yaw) {
  PushQuaternion(L, std::cos(yaw / 2), 0, 0, std::sin(yaw / 2));
}

}  // namespace colony::lua
