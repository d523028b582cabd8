// Simulated cameras: each robot's image is drawn off-screen by the osmesa
// renderer's code (render/osmesa) from the camera's pose on the
// robot, showing the floor and every entity within range as simple shapes.
// One OpenGL context per camera configuration draws the images one at a time
// (Mesa spreads each over its own threads); it is made on the first update,
// so a camera that no controller declares costs nothing.
#include "sensors/camera/camera.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "core/device.h"
#include "core/simulation.h"
#include "render/osmesa/offscreen.h"

namespace colony {
namespace {

constexpr double kNearClip = 0.01;           // m
constexpr double kDefaultMountHeight = 0.1;  // m above the robot's base
// Margin around an entity's shape when culling: LEDs and lights stand out of it.
constexpr double kLooseness = 0.05;  // m

struct CameraInstance : CameraSensor, InstanceBase {
  using Interface = CameraSensor;
  Pose mount;  // in the robot's frame: x forwards along the optical axis, z up
  void Resize(int w, int h) {
    width_ = w;
    height_ = h;
    rgb_.assign(static_cast<size_t>(w) * h * 3, 0);
  }
  std::vector<uint8_t>& mutable_rgb() { return rgb_; }
};

class CameraSystem : public SensorSystem {
 public:
  void Configure(const ConfigNode& node) override {
    width_ = static_cast<int>(node.GetInt("width", 384, 1, 4096));
    height_ = static_cast<int>(node.GetInt("height", 128, 1, 4096));
    fov_ = node.GetDouble("fov", 45, Range{0, 179, true});
    range_ = node.GetDouble("range", 4, Range::Positive());
    if (node.Has("position")) {
      const auto p = node.GetTriple("position", {0, 0, 0});
      position_ = Vec3(p[0], p[1], p[2]);
    }
    const auto o = node.GetTriple("orientation", {0, 0, 0});
    orientation_ = FromEulerZYX(DegToRad(o[0]), DegToRad(o[1]), DegToRad(o[2]));
    noise_ = NoiseModel::Read(node);
  }

  size_t BytesPerRobot() const override { return static_cast<size_t>(width_) * height_ * 3; }

  Sensor* Attach(EntityHandle robot, const RandomStream& rng) override {
    CameraInstance& c = instances_.Add(robot, rng);
    const double front = sim().space().geometry(robot.index).BoundingRadius();
    c.mount.position = position_.value_or(Vec3(front, 0, kDefaultMountHeight));
    c.mount.orientation = orientation_;
    c.Resize(width_, height_);
    return &c;
  }
  void Detach(Sensor* s) override { instances_.Remove(static_cast<CameraSensor*>(s)); }
  size_t size() const override { return instances_.size(); }

  void Update(size_t begin, size_t end) override {
    const std::lock_guard lock(mutex_);
    if (!renderer_) renderer_ = std::make_unique<render::OffscreenRenderer>();
    for (size_t k = begin; k < end; ++k) {
      if (instances_[k].alive) Render(instances_[k]);
    }
  }

  void Hash(StateHasher& h) const override {
    for (size_t k = 0; k < instances_.size(); ++k) {
      if (instances_[k].alive) h.Add(instances_[k].rgb().data(), instances_[k].rgb().size());
    }
  }

 private:
  render::View ViewOf(const CameraInstance& c) const {
    const Pose& robot = sim().space().pose(c.robot.index);
    const Quat axes = robot.orientation * c.mount.orientation;
    render::View view;
    view.eye = robot.position + robot.orientation * c.mount.position;
    view.target = view.eye + axes * Vec3::UnitX();
    view.up = axes * Vec3::UnitZ();
    view.fov = fov_;
    view.near_clip = kNearClip;
    view.far_clip = range_;
    view.width = width_;
    view.height = height_;
    return view;
  }

  // The entities that may show in `view`: solid ones within range (from the
  // spatial index) and the others (lights), unless wholly outside the view.
  void BuildScene(const render::View& view) {
    const Space& space = sim().space();
    nearby_.clear();
    space.Gather(view.eye.x() - range_, view.eye.y() - range_, view.eye.x() + range_,
                 view.eye.y() + range_, nearby_);
    for (uint32_t i = 0; i < space.slots(); ++i) {
      if (space.alive(i) && !(space.flags(i) & kSolid)) nearby_.push_back(i);
    }
    const render::Frustum frustum(view);
    const render::SceneBuilder builder(sim(), nullptr);
    batch_.Clear();
    for (uint32_t i : nearby_) {
      const Geometry& g = space.geometry(i);
      const Vec3 center = space.pose(i).position + Vec3(0, 0, g.height() / 2);
      const double radius = std::hypot(g.BoundingRadius(), g.height() / 2) + kLooseness;
      if (frustum.MayShow(center, radius)) builder.AddEntity(i, batch_);
    }
  }

  void Render(CameraInstance& c) {
    const render::View view = ViewOf(c);
    BuildScene(view);
    renderer_->Draw(sim().space(), batch_, view, {}, image_);
    std::swap(c.mutable_rgb(), image_.rgb);
    if (noise_.enabled()) {
      for (uint8_t& v : c.mutable_rgb()) {
        v = static_cast<uint8_t>(std::clamp(noise_.Apply(v / 255.0, c.rng), 0.0, 1.0) * 255 + 0.5);
      }
    }
  }

  int width_ = 384, height_ = 128;
  double fov_ = 45, range_ = 4;
  std::optional<Vec3> position_;
  Quat orientation_ = Quat::Identity();
  NoiseModel noise_;
  InstanceStore<CameraInstance> instances_;
  // Drawing, one camera at a time.
  std::mutex mutex_;
  std::unique_ptr<render::OffscreenRenderer> renderer_;
  std::vector<uint32_t> nearby_;
  render::SceneBatch batch_;
  render::Image image_;
};

std::vector<AttributeDoc> CameraAttributes() {
  std::vector<AttributeDoc> a = {
      {"width", "a whole number in [1, 4096] (pixels)", "384", "image width"},
      {"height", "a whole number in [1, 4096] (pixels)", "128", "image height"},
      {"fov", "a number in (0, 179] (degrees)", "45", "horizontal field of view"},
      {"range", "a number > 0 (m)", "4", "farthest distance seen (beyond: black)"},
      {"position", "\"x,y,z\" (m, robot frame)", "the body's front, 0.1 m up",
       "where the camera sits on the robot (x forwards, z up, from the centre of its base)"},
      {"orientation", "\"yaw,pitch,roll\" (degrees)", "0,0,0",
       "where it looks, from the robot's front; pitch > 0 tilts it down"},
  };
  for (auto& n : NoiseModel::Attributes(false)) a.push_back(n);
  return a;
}

COLONY_REGISTER_SENSOR(
    CameraSystem, "camera", "default",
    "perspective colour camera: an RGB image of width x height pixels drawn off-screen "
    "(OSMesa) from its pose on the robot",
    CameraAttributes());

}  // namespace
}  // namespace colony
