// Rays against 3D footprints: boxes and cylinders from the side, from above
// and below, missed over the top, from inside; the floor's and ceiling's
// planes.
#include "core/geometry3d.h"

#include <gtest/gtest.h>

namespace colony {
namespace {

Geometry Box(double x, double y, double z) {
  Geometry g;
  g.shape = ShapeKind::kBox;
  g.size = Vec3(x, y, z);
  return g;
}
Geometry Cylinder(double r, double h) {
  Geometry g;
  g.shape = ShapeKind::kCylinder;
  g.radius = r;
  g.size = Vec3(2 * r, 2 * r, h);
  return g;
}
Pose At(double x, double y, double z, double yaw_degrees = 0) {
  Pose p;
  p.position = Vec3(x, y, z);
  p.orientation = FromYaw(DegToRad(yaw_degrees));
  return p;
}

TEST(Geometry3d, RaysHitABoxFromTheSideFromAboveAndMissOverItsTop) {
  const Geometry box = Box(0.2, 0.2, 0.1);  // base at z = 0, top at 0.1
  const Pose pose = At(1, 0, 0);
  EXPECT_NEAR(RayFootprint3d(Vec3(0, 0, 0.05), Vec3(1, 0, 0), pose, box), 0.9, 1e-12);
  EXPECT_NEAR(RayFootprint3d(Vec3(1, 0, 0.5), Vec3(0, 0, -1), pose, box), 0.4, 1e-12);
  EXPECT_EQ(RayFootprint3d(Vec3(0, 0, 0.15), Vec3(1, 0, 0), pose, box), kNoHit) << "over the top";
  // Slanting down over the top: enters through the top face.
  const Vec3 d = Vec3(1, 0, -1).normalized();
  EXPECT_NEAR(RayFootprint3d(Vec3(0.5, 0, 0.6), d, pose, box), std::sqrt(2.0) * 0.5, 1e-9);
  EXPECT_EQ(RayFootprint3d(Vec3(1, 0, 0.05), Vec3(1, 0, 0), pose, box), 0.0) << "from inside";
  EXPECT_EQ(RayFootprint3d(Vec3(0, 0, 0.05), Vec3(-1, 0, 0), pose, box), kNoHit) << "away from it";
  // Turned 45 degrees: the corner faces the ray, 0.1 sqrt(2) from the centre.
  EXPECT_NEAR(RayFootprint3d(Vec3(0, 0, 0.05), Vec3(1, 0, 0), At(1, 0, 0, 45), box),
              1 - 0.1 * std::sqrt(2.0), 1e-9);
}

TEST(Geometry3d, RaysHitACylinderFromTheSideAndFromBelow) {
  const Geometry c = Cylinder(0.1, 0.5);
  const Pose pose = At(0, 1, 0.2);  // from z = 0.2 to 0.7
  EXPECT_NEAR(RayFootprint3d(Vec3(0, 0, 0.3), Vec3(0, 1, 0), pose, c), 0.9, 1e-12);
  EXPECT_NEAR(RayFootprint3d(Vec3(0.05, 1, 0), Vec3(0, 0, 1), pose, c), 0.2, 1e-12);
  EXPECT_EQ(RayFootprint3d(Vec3(0.15, 1, 0), Vec3(0, 0, 1), pose, c), kNoHit) << "beside it";
  EXPECT_EQ(RayFootprint3d(Vec3(0, 0, 0.1), Vec3(0, 1, 0), pose, c), kNoHit) << "under it";
}

TEST(Geometry3d, HorizontalPlanes) {
  EXPECT_NEAR(RayPlaneZ(Vec3(0, 0, 1), Vec3(0, 0, -1), 0), 1.0, 1e-12);
  EXPECT_NEAR(RayPlaneZ(Vec3(0, 0, 1), Vec3(0.6, 0, 0.8), 2.6), 2.0, 1e-12);
  EXPECT_EQ(RayPlaneZ(Vec3(0, 0, 1), Vec3(0, 0, 1), 0), kNoHit);
  EXPECT_EQ(RayPlaneZ(Vec3(0, 0, 1), Vec3(1, 0, 0), 0), kNoHit);
}

}  // namespace
}  // namespace colony
