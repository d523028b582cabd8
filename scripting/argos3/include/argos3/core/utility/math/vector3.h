// ARGoS compatibility layer (Colony): CVector3, a vector in space (positions
// in metres, as ARGoS's positioning sensor and entities give them).
#pragma once

#include <array>
#include <cmath>
#include <iostream>

#include "argos3/core/utility/datatypes/datatypes.h"
#include "argos3/core/utility/math/angles.h"
#include "argos3/core/utility/math/vector2.h"

namespace argos {

class CQuaternion;

class CVector3 {
 public:
  static const CVector3 X;
  static const CVector3 Y;
  static const CVector3 Z;
  static const CVector3 ZERO;

  constexpr CVector3() : x_(0), y_(0), z_(0) {}
  constexpr CVector3(Real x, Real y, Real z) : x_(x), y_(y), z_(z) {}
  explicit CVector3(const std::array<Real, 3>& c) : x_(c[0]), y_(c[1]), z_(c[2]) {}
  // Spherical coordinates: inclination from +z, azimuth from +x about z.
  CVector3(Real length, const CRadians& inclination, const CRadians& azimuth) {
    FromSphericalCoords(length, inclination, azimuth);
  }

  Real GetX() const { return x_; }
  void SetX(Real x) { x_ = x; }
  Real GetY() const { return y_; }
  void SetY(Real y) { y_ = y; }
  Real GetZ() const { return z_; }
  void SetZ(Real z) { z_ = z; }
  void Set(Real x, Real y, Real z) {
    x_ = x;
    y_ = y;
    z_ = z;
  }
  void Set(const std::array<Real, 3>& c) { Set(c[0], c[1], c[2]); }

  CVector3& FromSphericalCoords(Real length, const CRadians& inclination, const CRadians& azimuth) {
    x_ = length * Sin(inclination) * Cos(azimuth);
    y_ = length * Sin(inclination) * Sin(azimuth);
    z_ = length * Cos(inclination);
    return *this;
  }
  void ToSphericalCoords(Real& radius, CRadians& inclination, CRadians& azimuth) const {
    radius = Length();
    inclination = radius > 0 ? ACos(z_ / radius) : CRadians::ZERO;
    azimuth = ATan2(y_, x_);
  }

  Real SquareLength() const { return x_ * x_ + y_ * y_ + z_ * z_; }
  Real Length() const { return std::sqrt(SquareLength()); }
  CVector3& Normalize() {
    *this /= Length();
    return *this;
  }
  CVector3& RotateX(const CRadians& angle) {
    const Real s = Sin(angle), c = Cos(angle);
    const Real y = y_ * c - z_ * s;
    z_ = y_ * s + z_ * c;
    y_ = y;
    return *this;
  }
  CVector3& RotateY(const CRadians& angle) {
    const Real s = Sin(angle), c = Cos(angle);
    const Real x = x_ * c + z_ * s;
    z_ = z_ * c - x_ * s;
    x_ = x;
    return *this;
  }
  CVector3& RotateZ(const CRadians& angle) {
    const Real s = Sin(angle), c = Cos(angle);
    const Real x = x_ * c - y_ * s;
    y_ = x_ * s + y_ * c;
    x_ = x;
    return *this;
  }
  // Rotates about z by the angle of `v` (whose length scales too, as in ARGoS).
  CVector3& RotateZ(const CVector2& v) {
    const Real x = x_ * v.GetX() - y_ * v.GetY();
    y_ = x_ * v.GetY() + y_ * v.GetX();
    x_ = x;
    return *this;
  }
  CVector3& Rotate(const CQuaternion& rotation);  // quaternion.h

  CRadians GetAngleWith(const CVector3& other) const {
    return ACos(DotProduct(other) / (Length() * other.Length()));
  }
  CRadians GetXAngle() const { return ATan2(z_, y_); }
  CRadians GetYAngle() const { return ATan2(x_, z_); }
  CRadians GetZAngle() const { return ATan2(y_, x_); }

  Real DotProduct(const CVector3& o) const { return x_ * o.x_ + y_ * o.y_ + z_ * o.z_; }
  // Replaces this vector with this x other.
  CVector3& CrossProduct(const CVector3& o) {
    const Real x = y_ * o.z_ - z_ * o.y_;
    const Real y = z_ * o.x_ - x_ * o.z_;
    z_ = x_ * o.y_ - y_ * o.x_;
    x_ = x;
    y_ = y;
    return *this;
  }
  CVector2& ProjectOntoXY(CVector2& out) const {
    out.Set(x_, y_);
    return out;
  }
  CVector2& ProjectOntoYZ(CVector2& out) const {
    out.Set(y_, z_);
    return out;
  }
  CVector2& ProjectOntoXZ(CVector2& out) const {
    out.Set(x_, z_);
    return out;
  }
  CVector3& Negate() {
    x_ = -x_;
    y_ = -y_;
    z_ = -z_;
    return *this;
  }

  Real operator[](UInt32 i) const { return i == 0 ? x_ : (i == 1 ? y_ : z_); }
  Real& operator[](UInt32 i) { return i == 0 ? x_ : (i == 1 ? y_ : z_); }

  bool operator==(const CVector3& o) const { return x_ == o.x_ && y_ == o.y_ && z_ == o.z_; }
  bool operator!=(const CVector3& o) const { return !(*this == o); }
  // Component-wise: true when it holds for all three (as CRange<CVector3> needs).
  bool operator<(const CVector3& o) const { return x_ < o.x_ && y_ < o.y_ && z_ < o.z_; }
  bool operator<=(const CVector3& o) const { return x_ <= o.x_ && y_ <= o.y_ && z_ <= o.z_; }
  bool operator>(const CVector3& o) const { return x_ > o.x_ && y_ > o.y_ && z_ > o.z_; }
  bool operator>=(const CVector3& o) const { return x_ >= o.x_ && y_ >= o.y_ && z_ >= o.z_; }

  CVector3 operator-() const { return CVector3(-x_, -y_, -z_); }
  CVector3& operator+=(const CVector3& o) {
    x_ += o.x_;
    y_ += o.y_;
    z_ += o.z_;
    return *this;
  }
  CVector3& operator-=(const CVector3& o) {
    x_ -= o.x_;
    y_ -= o.y_;
    z_ -= o.z_;
    return *this;
  }
  CVector3& operator*=(Real f) {
    x_ *= f;
    y_ *= f;
    z_ *= f;
    return *this;
  }
  CVector3& operator/=(Real f) {
    x_ /= f;
    y_ /= f;
    z_ /= f;
    return *this;
  }
  CVector3 operator+(const CVector3& o) const { return CVector3(x_ + o.x_, y_ + o.y_, z_ + o.z_); }
  CVector3 operator-(const CVector3& o) const { return CVector3(x_ - o.x_, y_ - o.y_, z_ - o.z_); }
  CVector3 operator*(Real f) const { return CVector3(x_ * f, y_ * f, z_ * f); }
  CVector3 operator/(Real f) const { return CVector3(x_ / f, y_ / f, z_ / f); }
  friend CVector3 operator*(Real f, const CVector3& v) { return v * f; }

  friend std::ostream& operator<<(std::ostream& os, const CVector3& v) {
    return os << v.x_ << "," << v.y_ << "," << v.z_;
  }
  // Reads "x,y,z".
  friend std::istream& operator>>(std::istream& is, CVector3& v) {
    Real x = 0, y = 0, z = 0;
    char c1 = 0, c2 = 0;
    if (is >> x >> c1 >> y >> c2 >> z && c1 == ',' && c2 == ',') {
      v.Set(x, y, z);
    } else {
      is.setstate(std::ios::failbit);
    }
    return is;
  }

 private:
  Real x_;
  Real y_;
  Real z_;
};

inline const CVector3 CVector3::X{1, 0, 0};
inline const CVector3 CVector3::Y{0, 1, 0};
inline const CVector3 CVector3::Z{0, 0, 1};
inline const CVector3 CVector3::ZERO{0, 0, 0};

inline Real SquareDistance(const CVector3& a, const CVector3& b) { return (a - b).SquareLength(); }
inline Real Distance(const CVector3& a, const CVector3& b) { return (a - b).Length(); }

}  // namespace argos

// CVector3::Rotate needs the quaternion.
#include "argos3/core/utility/math/quaternion.h"
