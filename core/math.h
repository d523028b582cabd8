// Geometry types of the core: Eigen vectors and quaternions, SI units
// (metres, radians). Orientation in XML is given in degrees as "yaw,pitch,roll"
// (the ARGoS convention: rotations about Z, then Y, then X).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace colony {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;

inline double DegToRad(double d) { return d * M_PI / 180.0; }
inline double RadToDeg(double r) { return r * 180.0 / M_PI; }

// Rotation about Z of `q` (the heading of a robot on the floor), in (-pi, pi].
inline double YawOf(const Quat& q) {
  return std::atan2(2.0 * (q.w() * q.z() + q.x() * q.y()),
                    1.0 - 2.0 * (q.y() * q.y() + q.z() * q.z()));
}

inline Quat FromYaw(double yaw) { return Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ())); }

inline Quat FromEulerZYX(double yaw, double pitch, double roll) {
  return Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ()) * Eigen::AngleAxisd(pitch, Vec3::UnitY()) *
              Eigen::AngleAxisd(roll, Vec3::UnitX()));
}

// Wraps an angle to (-pi, pi].
inline double WrapAngle(double a) {
  if (a > -M_PI && a <= M_PI) return a;
  a = std::fmod(a - M_PI, 2.0 * M_PI);
  if (a <= -2.0 * M_PI) a += 2.0 * M_PI;
  if (a > 0) a -= 2.0 * M_PI;
  return a + M_PI;
}

struct Pose {
  Vec3 position = Vec3::Zero();
  Quat orientation = Quat::Identity();
};

struct Twist {
  Vec3 linear = Vec3::Zero();   // m/s
  Vec3 angular = Vec3::Zero();  // rad/s
};

// The cell of a uniform grid of `n` cells holding `f` (a position in cell
// units from the grid's start), clamped to [0, n - 1] before the conversion,
// so that no position, far outside the grid or NaN, overflows an int.
inline int ClampedCellIndex(double f, int n) {
  return f >= 1 ? (f < n ? static_cast<int>(f) : n - 1) : 0;
}

}  // namespace colony
