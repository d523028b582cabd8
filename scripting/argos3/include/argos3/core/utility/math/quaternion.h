// ARGoS compatibility layer (Colony): CQuaternion, an orientation in space
// (w, x, y, z). The positioning sensor gives the robot's orientation as one;
// on the floor it is a rotation about z: ToEulerAngles gives that heading
// first.
#pragma once

#include <cmath>
#include <iostream>

#include "argos3/core/utility/datatypes/datatypes.h"
#include "argos3/core/utility/math/angles.h"
#include "argos3/core/utility/math/vector3.h"

namespace argos {

class CQuaternion {
 public:
  CQuaternion() : w_(1), x_(0), y_(0), z_(0) {}
  CQuaternion(Real w, Real x, Real y, Real z) : w_(w), x_(x), y_(y), z_(z) {}
  // A rotation by `angle` about `axis` (a unit vector).
  CQuaternion(const CRadians& angle, const CVector3& axis) { FromAngleAxis(angle, axis); }
  // The rotation taking `from` onto `to`.
  CQuaternion(const CVector3& from, const CVector3& to) { BetweenTwoVectors(from, to); }

  Real GetW() const { return w_; }
  Real GetX() const { return x_; }
  Real GetY() const { return y_; }
  Real GetZ() const { return z_; }
  void SetW(Real w) { w_ = w; }
  void SetX(Real x) { x_ = x; }
  void SetY(Real y) { y_ = y; }
  void SetZ(Real z) { z_ = z; }
  void Set(Real w, Real x, Real y, Real z) {
    w_ = w;
    x_ = x;
    y_ = y;
    z_ = z;
  }

  CQuaternion Conjugate() const { return CQuaternion(w_, -x_, -y_, -z_); }
  CQuaternion Inverse() const {
    const Real n = SquareLength();
    return CQuaternion(w_ / n, -x_ / n, -y_ / n, -z_ / n);
  }
  Real SquareLength() const { return w_ * w_ + x_ * x_ + y_ * y_ + z_ * z_; }
  Real Length() const { return std::sqrt(SquareLength()); }
  CQuaternion& Normalize() {
    const Real n = Length();
    w_ /= n;
    x_ /= n;
    y_ /= n;
    z_ /= n;
    return *this;
  }

  CQuaternion& FromAngleAxis(const CRadians& angle, const CVector3& axis) {
    const CRadians half = angle * 0.5;
    const Real s = Sin(half);
    Set(Cos(half), axis.GetX() * s, axis.GetY() * s, axis.GetZ() * s);
    return *this;
  }
  void ToAngleAxis(CRadians& angle, CVector3& axis) const {
    const Real s2 = x_ * x_ + y_ * y_ + z_ * z_;
    if (s2 <= 0) {
      angle = CRadians::ZERO;
      axis = CVector3::X;
      return;
    }
    const Real inv = 1 / std::sqrt(s2);
    angle = CRadians(2 * std::acos(std::fmax(-1.0, std::fmin(1.0, w_))));
    axis.Set(x_ * inv, y_ * inv, z_ * inv);
  }
  // Rotation about z, then about the new y, then about the new x (ARGoS's
  // and Colony's "yaw,pitch,roll").
  CQuaternion& FromEulerAngles(const CRadians& z_angle, const CRadians& y_angle,
                               const CRadians& x_angle) {
    *this = CQuaternion(z_angle, CVector3::Z) * CQuaternion(y_angle, CVector3::Y) *
            CQuaternion(x_angle, CVector3::X);
    return *this;
  }
  void ToEulerAngles(CRadians& z_angle, CRadians& y_angle, CRadians& x_angle) const {
    z_angle = ATan2(2 * (w_ * z_ + x_ * y_), 1 - 2 * (y_ * y_ + z_ * z_));
    y_angle = ASin(std::fmax(-1.0, std::fmin(1.0, 2 * (w_ * y_ - z_ * x_))));
    x_angle = ATan2(2 * (w_ * x_ + y_ * z_), 1 - 2 * (x_ * x_ + y_ * y_));
  }
  CQuaternion& BetweenTwoVectors(const CVector3& from, const CVector3& to) {
    CVector3 axis(from);
    axis.CrossProduct(to);
    const Real w = std::sqrt(from.SquareLength() * to.SquareLength()) + from.DotProduct(to);
    if (w <= 1e-12 * std::sqrt(from.SquareLength() * to.SquareLength())) {
      // Opposite vectors: half a turn about any axis perpendicular to `from`.
      CVector3 perpendicular = std::fabs(from.GetX()) > std::fabs(from.GetZ())
                                   ? CVector3(-from.GetY(), from.GetX(), 0)
                                   : CVector3(0, -from.GetZ(), from.GetY());
      perpendicular.Normalize();
      Set(0, perpendicular.GetX(), perpendicular.GetY(), perpendicular.GetZ());
      return *this;
    }
    Set(w, axis.GetX(), axis.GetY(), axis.GetZ());
    return Normalize();
  }

  bool operator==(const CQuaternion& o) const {
    return w_ == o.w_ && x_ == o.x_ && y_ == o.y_ && z_ == o.z_;
  }
  CQuaternion& operator+=(const CQuaternion& o) {
    Set(w_ + o.w_, x_ + o.x_, y_ + o.y_, z_ + o.z_);
    return *this;
  }
  CQuaternion& operator-=(const CQuaternion& o) {
    Set(w_ - o.w_, x_ - o.x_, y_ - o.y_, z_ - o.z_);
    return *this;
  }
  // Hamilton product: this rotation after `o`.
  CQuaternion& operator*=(const CQuaternion& o) {
    Set(w_ * o.w_ - x_ * o.x_ - y_ * o.y_ - z_ * o.z_,  //
        w_ * o.x_ + x_ * o.w_ + y_ * o.z_ - z_ * o.y_,  //
        w_ * o.y_ - x_ * o.z_ + y_ * o.w_ + z_ * o.x_,  //
        w_ * o.z_ + x_ * o.y_ - y_ * o.x_ + z_ * o.w_);
    return *this;
  }
  CQuaternion operator+(const CQuaternion& o) const { return CQuaternion(*this) += o; }
  CQuaternion operator-(const CQuaternion& o) const { return CQuaternion(*this) -= o; }
  CQuaternion operator*(const CQuaternion& o) const { return CQuaternion(*this) *= o; }
  // Writes and reads "z,y,x": the Euler angles in degrees, as XML gives them.
  friend std::ostream& operator<<(std::ostream& os, const CQuaternion& q) {
    CRadians z, y, x;
    q.ToEulerAngles(z, y, x);
    return os << ToDegrees(z).GetValue() << "," << ToDegrees(y).GetValue() << ","
              << ToDegrees(x).GetValue();
  }
  friend std::istream& operator>>(std::istream& is, CQuaternion& q) {
    CVector3 angles;
    if (is >> angles) {
      q.FromEulerAngles(ToRadians(CDegrees(angles.GetX())), ToRadians(CDegrees(angles.GetY())),
                        ToRadians(CDegrees(angles.GetZ())));
    }
    return is;
  }

 private:
  friend class CVector3;
  // The vector `v` rotated by this (unit) quaternion.
  CVector3 Rotate(const CVector3& v) const {
    const CQuaternion p = *this * CQuaternion(0, v.GetX(), v.GetY(), v.GetZ()) * Conjugate();
    return CVector3(p.x_, p.y_, p.z_);
  }

  Real w_, x_, y_, z_;
};

inline CVector3& CVector3::Rotate(const CQuaternion& rotation) {
  *this = rotation.Rotate(*this);
  return *this;
}

}  // namespace argos
