// ARGoS compatibility layer (Colony): CVector2, a vector on the plane. Built
// from (x, y) or from polar coordinates (length, angle), the way controllers
// sum sensor readings: CVector2(reading.Value, reading.Angle).
#pragma once

#include <array>
#include <cmath>
#include <iostream>

#include "argos3/core/utility/datatypes/datatypes.h"
#include "argos3/core/utility/math/angles.h"

namespace argos {

class CVector2 {
 public:
  static const CVector2 X;
  static const CVector2 Y;
  static const CVector2 ZERO;

  constexpr CVector2() : x_(0), y_(0) {}
  constexpr CVector2(Real x, Real y) : x_(x), y_(y) {}
  explicit CVector2(const std::array<Real, 2>& coordinates)
      : x_(coordinates[0]), y_(coordinates[1]) {}
  // Polar coordinates: `length` along `angle` (counter-clockwise from +x).
  CVector2(Real length, const CRadians& angle) : x_(length * Cos(angle)), y_(length * Sin(angle)) {}

  Real GetX() const { return x_; }
  void SetX(Real x) { x_ = x; }
  Real GetY() const { return y_; }
  void SetY(Real y) { y_ = y; }
  void Set(Real x, Real y) {
    x_ = x;
    y_ = y;
  }
  void Set(const std::array<Real, 2>& coordinates) {
    x_ = coordinates[0];
    y_ = coordinates[1];
  }
  void FromPolarCoordinates(Real length, const CRadians& angle) {
    x_ = length * Cos(angle);
    y_ = length * Sin(angle);
  }

  Real SquareLength() const { return x_ * x_ + y_ * y_; }
  Real Length() const { return std::sqrt(SquareLength()); }
  // Scales to length 1 (a zero vector gives NaN, as in ARGoS).
  CVector2& Normalize() {
    *this /= Length();
    return *this;
  }
  // Direction, counter-clockwise from +x, in [-pi, pi].
  CRadians Angle() const { return ATan2(y_, x_); }
  CVector2& Rotate(const CRadians& angle) {
    const Real s = Sin(angle), c = Cos(angle);
    const Real x = x_ * c - y_ * s;
    y_ = x_ * s + y_ * c;
    x_ = x;
    return *this;
  }
  Real DotProduct(const CVector2& other) const { return x_ * other.x_ + y_ * other.y_; }
  // z of the 3D cross product: positive when `other` is counter-clockwise.
  Real CrossProduct(const CVector2& other) const { return x_ * other.y_ - y_ * other.x_; }
  CVector2& Scale(Real scale_x, Real scale_y) {
    x_ *= scale_x;
    y_ *= scale_y;
    return *this;
  }
  // Turns by +90 degrees.
  CVector2& Perpendicularize() {
    const Real x = -y_;
    y_ = x_;
    x_ = x;
    return *this;
  }
  CVector2& Absolute() {
    x_ = std::fabs(x_);
    y_ = std::fabs(y_);
    return *this;
  }

  bool operator==(const CVector2& other) const { return x_ == other.x_ && y_ == other.y_; }
  bool operator!=(const CVector2& other) const { return !(*this == other); }
  CVector2& operator+=(const CVector2& other) {
    x_ += other.x_;
    y_ += other.y_;
    return *this;
  }
  CVector2& operator-=(const CVector2& other) {
    x_ -= other.x_;
    y_ -= other.y_;
    return *this;
  }
  CVector2& operator*=(Real factor) {
    x_ *= factor;
    y_ *= factor;
    return *this;
  }
  CVector2& operator/=(Real divisor) {
    x_ /= divisor;
    y_ /= divisor;
    return *this;
  }
  CVector2 operator+(const CVector2& other) const { return CVector2(x_ + other.x_, y_ + other.y_); }
  CVector2 operator-(const CVector2& other) const { return CVector2(x_ - other.x_, y_ - other.y_); }
  CVector2 operator*(Real factor) const { return CVector2(x_ * factor, y_ * factor); }
  CVector2 operator/(Real divisor) const { return CVector2(x_ / divisor, y_ / divisor); }
  friend CVector2 operator*(Real factor, const CVector2& v) {
    return CVector2(factor * v.x_, factor * v.y_);
  }
  CVector2 operator-() const { return CVector2(-x_, -y_); }

  friend std::ostream& operator<<(std::ostream& os, const CVector2& v) {
    return os << v.x_ << "," << v.y_;
  }
  // Reads "x,y".
  friend std::istream& operator>>(std::istream& is, CVector2& v) {
    Real x = 0, y = 0;
    char comma = 0;
    if (is >> x >> comma >> y && comma == ',') {
      v.Set(x, y);
    } else {
      is.setstate(std::ios::failbit);
    }
    return is;
  }

 private:
  Real x_;
  Real y_;
};

inline const CVector2 CVector2::X{1, 0};
inline const CVector2 CVector2::Y{0, 1};
inline const CVector2 CVector2::ZERO{0, 0};

inline Real SquareDistance(const CVector2& a, const CVector2& b) { return (a - b).SquareLength(); }
inline Real Distance(const CVector2& a, const CVector2& b) { return (a - b).Length(); }

}  // namespace argos
