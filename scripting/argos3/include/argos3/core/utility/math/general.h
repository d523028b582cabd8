// ARGoS compatibility layer (Colony): small numeric helpers of ARGoS's
// general.h (Abs, Min, Max, Sign, Square, rounding, Interpolate). ARGoS
// defines Log, Sqrt, Exp and Mod as macros; here they are functions, so they
// cannot clash with other code.
#pragma once

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "argos3/core/utility/datatypes/datatypes.h"

namespace argos {

template <typename T>
T Abs(const T& value) {
  return value < T() ? -value : value;
}
inline SInt32 Abs(SInt32 value) { return value < 0 ? -value : value; }
inline Real Abs(Real value) { return std::fabs(value); }

inline Real Log(Real value) { return std::log(value); }
inline Real Sqrt(Real value) { return std::sqrt(value); }
inline Real Exp(Real value) { return std::exp(value); }
inline Real Mod(Real value, Real divisor) { return std::fmod(value, divisor); }

template <typename T>
T Min(const T& a, const T& b) {
  return a < b ? a : b;
}
template <typename T>
T& Min(T& a, T& b) {
  return a < b ? a : b;
}
template <typename T>
T Max(const T& a, const T& b) {
  return a > b ? a : b;
}
template <typename T>
T& Max(T& a, T& b) {
  return a > b ? a : b;
}

// 1 for a positive value, -1 for a negative one, 0 for zero.
template <typename T>
SInt32 Sign(const T& value) {
  return (T() < value) - (value < T());
}

template <typename T>
T Square(const T& value) {
  return value * value;
}

inline SInt32 Floor(Real value) { return static_cast<SInt32>(std::floor(value)); }
inline SInt32 Ceil(Real value) { return static_cast<SInt32>(std::ceil(value)); }
// Halves round away from zero.
inline SInt32 Round(Real value) { return static_cast<SInt32>(std::round(value)); }
inline SInt32 RoundClosestToZero(Real value) { return static_cast<SInt32>(std::trunc(value)); }

inline bool DoubleEqAbsolute(Real a, Real b, Real epsilon) { return std::fabs(a - b) <= epsilon; }
// Equal within a relative tolerance of a few units in the last place.
inline bool DoubleEq(Real a, Real b) {
  const Real scale = std::fmax(std::fabs(a), std::fabs(b));
  return std::fabs(a - b) <= 4 * std::numeric_limits<Real>::epsilon() * std::fmax(scale, 1);
}

// Linear interpolation of y at `x` between (x, y) points sorted by x; the
// first or last y outside the points' span.
inline Real Interpolate(Real x, const std::vector<std::pair<Real, Real>>& points) {
  if (points.empty()) return 0;
  if (x <= points.front().first) return points.front().second;
  for (size_t i = 1; i < points.size(); ++i) {
    if (x > points[i].first) continue;
    const auto& [x0, y0] = points[i - 1];
    const auto& [x1, y1] = points[i];
    return x1 == x0 ? y1 : y0 + (y1 - y0) * (x - x0) / (x1 - x0);
  }
  return points.back().second;
}

}  // namespace argos
