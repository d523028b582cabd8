// A perspective view: where a camera is, where it looks, and the image it
// makes. Shared by the frame renderer and the robots' camera sensors.
#pragma once

#include <optional>

#include "core/math.h"

namespace colony::render {

struct View {
  Vec3 eye = Vec3(0, 0, 1);
  Vec3 target = Vec3::Zero();
  Vec3 up = Vec3::UnitZ();  // not parallel to target - eye
  double fov = 60;          // horizontal field of view (degrees), in (0, 180)
  double near_clip = 0.01;  // m
  double far_clip = 100;    // m
  int width = 640, height = 480;
  double pixel_aspect = 1;  // a pixel's width over its height (a camera binning columns: > 1)

  // The image's width over its height, in the scene's units.
  double aspect() const { return pixel_aspect * width / height; }
  // Pixels per metre at one metre from the eye.
  double focal_length() const { return width / 2.0 / std::tan(DegToRad(fov) / 2); }
  // World to camera (OpenGL convention: the camera looks along -z).
  Eigen::Matrix4d ViewMatrix() const {
    const Vec3 f = (target - eye).normalized();
    const Vec3 s = f.cross(up).normalized();
    const Vec3 u = s.cross(f);
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.block<1, 3>(0, 0) = s.transpose();
    m.block<1, 3>(1, 0) = u.transpose();
    m.block<1, 3>(2, 0) = -f.transpose();
    m(0, 3) = -s.dot(eye);
    m(1, 3) = -u.dot(eye);
    m(2, 3) = f.dot(eye);
    return m;
  }
  Eigen::Matrix4d ProjectionMatrix() const {
    const double sx = 1.0 / std::tan(DegToRad(fov) / 2);
    Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
    p(0, 0) = sx;
    p(1, 1) = sx * aspect();
    p(2, 2) = (far_clip + near_clip) / (near_clip - far_clip);
    p(2, 3) = 2 * far_clip * near_clip / (near_clip - far_clip);
    p(3, 2) = -1;
    return p;
  }
  // Where `p` appears in the image (pixels, x right, y down from the top-left
  // corner), or nothing when it is behind the camera.
  std::optional<Vec2> ToPixel(const Vec3& p) const {
    const Eigen::Vector4d clip = ProjectionMatrix() * ViewMatrix() * p.homogeneous();
    if (clip.w() <= 1e-9) return std::nullopt;
    return Vec2((clip.x() / clip.w() + 1) / 2 * width, (1 - clip.y() / clip.w()) / 2 * height);
  }
};

// The space a view sees, to skip what cannot show in its image.
class Frustum {
 public:
  explicit Frustum(const View& view)
      : to_camera_(view.ViewMatrix()),
        tan_x_(std::tan(DegToRad(view.fov) / 2)),
        tan_y_(tan_x_ / view.aspect()),
        norm_x_(std::sqrt(1 + tan_x_ * tan_x_)),
        norm_y_(std::sqrt(1 + tan_y_ * tan_y_)),
        near_(view.near_clip),
        far_(view.far_clip) {}
  // False when the sphere lies wholly outside the view.
  bool MayShow(const Vec3& center, double radius) const {
    const Vec3 c = (to_camera_ * center.homogeneous()).head<3>();
    const double depth = -c.z();
    return depth >= near_ - radius && depth <= far_ + radius &&
           std::abs(c.x()) - tan_x_ * depth <= radius * norm_x_ &&
           std::abs(c.y()) - tan_y_ * depth <= radius * norm_y_;
  }

 private:
  Eigen::Matrix4d to_camera_;
  double tan_x_, tan_y_, norm_x_, norm_y_, near_, far_;
};

}  // namespace colony::render
