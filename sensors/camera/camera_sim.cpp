// Simulated cameras: each robot's image is drawn off-screen by the build's
// image renderer (core/image_renderer.h; render/osmesa) from the camera's
// pose on the robot, showing the floor and every entity within range as
// simple shapes. One image renderer per camera configuration draws the images
// one at a time (Mesa spreads each over its own threads); it is made on the
// first update, so a camera that no controller declares costs nothing.
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "core/device.h"
#include "core/drawing.h"
#include "core/image_renderer.h"
#include "core/simulation.h"
#include "entities/marxbot/marxbot.h"
#include "sensors/camera/camera.h"

namespace colony {
namespace {

constexpr double kNearClip = 0.01;           // m
constexpr double kDefaultMountHeight = 0.1;  // m above the robot's base

class CameraSystem;

// Defaults of a camera configuration.
struct Preset {
  int64_t width = 384, height = 128;
  double pixel_aspect = 1, fov = 45, range = 4;
  std::optional<Vec3> position;  // none: the front of the body, kDefaultMountHeight up
  std::array<double, 3> orientation{0, 0, 0};
};

// The marXbot's front camera as the seeds used it (ROBOTS.md; seed 000,
// 5.2.4): the 2048 x 1536 chip binned to 512 x 384 with a normal (4:3)
// view, then each 4 columns averaged: 128 wide x 384 high, each pixel 4
// times as wide as high. It looks level from the top of the robot's front
// (objects of interest lie below it: the seed processed the lower half).
// The sources give neither the lens nor the mount: we put the lens 15.1 cm
// up (just above the top plate) at the body's front (8.5 cm ahead of the
// axis, clear of the LED ring), and choose the field of view so that the
// lowest row meets the floor 30 cm ahead of the body's front, the near end
// of the seed's camera coverage: tan(vertical half-angle) = 0.151 / 0.30 =
// 0.503, horizontal half-angle atan(4/3 x 0.503) = 33.9 degrees.
constexpr double kMarxbotCameraHeight = 0.151;                // m
constexpr double kMarxbotCameraAhead = marxbot::kBodyRadius;  // m
constexpr double kMarxbotBlindTo = 0.30;                      // m ahead of the body's front
Preset MarxbotFrontCamera() {
  Preset p;
  p.width = 128;
  p.height = 384;
  p.pixel_aspect = 4;
  const double tan_vertical =
      kMarxbotCameraHeight / (marxbot::kBodyRadius + kMarxbotBlindTo - kMarxbotCameraAhead);
  p.fov = RadToDeg(2 * std::atan(tan_vertical * 512.0 / 384.0));
  p.range = 4;
  p.position = Vec3(kMarxbotCameraAhead, 0, kMarxbotCameraHeight);
  return p;
}

struct CameraInstance : CameraSensor, InstanceBase, FieldOfView {
  using Interface = CameraSensor;
  Pose mount;  // in the robot's frame: x forwards along the optical axis, z up
  const CameraSystem* system = nullptr;
  // Its frustum, from the lens to the far rectangle at `range`.
  void DrawFieldOfView(const Simulation& sim, DrawList& list) const override;
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
    if (!HaveImageRenderer()) node.ElementError(NoImageRendererMessage("the camera sensor"));
    // A preset gives the defaults; attributes given override them.
    const bool marxbot = node.GetChoice("preset", {"none", "marxbot_front_camera"}, "none") ==
                         "marxbot_front_camera";
    const Preset d = marxbot ? MarxbotFrontCamera() : Preset{};
    width_ = static_cast<int>(node.GetInt("width", d.width, 1, 4096));
    height_ = static_cast<int>(node.GetInt("height", d.height, 1, 4096));
    pixel_aspect_ = node.GetDouble("pixel_aspect", d.pixel_aspect, Range{0, 16, true});
    fov_ = node.GetDouble("fov", d.fov, Range{0, 179, true});
    range_ = node.GetDouble("range", d.range, Range::Positive());
    if (node.Has("position")) {
      const auto p = node.GetTriple("position", {0, 0, 0});
      position_ = Vec3(p[0], p[1], p[2]);
    } else {
      position_ = d.position;
    }
    anchor_ = node.GetString("anchor", "");
    if (marxbot && !anchor_.empty()) {
      node.Error("anchor", anchor_,
                 "the marxbot_front_camera preset sits on the marXbot's body; it takes no anchor");
    }
    const auto o = node.GetTriple("orientation", d.orientation);
    orientation_ = FromEulerZYX(DegToRad(o[0]), DegToRad(o[1]), DegToRad(o[2]));
    noise_ = NoiseModel::Read(node);
  }

  size_t BytesPerRobot() const override { return static_cast<size_t>(width_) * height_ * 3; }

  Sensor* Attach(EntityHandle robot, const RandomStream& rng) override {
    Pose part;
    if (!anchor_.empty() && !sim().Anchor(robot, anchor_, part)) {
      throw AttachError("its physics model gives no '" + anchor_ + "' anchor (attribute 'anchor')");
    }
    CameraInstance& c = instances_.Add(robot, rng);
    const double front = sim().space().geometry(robot.index).BoundingRadius();
    // On a part, at its anchor unless told where; on the body, at its front.
    const Vec3 fallback = anchor_.empty() ? Vec3(front, 0, kDefaultMountHeight) : Vec3::Zero();
    c.mount.position = position_.value_or(fallback);
    c.mount.orientation = orientation_;
    c.Resize(width_, height_);
    c.system = this;
    return &c;
  }
  void Detach(Sensor* s) override { instances_.Remove(static_cast<CameraSensor*>(s)); }
  size_t size() const override { return instances_.size(); }

  void Update(size_t begin, size_t end) override {
    const std::lock_guard lock(mutex_);
    if (!renderer_) renderer_ = MakeImageRenderer(sim());
    for (size_t k = begin; k < end; ++k) {
      if (instances_[k].alive) Render(instances_[k]);
    }
  }

  void Hash(StateHasher& h) const override {
    for (size_t k = 0; k < instances_.size(); ++k) {
      if (instances_[k].alive) h.Add(instances_[k].rgb().data(), instances_[k].rgb().size());
    }
  }

 public:
  CameraView ViewOf(const CameraInstance& c) const {
    // The frame it is mounted on: the robot's body, or a moving part where
    // the physics put it (checked at Attach; a robot migrates only into
    // engines whose model simulates what its devices need).
    Pose frame = sim().space().pose(c.robot.index);
    if (!anchor_.empty()) sim().Anchor(c.robot, anchor_, frame);
    CameraView view;
    view.position = frame.position + frame.orientation * c.mount.position;
    view.orientation = frame.orientation * c.mount.orientation;
    view.fov = fov_;
    view.near_clip = kNearClip;
    view.far_clip = range_;
    view.width = width_;
    view.height = height_;
    view.pixel_aspect = pixel_aspect_;
    return view;
  }

 private:
  void Render(CameraInstance& c) {
    renderer_->Render(ViewOf(c), c.mutable_rgb());
    if (noise_.enabled()) {
      for (uint8_t& v : c.mutable_rgb()) {
        v = static_cast<uint8_t>(std::clamp(noise_.Apply(v / 255.0, c.rng), 0.0, 1.0) * 255 + 0.5);
      }
    }
  }

  int width_ = 384, height_ = 128;
  double pixel_aspect_ = 1, fov_ = 45, range_ = 4;
  std::optional<Vec3> position_;
  Quat orientation_ = Quat::Identity();
  std::string anchor_;  // "": the robot's body
  NoiseModel noise_;
  InstanceStore<CameraInstance> instances_;
  // Drawing, one camera at a time.
  std::mutex mutex_;
  std::unique_ptr<ImageRenderer> renderer_;
};

std::vector<AttributeDoc> CameraAttributes() {
  std::vector<AttributeDoc> a = {
      {"preset", "none, marxbot_front_camera", "none",
       "a configuration whose values are the defaults: marxbot_front_camera is 128 x 384, "
       "pixel_aspect 4, fov 67.7, at the top of the body's front looking level, the floor seen "
       "from 30 cm "
       "ahead of the body"},
      {"width", "a whole number in [1, 4096] (pixels)", "384", "image width"},
      {"height", "a whole number in [1, 4096] (pixels)", "128", "image height"},
      {"pixel_aspect", "a number in (0, 16]", "1",
       "a pixel's width over its height (a camera that averages columns: > 1)"},
      {"fov", "a number in (0, 179] (degrees)", "45", "horizontal field of view"},
      {"range", "a number > 0 (m)", "4", "farthest distance seen (beyond: black)"},
      {"position", "\"x,y,z\" (m, robot frame)", "the body's front, 0.1 m up",
       "where the camera sits on the robot (x forwards, z up, from the centre of its base)"},
      {"orientation", "\"yaw,pitch,roll\" (degrees)", "0,0,0",
       "where it looks, from the robot's front; pitch > 0 tilts it down"},
      {"anchor", "the name of an anchor of the robot's physics model", "none: the body",
       "mounts the camera on a moving part (e.g. a hand-bot's gripper_left), position and "
       "orientation "
       "then in that part's frame"},
  };
  for (auto& n : NoiseModel::Attributes(false)) a.push_back(n);
  return a;
}

COLONY_REGISTER_SENSOR(
    CameraSystem, "camera", "default",
    "perspective colour camera: an RGB image of width x height pixels drawn off-screen "
    "by the image renderer (OSMesa) from its pose on the robot",
    DeviceInterface{
        "sensors/camera/camera.h",
        "colony::CameraSensor",
        {"width(), height(): the image's size (pixels)",
         "rgb(): the image, 3 bytes per pixel (red, green, blue, 0..255), rows from the top",
         "At(x, y): the colony::Color of column x (from the left), row y (from the top)"}},
    CameraAttributes());

void CameraInstance::DrawFieldOfView(const Simulation&, DrawList& list) const {
  const CameraView view = system->ViewOf(*this);
  // Camera frame: x along the optical axis, y left, z up; fov is horizontal.
  const double half_width = view.far_clip * std::tan(DegToRad(view.fov) / 2);
  const double half_height = half_width * view.height / (view.width * view.pixel_aspect);
  Vec3 corners[4];
  const double sides[4][2] = {{1, 1}, {-1, 1}, {-1, -1}, {1, -1}};
  for (int k = 0; k < 4; ++k) {
    corners[k] = view.position + view.orientation * Vec3(view.far_clip, sides[k][0] * half_width,
                                                         sides[k][1] * half_height);
  }
  const Color color{255, 210, 40, 255};
  list.AddPolyline(corners, color, /*closed=*/true);
  for (const Vec3& corner : corners) list.AddSegment(view.position, corner, color);
}

}  // namespace
}  // namespace colony
