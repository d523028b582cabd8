#include "render/osmesa/scene.h"

#include <algorithm>
#include <cmath>

#include "actuators/handbot_arms/handbot_arms_state.h"
#include "actuators/manipulator/manipulator_state.h"
#include "actuators/rope_launcher/rope_state.h"
#include "core/simulation.h"
#include "entities/eyebot/eyebot.h"
#include "entities/handbot/handbot.h"
#include "entities/marxbot/marxbot.h"

namespace colony::render {
namespace {

using Vec3f = Eigen::Vector3f;
using Vec2f = Eigen::Vector2f;

// Light from above, a little from the south-west: tops are brightest and
// sides show which way they face.
const Vec3f kLight = Vec3f(-0.35f, -0.5f, 1.0f).normalized();
constexpr float kAmbient = 0.45f, kDiffuse = 0.6f;
constexpr float kLightBallRadius = 0.03f;  // m
// A laser spot, drawn larger than a real one (a few mm) to show in frames.
constexpr float kLaserSpotRadius = 0.015f;  // m

Color Scaled(Color c, float k) {
  auto channel = [k](uint8_t v) { return static_cast<uint8_t>(std::min(255.0f, v * k + 0.5f)); };
  return {channel(c.r), channel(c.g), channel(c.b), c.a};
}

std::vector<Vec2f> MakeCircle(int segments) {
  std::vector<Vec2f> points;
  for (int i = 0; i <= segments; ++i) {
    const double a = 2 * M_PI * i / segments;
    points.emplace_back(static_cast<float>(std::cos(a)), static_cast<float>(std::sin(a)));
  }
  return points;
}

// segments + 1 points on the unit circle, the last equal to the first.
const std::vector<Vec2f>& Circle(int segments) {
  static const std::vector<Vec2f> k8 = MakeCircle(8), k12 = MakeCircle(12), k24 = MakeCircle(24),
                                  k32 = MakeCircle(32);
  return segments <= 8 ? k8 : segments <= 12 ? k12 : segments <= 24 ? k24 : k32;
}

// Emits triangles given in an entity's frame, placed at its pose.
class Painter {
 public:
  Painter(std::vector<Vertex>& out, const Pose& pose)
      : out_(out),
        rotation_(pose.orientation.toRotationMatrix().cast<float>()),
        translation_(pose.position.cast<float>()) {}

  // A vertex shaded by its normal `n`.
  void Lit(const Vec3f& p, const Vec3f& n, Color c) {
    Emit(p, Scaled(c, kAmbient + kDiffuse * std::max(0.0f, (rotation_ * n).dot(kLight))));
  }
  // A vertex that shines in its own colour (LEDs, lights).
  void Emit(const Vec3f& p, Color c) {
    const Vec3f w = rotation_ * p + translation_;
    out_.push_back({w.x(), w.y(), w.z(), c.r, c.g, c.b, c.a});
  }
  // a, b, c, d counter-clockwise seen from the side `n` points to.
  void Quad(const Vec3f& a, const Vec3f& b, const Vec3f& c, const Vec3f& d, const Vec3f& n,
            Color color, bool glow = false) {
    for (const Vec3f* v : {&a, &b, &c, &a, &c, &d}) glow ? Emit(*v, color) : Lit(*v, n, color);
  }

  // Upright cylinder on (x, y) from z0 to z1, with its top.
  void Cylinder(float x, float y, float z0, float z1, float radius, int segments, Color c,
                bool glow = false) {
    const auto& circle = Circle(segments);
    const int n = static_cast<int>(circle.size()) - 1;
    const Vec3f up = Vec3f::UnitZ(), top_center(x, y, z1);
    for (int i = 0; i < n; ++i) {
      const Vec2f& u = circle[i];
      const Vec2f& v = circle[i + 1];
      const Vec3f a(x + radius * u.x(), y + radius * u.y(), z0),
          b(x + radius * v.x(), y + radius * v.y(), z0);
      const Vec3f c2(b.x(), b.y(), z1), d(a.x(), a.y(), z1);
      const Vec3f nu(u.x(), u.y(), 0), nv(v.x(), v.y(), 0);
      auto vertex = [&](const Vec3f& p, const Vec3f& normal) {
        glow ? Emit(p, c) : Lit(p, normal, c);
      };
      vertex(a, nu);
      vertex(b, nv);
      vertex(c2, nv);
      vertex(a, nu);
      vertex(c2, nv);
      vertex(d, nu);
      vertex(top_center, up);
      vertex(d, up);
      vertex(c2, up);
    }
  }

  // Box of `size` whose base is centred on `base` (no bottom face).
  void Box(const Vec3f& base, const Vec3f& size, Color c) {
    const Vec3f h(size.x() / 2, size.y() / 2, 0);
    const float z0 = base.z(), z1 = base.z() + size.z();
    auto corner = [&](float sx, float sy, float z) {
      return Vec3f(base.x() + sx * h.x(), base.y() + sy * h.y(), z);
    };
    Quad(corner(-1, -1, z1), corner(1, -1, z1), corner(1, 1, z1), corner(-1, 1, z1), Vec3f::UnitZ(),
         c);
    Quad(corner(1, -1, z0), corner(1, 1, z0), corner(1, 1, z1), corner(1, -1, z1), Vec3f::UnitX(),
         c);
    Quad(corner(-1, 1, z0), corner(-1, -1, z0), corner(-1, -1, z1), corner(-1, 1, z1),
         -Vec3f::UnitX(), c);
    Quad(corner(1, 1, z0), corner(-1, 1, z0), corner(-1, 1, z1), corner(1, 1, z1), Vec3f::UnitY(),
         c);
    Quad(corner(-1, -1, z0), corner(1, -1, z0), corner(1, -1, z1), corner(-1, -1, z1),
         -Vec3f::UnitY(), c);
  }

  // A glowing ball.
  void Ball(const Vec3f& center, float radius, Color c) {
    constexpr int kStacks = 6;
    const auto& circle = Circle(12);
    auto at = [&](int stack, const Vec2f& u) {
      const float polar = static_cast<float>(M_PI) * stack / kStacks;
      return Vec3f(center + radius * Vec3f(std::sin(polar) * u.x(), std::sin(polar) * u.y(),
                                           std::cos(polar)));
    };
    for (int s = 0; s < kStacks; ++s) {
      for (size_t i = 0; i + 1 < circle.size(); ++i) {
        Quad(at(s, circle[i]), at(s + 1, circle[i]), at(s + 1, circle[i + 1]), at(s, circle[i + 1]),
             Vec3f::UnitZ(), c, true);
      }
    }
  }

  // A glowing piece of ring between angles a0 and a1 (rad), cut in `steps`:
  // outer side and top.
  void RingSector(float a0, float a1, float r_in, float r_out, float z0, float z1, int steps,
                  Color c) {
    for (int k = 0; k < steps; ++k) {
      const float b0 = a0 + (a1 - a0) * k / steps, b1 = a0 + (a1 - a0) * (k + 1) / steps;
      const Vec2f u(std::cos(b0), std::sin(b0)), v(std::cos(b1), std::sin(b1));
      const Vec3f n(u.x(), u.y(), 0);
      Quad(Vec3f(r_out * u.x(), r_out * u.y(), z0), Vec3f(r_out * v.x(), r_out * v.y(), z0),
           Vec3f(r_out * v.x(), r_out * v.y(), z1), Vec3f(r_out * u.x(), r_out * u.y(), z1), n, c,
           true);
      Quad(Vec3f(r_in * u.x(), r_in * u.y(), z1), Vec3f(r_out * u.x(), r_out * u.y(), z1),
           Vec3f(r_out * v.x(), r_out * v.y(), z1), Vec3f(r_in * v.x(), r_in * v.y(), z1),
           Vec3f::UnitZ(), c, true);
    }
  }

  // An upright band around the axis between radii r_in and r_out, from z0
  // to z1: outer and inner sides and top (a protective ring).
  void Band(float r_in, float r_out, float z0, float z1, int segments, Color c) {
    const auto& circle = Circle(segments);
    for (size_t i = 0; i + 1 < circle.size(); ++i) {
      const Vec2f& u = circle[i];
      const Vec2f& v = circle[i + 1];
      auto at = [](const Vec2f& w, float r, float z) { return Vec3f(r * w.x(), r * w.y(), z); };
      const Vec3f out(u.x(), u.y(), 0);
      Quad(at(u, r_out, z0), at(v, r_out, z0), at(v, r_out, z1), at(u, r_out, z1), out, c);
      Quad(at(v, r_in, z0), at(u, r_in, z0), at(u, r_in, z1), at(v, r_in, z1), -out, c);
      Quad(at(u, r_in, z1), at(u, r_out, z1), at(v, r_out, z1), at(v, r_in, z1), Vec3f::UnitZ(), c);
    }
  }

  void Triangles(const Mesh& mesh) {
    for (size_t i = 0; i < mesh.positions.size(); ++i)
      Lit(mesh.positions[i], mesh.normals[i], mesh.colors[i]);
  }

 private:
  std::vector<Vertex>& out_;
  Eigen::Matrix3f rotation_;
  Vec3f translation_;
};

// One glowing sector per LED of the ring, centred on the LED's angle.
void AddLedRing(Painter& p, const RingMount& ring, std::span<const Color> leds, Detail detail) {
  const int steps = detail == Detail::kFine ? 2 : 1;
  const float half = static_cast<float>(M_PI / ring.count);
  const float z = static_cast<float>(ring.elevation), r = static_cast<float>(ring.radius);
  const int lit = std::min(ring.count, static_cast<int>(leds.size()));
  for (int i = 0; i < lit; ++i) {
    const float a = static_cast<float>(ring.AngleOf(i));
    p.RingSector(a - half, a + half, r - 0.015f, r + 0.005f, z - 0.01f, z + 0.01f, steps, leds[i]);
  }
}

// The marXbot: treels, body (the docking ring), upper body, LED ring, top
// plate with the front camera's housing (shows the heading from above) and
// the beacon (the LED after the ring's) on top. Coarse: no treels, one body.
void AddMarxbot(Painter& p, Color body, std::span<const Color> leds, const RingMount* ring,
                Detail detail) {
  using namespace marxbot;
  const Color treel{30, 30, 30, 255}, plate{170, 170, 170, 255};
  const float top = static_cast<float>(kBodyHeight), radius = static_cast<float>(kBodyRadius);
  const float ring_bottom = ring ? static_cast<float>(ring->elevation) - 0.01f : 0.12f;
  const bool fine = detail == Detail::kFine;
  const int segments = fine ? 24 : 12;
  if (fine) {
    const float track = static_cast<float>(kWheelBase / 2) - 0.015f;
    p.Box(Vec3f(0, track, 0), Vec3f(0.11f, 0.03f, 0.045f), treel);
    p.Box(Vec3f(0, -track, 0), Vec3f(0.11f, 0.03f, 0.045f), treel);
    p.Cylinder(0, 0, 0, 0.045f, 0.05f, 12, Scaled(body, 0.7f));
    p.Cylinder(0, 0, 0.045f, 0.095f, radius, segments, body);
    p.Cylinder(0, 0, 0.095f, ring_bottom, 0.07f, segments, Scaled(body, 1.3f));
  } else {
    p.Cylinder(0, 0, 0, ring_bottom, radius, segments, body);
  }
  if (ring) AddLedRing(p, *ring, leds, detail);
  p.Cylinder(0, 0, ring_bottom + 0.02f, top, 0.06f, segments, plate);
  p.Box(Vec3f(0.045f, 0, top), Vec3f(0.02f, 0.025f, 0.008f), treel);
  const size_t beacon = ring ? static_cast<size_t>(ring->count) : leds.size();
  if (beacon < leds.size()) {
    p.Cylinder(0, 0, top, top + 0.012f, 0.018f, fine ? 12 : 8, leds[beacon], true);
  }
}

// A pose at `from` whose axis `axis` (x or z) points at `to`.
Pose Towards(const Vec3& from, const Vec3& to, const Vec3& axis) {
  Pose pose;
  pose.position = from;
  const Vec3 d = to - from;
  if (d.squaredNorm() > 1e-12) pose.orientation = Quat::FromTwoVectors(axis, d.normalized());
  return pose;
}

// The marXbot's construction manipulator: its head where the physics put it
// (anchor), on a column in front of the body.
void AddManipulator(std::vector<Vertex>& out, const Simulation& sim, EntityHandle robot,
                    const Pose& robot_pose, Detail detail) {
  Pose head;
  if (!sim.Anchor(robot, ManipulatorState::kHeadAnchor, head)) return;
  using namespace marxbot;
  const Color metal{150, 150, 160, 255}, face{90, 90, 100, 255};
  Painter column(out, robot_pose);
  const float pivot = static_cast<float>(kBodyRadius + 0.5 * kHeadDepth);
  const float top = static_cast<float>(
      (robot_pose.orientation.conjugate() * (head.position - robot_pose.position)).z());
  column.Cylinder(pivot, 0, 0.04f, std::max(0.05f, top), 0.006f, detail == Detail::kFine ? 8 : 6,
                  metal);
  Painter p(out, head);
  p.Box(Vec3f(0, 0, static_cast<float>(-0.5 * kHeadHeight)),
        Vec3f(static_cast<float>(kHeadDepth), static_cast<float>(kHeadWidth),
              static_cast<float>(kHeadHeight)),
        metal);
  // The magnet's face (the head's +x side), darker.
  p.Box(Vec3f(static_cast<float>(0.5 * kHeadDepth), 0, static_cast<float>(-0.4 * kHeadHeight)),
        Vec3f(0.004f, static_cast<float>(0.8 * kHeadWidth), static_cast<float>(0.8 * kHeadHeight)),
        face);
}

// The hand-bot: hull, docking ring LEDs, rope launcher; the head, arms and
// grippers where the physics put them (anchors); the rope to its magnet.
void AddHandbot(std::vector<Vertex>& out, const Simulation& sim, EntityHandle robot,
                const Pose& pose, Color body, std::span<const Color> leds, const RingMount* ring,
                Detail detail) {
  using namespace handbot;
  const int segments = detail == Detail::kFine ? 24 : 12;
  const Color metal{150, 150, 160, 255}, dark{60, 60, 70, 255}, rope{200, 170, 90, 255};
  Painter p(out, pose);
  const float hull = static_cast<float>(kHullHeight), radius = static_cast<float>(kHullRadius);
  const float ring_z = ring ? static_cast<float>(ring->elevation) : 0.13f;
  p.Cylinder(0, 0, 0, ring_z - 0.012f, radius, segments, body);
  p.Cylinder(0, 0, ring_z - 0.012f, ring_z + 0.012f, radius - 0.012f, segments, Scaled(body, 0.8f));
  p.Cylinder(0, 0, ring_z + 0.012f, hull, radius, segments, body);
  if (ring) AddLedRing(p, *ring, leds, detail);
  p.Cylinder(0, 0, hull, static_cast<float>(kHeight), static_cast<float>(kLauncherRadius), 8, dark);
  Pose head;
  if (sim.Anchor(robot, "handbot_head", head)) {
    Painter h(out, head);
    h.Box(Vec3f(0, 0, static_cast<float>(-0.5 * kHeadHeight)),
          Vec3f(static_cast<float>(kHeadDepth), static_cast<float>(kHeadWidth),
                static_cast<float>(kHeadHeight)),
          metal);
    for (int k = 0; k < 2; ++k) {
      Pose grip;
      if (!sim.Anchor(robot, k == 0 ? "gripper_left" : "gripper_right", grip)) continue;
      // The arm: a bar from its shoulder on the head's front to the gripper's base.
      const Vec3 shoulder =
          head.position +
          head.orientation * Vec3(0.5 * kHeadDepth, (k == 0 ? 1 : -1) * kShoulderY, 0);
      const Vec3 base = grip.position - grip.orientation * Vec3(kGripperLength, 0, 0);
      const float length = static_cast<float>((base - shoulder).norm());
      const float t = static_cast<float>(kArmThickness);
      Painter arm(out, Towards(shoulder, base, Vec3::UnitX()));
      arm.Box(Vec3f(0.5f * length, 0, -0.5f * t), Vec3f(length, t, t), metal);
      // The gripper, and its two claws (opened by the aperture).
      Painter g(out, grip);
      const float w = static_cast<float>(kGripperWidth), gl = static_cast<float>(kGripperLength);
      g.Box(Vec3f(-0.5f * gl, 0, -0.5f * w), Vec3f(gl, w, w), dark);
      const auto* arms = sim.space().Get<HandbotArmsState>(robot.index);
      const double open = arms ? arms->claws[k].aperture : M_PI / 2;
      for (int side : {-1, 1}) {
        const float y =
            side * static_cast<float>(0.5 * kGripperWidth * std::sin(0.5 * open) + 0.004);
        g.Box(Vec3f(0.015f, y, -0.006f), Vec3f(0.03f, 0.006f, 0.012f), metal);
      }
    }
  }
  const RopeState* r = sim.space().Get<RopeState>(robot.index);
  if (r && r->attached()) {
    const Vec3 top = pose.position + pose.orientation * Vec3(0, 0, kHeight);
    Painter line(out, Towards(top, r->anchor, Vec3::UnitZ()));
    line.Cylinder(0, 0, 0, static_cast<float>((r->anchor - top).norm()), 0.004f, 6, rope);
    Painter magnet(out, Towards(r->anchor, r->anchor + Vec3(0, 0, 1), Vec3::UnitZ()));
    magnet.Cylinder(0, 0, -0.02f, 0, 0.015f, 8, dark);
  }
}

// The eye-bot: landing legs, central body with the ceiling attachment plate
// on top (and a dark mark at its front), four arms out to the rotors on the
// diagonals, the protective ring around them, the RGB LED (a glowing
// collar under the body) and the pan-tilt head where the physics put it
// (anchor "pan_tilt"; else from the unit's angles): a box along the head's
// axis with the camera's lens and the laser's red aperture on its front.
void AddEyebot(std::vector<Vertex>& out, const Simulation& sim, EntityHandle robot,
               const Pose& pose, Color body, std::span<const Color> leds, Detail detail) {
  using namespace eyebot;
  const bool fine = detail == Detail::kFine;
  const int segments = fine ? 24 : 12;
  const Color metal{150, 150, 160, 255}, dark{45, 45, 50, 255}, rotor{110, 110, 115, 255};
  const float ring_z = static_cast<float>(kRotorZ);
  Painter p(out, pose);
  // Ring, body (10 to 24 cm up) and attachment plate (up to the top).
  p.Band(static_cast<float>(kRadius) - 0.012f, static_cast<float>(kRadius), ring_z - 0.03f,
         ring_z + 0.01f, fine ? 32 : 16, metal);
  p.Cylinder(0, 0, 0.10f, 0.24f, 0.07f, segments, body);
  p.Cylinder(0, 0, 0.24f, static_cast<float>(kHeight), 0.05f, segments, metal);
  p.Box(Vec3f(0.035f, 0, static_cast<float>(kHeight)), Vec3f(0.02f, 0.03f, 0.006f), dark);
  if (!leds.empty()) p.Cylinder(0, 0, 0.085f, 0.10f, 0.05f, segments, leds[0], true);
  for (int k = 0; k < kRotorCount; ++k) {
    Pose arm = pose;
    arm.orientation = pose.orientation * FromYaw(M_PI / 4 + k * M_PI / 2);
    Painter a(out, arm);
    const float hub = static_cast<float>(kRotorArm);
    a.Box(Vec3f(0.5f * hub, 0, ring_z - 0.02f), Vec3f(hub, 0.016f, 0.016f), body);
    a.Cylinder(hub, 0, ring_z - 0.02f, ring_z + 0.012f, 0.015f, 8, dark);
    if (fine) {
      a.Cylinder(hub, 0, ring_z + 0.012f, ring_z + 0.015f, static_cast<float>(kRotorRadius),
                 segments, rotor);
    }
    // A landing leg under each arm, half-way out.
    a.Box(Vec3f(0.6f * hub, 0, 0), Vec3f(0.012f, 0.012f, ring_z - 0.02f), dark);
  }
  Pose head;
  if (!sim.Anchor(robot, "pan_tilt", head)) {
    const PanTiltState* unit = sim.space().Get<PanTiltState>(robot.index);
    if (!unit) return;
    head = PanTiltFrame(pose, *unit);
  }
  // The head's stem (the pan axis) down from the body.
  const Vec3 base = pose.position + pose.orientation * Vec3(0, 0, 0.10);
  Painter stem(out, Towards(base, head.position, Vec3::UnitZ()));
  stem.Cylinder(0, 0, 0, static_cast<float>((head.position - base).norm()), 0.008f, 8, dark);
  Painter h(out, head);
  h.Box(Vec3f(0, 0, -0.018f), Vec3f(0.04f, 0.036f, 0.036f), dark);
  h.Box(Vec3f(0.022f, -0.006f, -0.007f), Vec3f(0.004f, 0.014f, 0.014f), Color{10, 10, 10, 255});
  h.Box(Vec3f(0.021f, 0.011f, -0.003f), Vec3f(0.002f, 0.006f, 0.006f), Color{220, 0, 0, 255});
}

// The outward normal of the surface a laser lit at `spot` (beam: the beam's
// unit direction): up on the floor and a ditch's bottom; a body's top,
// bottom or side; facing the beam on a ditch's wall.
Vec3 SurfaceNormal(const Space& space, const LaserSpot& spot, const Vec3& beam) {
  const Vec3& p = spot.point;
  if (spot.entity == LaserSpot::kFloor) {
    const double z0 = space.arena_min().z();
    const Ditch* ditch = space.floor().DitchAt(p.x(), p.y());
    const double ground = ditch ? z0 - ditch->depth : z0;
    return std::abs(p.z() - ground) < 1e-6 ? Vec3::UnitZ() : Vec3(-beam);
  }
  const Pose& pose = space.pose(spot.entity);
  const Geometry& g = space.geometry(spot.entity);
  const Vec3 local = pose.orientation.conjugate() * (p - pose.position);
  Vec3 n = Vec3::UnitZ();
  if (local.z() <= 1e-6) {
    n = -Vec3::UnitZ();
  } else if (local.z() < g.height() - 1e-6) {
    if (g.shape == ShapeKind::kBox) {
      const bool along_x = std::abs(local.x()) / g.size.x() >= std::abs(local.y()) / g.size.y();
      n = along_x ? Vec3(std::copysign(1.0, local.x()), 0, 0)
                  : Vec3(0, std::copysign(1.0, local.y()), 0);
    } else {
      n = Vec3(local.x(), local.y(), 0).normalized();
    }
  }
  return pose.orientation * n;
}

void AddShape(Painter& p, const Geometry& g, Color c, Detail detail) {
  const float height = static_cast<float>(g.height());
  const int segments = detail == Detail::kFine ? 32 : 12;
  if (g.shape == ShapeKind::kBox) p.Box(Vec3f::Zero(), g.size.cast<float>(), c);
  if (g.shape == ShapeKind::kCylinder) {
    p.Cylinder(0, 0, 0, height, static_cast<float>(g.radius), segments, c);
  }
}

}  // namespace

void AddLine(std::vector<Vertex>& lines, const Vec3& from, const Vec3& to, Color from_color,
             Color to_color) {
  const Vec3f a = from.cast<float>(), b = to.cast<float>();
  lines.push_back({a.x(), a.y(), a.z(), from_color.r, from_color.g, from_color.b, from_color.a});
  lines.push_back({b.x(), b.y(), b.z(), to_color.r, to_color.g, to_color.b, to_color.a});
}

void AddGrid(const Space& space, double spacing, SceneBatch& batch) {
  const Vec3& lo = space.arena_min();
  const Vec3& hi = space.arena_max();
  const Color faint{0, 0, 0, 45};
  // Lines 10 times farther apart until at most kMaxGridLines cross each side.
  constexpr double kMaxGridLines = 2000;
  while (std::max(hi.x() - lo.x(), hi.y() - lo.y()) / spacing > kMaxGridLines) spacing *= 10;
  for (double k = std::ceil(lo.x() / spacing); k * spacing <= hi.x(); ++k) {
    const double x = k * spacing;
    AddLine(batch.floor_lines, Vec3(x, lo.y(), lo.z()), Vec3(x, hi.y(), lo.z()), faint, faint);
  }
  for (double k = std::ceil(lo.y() / spacing); k * spacing <= hi.y(); ++k) {
    const double y = k * spacing;
    AddLine(batch.floor_lines, Vec3(lo.x(), y, lo.z()), Vec3(hi.x(), y, lo.z()), faint, faint);
  }
}

void AddLaserSpots(const Simulation& sim, SceneBatch& batch, bool beams) {
  const Space& space = sim.space();
  const Color red{255, 0, 0, 255};
  const ComponentType pan_tilt = ComponentTypeOf<PanTiltState>();
  // Only types that give their entities a pan-tilt unit (as the eye-bot does
  // to every one): one check per type, not per entity.
  for (size_t t = 0; t < space.type_count(); ++t) {
    const auto& slots = space.OfType(static_cast<uint16_t>(t));
    if (slots.empty() || !space.Has(slots.front(), pan_tilt)) continue;
    for (uint32_t s : slots) {
      const std::optional<LaserSpot> spot = CastLaser(space, s);
      if (!spot) continue;
      const Pose head = PanTiltFrame(space.pose(s), *space.Get<PanTiltState>(s));
      const Vec3 beam = head.orientation * Vec3::UnitX();
      // A thin glowing disc on the surface, lifted 1 mm off it.
      const Vec3 n = SurfaceNormal(space, *spot, beam);
      const Vec3 centre = spot->point + 0.001 * n;
      Painter disc(batch.triangles, Towards(centre, centre + n, Vec3::UnitZ()));
      disc.Cylinder(0, 0, 0, 0.0005f, kLaserSpotRadius, 12, red, true);
      if (beams) AddLine(batch.lines, head.position, spot->point, red, red);
    }
  }
}

void SceneBuilder::AddEntity(uint32_t slot, SceneBatch& batch, Detail detail) const {
  const Space& space = sim_.space();
  Painter p(batch.triangles, space.pose(slot));
  const auto leds = space.leds(slot);
  const RingMount* ring = sim_.MountsOf(space.HandleOf(slot)).Ring("leds");
  if (const Mesh* mesh = meshes_ ? meshes_->For(space, slot) : nullptr) {
    p.Triangles(*mesh);
  } else if (space.TypeLabel(space.type(slot)) == "marxbot") {
    AddMarxbot(p, space.color(slot), leds, ring, detail);
    if (space.Get<ManipulatorState>(slot)) {
      AddManipulator(batch.triangles, sim_, space.HandleOf(slot), space.pose(slot), detail);
    }
    return;
  } else if (space.TypeLabel(space.type(slot)) == "eyebot") {
    AddEyebot(batch.triangles, sim_, space.HandleOf(slot), space.pose(slot), space.color(slot),
              leds, detail);
    return;
  } else if (space.TypeLabel(space.type(slot)) == "handbot") {
    AddHandbot(batch.triangles, sim_, space.HandleOf(slot), space.pose(slot), space.color(slot),
               leds, ring, detail);
    return;
  } else if (space.TypeLabel(space.type(slot)) == "landmark") {
    // A post in its colour; a black landmark is one cameras do not see,
    // so it is not drawn.
    const Color c = space.color(slot);
    if ((c.r | c.g | c.b) == 0) return;
    p.Cylinder(0, 0, 0, static_cast<float>(space.geometry(slot).height()),
               static_cast<float>(space.geometry(slot).radius), detail == Detail::kFine ? 16 : 8,
               space.color(slot));
    return;
  } else if (space.light(slot)) {
    p.Ball(Vec3f::Zero(), kLightBallRadius, leds.empty() ? space.color(slot) : leds[0]);
    return;
  } else {
    AddShape(p, space.geometry(slot), space.color(slot), detail);
  }
  if (ring) AddLedRing(p, *ring, leds, detail);
}

}  // namespace colony::render
