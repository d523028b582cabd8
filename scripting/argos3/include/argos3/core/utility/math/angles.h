// ARGoS compatibility layer (Colony): CRadians and CDegrees, angles as
// distinct types so that degrees never pass for radians. Every angle the
// control interface gives is in radians, counter-clockwise, 0 straight ahead.
#pragma once

#include <cmath>
#include <iostream>

#include "argos3/core/utility/datatypes/datatypes.h"
#include "argos3/core/utility/math/general.h"
#include "argos3/core/utility/math/range.h"

#define ARGOS_PI 3.14159265358979323846264338327950288

namespace argos {

class CDegrees;

class CRadians {
 public:
  static const CRadians PI;
  static const CRadians TWO_PI;
  static const CRadians PI_OVER_TWO;
  static const CRadians PI_OVER_THREE;
  static const CRadians PI_OVER_FOUR;
  static const CRadians PI_OVER_SIX;
  static const CRadians ZERO;
  static const CRange<CRadians> SIGNED_RANGE;    // [-pi, pi]
  static const CRange<CRadians> UNSIGNED_RANGE;  // [0, 2 pi]
  static constexpr Real RADIANS_TO_DEGREES = 180.0 / ARGOS_PI;

  constexpr CRadians() : value_(0) {}
  constexpr explicit CRadians(Real value) : value_(value) {}

  void FromValueInDegrees(Real degrees) { value_ = degrees / RADIANS_TO_DEGREES; }
  Real GetValue() const { return value_; }
  Real GetAbsoluteValue() const { return std::fabs(value_); }
  void SetValue(Real value) { value_ = value; }

  // Wraps into [-pi, pi] (a value already inside is unchanged).
  CRadians& SignedNormalize() {
    value_ = Wrap(value_, -ARGOS_PI);
    return *this;
  }
  // Wraps into [0, 2 pi] (a value already inside is unchanged).
  CRadians& UnsignedNormalize() {
    value_ = Wrap(value_, 0);
    return *this;
  }
  CRadians& Negate() {
    value_ = -value_;
    return *this;
  }

  CRadians& operator+() { return *this; }
  CRadians operator-() const { return CRadians(-value_); }
  CRadians& operator+=(const CRadians& other) {
    value_ += other.value_;
    return *this;
  }
  CRadians& operator-=(const CRadians& other) {
    value_ -= other.value_;
    return *this;
  }
  CRadians& operator*=(Real factor) {
    value_ *= factor;
    return *this;
  }
  CRadians& operator/=(Real divisor) {
    value_ /= divisor;
    return *this;
  }
  CRadians operator+(const CRadians& other) const { return CRadians(value_ + other.value_); }
  CRadians operator-(const CRadians& other) const { return CRadians(value_ - other.value_); }
  CRadians operator*(Real factor) const { return CRadians(value_ * factor); }
  friend CRadians operator*(Real factor, const CRadians& angle) {
    return CRadians(factor * angle.value_);
  }
  Real operator/(const CRadians& other) const { return value_ / other.value_; }
  CRadians operator/(Real divisor) const { return CRadians(value_ / divisor); }

  bool operator<(const CRadians& other) const { return value_ < other.value_; }
  bool operator<=(const CRadians& other) const { return value_ <= other.value_; }
  bool operator>(const CRadians& other) const { return value_ > other.value_; }
  bool operator>=(const CRadians& other) const { return value_ >= other.value_; }
  bool operator==(const CRadians& other) const { return value_ == other.value_; }
  bool operator!=(const CRadians& other) const { return value_ != other.value_; }

  friend std::ostream& operator<<(std::ostream& os, const CRadians& angle) {
    return os << "CRadians(" << angle.value_ << " -> " << angle.value_ * RADIANS_TO_DEGREES
              << " degrees)";
  }
  // Reads a number of radians.
  friend std::istream& operator>>(std::istream& is, CRadians& angle) { return is >> angle.value_; }

 private:
  // Into [start, start + 2 pi], by whole turns.
  static Real Wrap(Real value, Real start) {
    const Real turn = 2 * ARGOS_PI;
    if (value >= start && value <= start + turn) return value;
    Real wrapped = std::fmod(value - start, turn);
    if (wrapped < 0) wrapped += turn;
    return start + wrapped;
  }

  Real value_;
};

class CDegrees {
 public:
  static constexpr Real DEGREES_TO_RADIANS = ARGOS_PI / 180.0;

  constexpr CDegrees() : value_(0) {}
  constexpr explicit CDegrees(Real value) : value_(value) {}

  void FromValueInRadians(Real radians) { value_ = radians / DEGREES_TO_RADIANS; }
  Real GetValue() const { return value_; }
  Real GetAbsoluteValue() const { return std::fabs(value_); }
  void SetValue(Real value) { value_ = value; }

  // Wraps into [-180, 180] (a value already inside is unchanged).
  CDegrees& SignedNormalize() {
    value_ = Wrap(value_, -180);
    return *this;
  }
  // Wraps into [0, 360] (a value already inside is unchanged).
  CDegrees& UnsignedNormalize() {
    value_ = Wrap(value_, 0);
    return *this;
  }

  CDegrees& operator+() { return *this; }
  CDegrees operator-() const { return CDegrees(-value_); }
  CDegrees& operator+=(const CDegrees& other) {
    value_ += other.value_;
    return *this;
  }
  CDegrees& operator-=(const CDegrees& other) {
    value_ -= other.value_;
    return *this;
  }
  CDegrees& operator*=(Real factor) {
    value_ *= factor;
    return *this;
  }
  CDegrees& operator/=(Real divisor) {
    value_ /= divisor;
    return *this;
  }
  CDegrees operator+(const CDegrees& other) const { return CDegrees(value_ + other.value_); }
  CDegrees operator-(const CDegrees& other) const { return CDegrees(value_ - other.value_); }
  CDegrees operator*(Real factor) const { return CDegrees(value_ * factor); }
  friend CDegrees operator*(Real factor, const CDegrees& angle) {
    return CDegrees(factor * angle.value_);
  }
  Real operator/(const CDegrees& other) const { return value_ / other.value_; }
  CDegrees operator/(Real divisor) const { return CDegrees(value_ / divisor); }

  bool operator<(const CDegrees& other) const { return value_ < other.value_; }
  bool operator<=(const CDegrees& other) const { return value_ <= other.value_; }
  bool operator>(const CDegrees& other) const { return value_ > other.value_; }
  bool operator>=(const CDegrees& other) const { return value_ >= other.value_; }
  bool operator==(const CDegrees& other) const { return value_ == other.value_; }
  bool operator!=(const CDegrees& other) const { return value_ != other.value_; }

  friend std::ostream& operator<<(std::ostream& os, const CDegrees& angle) {
    return os << "CDegrees(" << angle.value_ << ")";
  }
  // Reads a number of degrees.
  friend std::istream& operator>>(std::istream& is, CDegrees& angle) { return is >> angle.value_; }

 private:
  static Real Wrap(Real value, Real start) {
    if (value >= start && value <= start + 360) return value;
    Real wrapped = std::fmod(value - start, 360.0);
    if (wrapped < 0) wrapped += 360;
    return start + wrapped;
  }

  Real value_;
};

inline const CRadians CRadians::PI{ARGOS_PI};
inline const CRadians CRadians::TWO_PI{2 * ARGOS_PI};
inline const CRadians CRadians::PI_OVER_TWO{ARGOS_PI / 2};
inline const CRadians CRadians::PI_OVER_THREE{ARGOS_PI / 3};
inline const CRadians CRadians::PI_OVER_FOUR{ARGOS_PI / 4};
inline const CRadians CRadians::PI_OVER_SIX{ARGOS_PI / 6};
inline const CRadians CRadians::ZERO{0};
inline const CRange<CRadians> CRadians::SIGNED_RANGE{CRadians(-ARGOS_PI), CRadians(ARGOS_PI)};
inline const CRange<CRadians> CRadians::UNSIGNED_RANGE{CRadians(0), CRadians(2 * ARGOS_PI)};

inline CDegrees ToDegrees(const CRadians& angle) {
  return CDegrees(angle.GetValue() * CRadians::RADIANS_TO_DEGREES);
}
inline CRadians ToRadians(const CDegrees& angle) {
  return CRadians(angle.GetValue() * CDegrees::DEGREES_TO_RADIANS);
}

// a1 - a2 wrapped into [-pi, pi): the smallest turn from a2 to a1.
inline CRadians NormalizedDifference(const CRadians& a1, const CRadians& a2) {
  Real d = std::fmod(a1.GetValue() - a2.GetValue() + ARGOS_PI, 2 * ARGOS_PI);
  if (d < 0) d += 2 * ARGOS_PI;
  return CRadians(d - ARGOS_PI);
}
// a1 - a2 wrapped into [-180, 180).
inline CDegrees NormalizedDifference(const CDegrees& a1, const CDegrees& a2) {
  Real d = std::fmod(a1.GetValue() - a2.GetValue() + 180.0, 360.0);
  if (d < 0) d += 360;
  return CDegrees(d - 180);
}

inline Real Sin(const CRadians& angle) { return std::sin(angle.GetValue()); }
inline Real Cos(const CRadians& angle) { return std::cos(angle.GetValue()); }
inline Real Tan(const CRadians& angle) { return std::tan(angle.GetValue()); }
inline void SinCos(const CRadians& angle, Real& sin, Real& cos) {
  sin = std::sin(angle.GetValue());
  cos = std::cos(angle.GetValue());
}
inline CRadians ASin(Real value) { return CRadians(std::asin(value)); }
inline CRadians ACos(Real value) { return CRadians(std::acos(value)); }
inline CRadians ATan2(Real y, Real x) { return CRadians(std::atan2(y, x)); }

}  // namespace argos
