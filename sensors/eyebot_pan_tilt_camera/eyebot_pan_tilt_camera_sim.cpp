// Simulated eye-bot pan-tilt camera: the coloured points of the LED medium
// (other entities' lit LEDs, landmarks, laser spots, and the spot of the
// robot's own laser) inside a cone of half-angle fov/2 around the head's
// axis (PanTiltFrame), within `range` of the head; each a blob with its
// colour, its distance from the head, and its bearing and elevation in the
// robot's frame.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/device.h"
#include "core/drawing.h"
#include "core/simulation.h"
#include "core/thread_pool.h"
#include "entities/eyebot/eyebot.h"
#include "media/fast_math.h"
#include "media/led/led_medium.h"
#include "media/occlusion.h"
#include "sensors/eyebot_pan_tilt_camera/eyebot_pan_tilt_camera.h"

namespace colony {
namespace {

constexpr double kDefaultFov = 60.0;   // degrees, the whole cone
constexpr double kDefaultRange = 5.0;  // m

class PanTiltCameraSystem;

struct CameraInstance : EyebotPanTiltCamera, InstanceBase, FieldOfView {
  using Interface = EyebotPanTiltCamera;
  const PanTiltCameraSystem* system = nullptr;
  // Its cone: the rim at `range` from the head and four of its sides.
  void DrawFieldOfView(const Simulation& sim, DrawList& list) const override;
  std::vector<Blob>& mutable_blobs() { return blobs_; }
  void SetHead(double pan, double tilt) {
    pan_ = pan;
    tilt_ = tilt;
  }
};

// Per-thread working memory of a query (no allocation once warmed up).
struct Scratch {
  Occluders occluders;
};

class PanTiltCameraSystem : public SensorSystem {
 public:
  void Configure(const ConfigNode& node) override {
    medium_ = dynamic_cast<LedMedium*>(sim().MediumFor(node, "led"));
    const double fov = node.GetDouble("fov", kDefaultFov, {0.0, 180.0, true});
    if (fov >= 180.0) {
      node.Error("fov", node.GetString("fov", ""),
                 "'" + node.GetString("fov", "") +
                     "' is out of range; accepted: a number in (0, 180) (degrees)");
    }
    cos_half_fov_ = std::cos(DegToRad(std::min(fov, 179.0)) / 2);
    range_ = node.GetDouble("range", kDefaultRange, Range::Positive());
    check_occlusions_ = node.GetBool("check_occlusions", true);
    noise_ = NoiseModel::Read(node);
    angle_noise_ = node.GetDouble("angle_noise_std_dev", 0, Range::NonNegative());
    if (medium_) {
      medium_->RequestReach(range_);
      if (check_occlusions_) medium_->RequestOcclusions();
    }
  }
  std::vector<std::string> NeededComponents() const override {
    return {PanTiltState::kComponentName};
  }
  Sensor* Attach(EntityHandle robot, const RandomStream& rng) override {
    CameraInstance& c = instances_.Add(robot, rng);
    c.system = this;
    return &c;
  }
  void Detach(Sensor* s) override { instances_.Remove(static_cast<EyebotPanTiltCamera*>(s)); }
  double range() const { return range_; }
  double half_fov() const { return std::acos(cos_half_fov_); }
  size_t size() const override { return instances_.size(); }

  void Update(size_t begin, size_t end) override {
    ChunkScratch<Scratch> chunk_scratch;  // this thread's (no allocation once warm)
    Scratch& scratch = *chunk_scratch;
    const Space& space = sim().space();
    const LedMedium& medium = *medium_;
    const auto& leds = medium.leds();
    for (size_t k = begin; k < end; ++k) {
      CameraInstance& c = instances_[k];
      c.mutable_blobs().clear();
      if (!c.alive) continue;
      const uint32_t self = c.robot.index;
      const Pose& body = space.pose(self);
      const PanTiltState& unit = *space.Get<PanTiltState>(self);
      c.SetHead(unit.pan, unit.tilt);
      const Pose head = PanTiltFrame(body, unit);
      View view{head.position, head.orientation * Vec3::UnitX(),
                body.orientation.toRotationMatrix().transpose()};
      bool gathered = false;
      auto see = [&](const LedMedium::Led& led) {
        const Vec3 v(led.x - view.eye.x(), led.y - view.eye.y(), led.z - view.eye.z());
        const double d2 = v.squaredNorm();
        if (d2 > range_ * range_) return;
        const double distance = std::sqrt(d2);
        if (v.dot(view.axis) < cos_half_fov_ * distance) return;  // outside the cone
        if (check_occlusions_) {
          if (!gathered) {
            scratch.occluders.clear();
            medium.occluders().Gather(view.eye.x(), view.eye.y(), range_, self, scratch.occluders);
            gathered = true;
          }
          if (scratch.occluders.Blocked(view.eye, Vec3(led.x, led.y, led.z), led.owner)) return;
        }
        Report(c, led, view.to_robot * v, distance);
      };
      // Other entities' points; then the robot's own laser spot (its LED is
      // not seen).
      medium.ForEachCandidateRun(view.eye.x(), view.eye.y(), range_, [&](uint32_t b, uint32_t e) {
        for (uint32_t i = b; i < e; ++i) {
          if (leds[i].owner != self) see(leds[i]);
        }
      });
      if (const LedMedium::Led* own = medium.LaserSpotOf(self)) see(*own);
    }
  }

  void Hash(StateHasher& h) const override {
    for (size_t k = 0; k < instances_.size(); ++k) {
      if (!instances_[k].alive) continue;
      for (const auto& b : instances_[k].blobs()) {
        const float v[3] = {b.distance, b.bearing, b.elevation};
        const uint8_t rgb[3] = {b.red, b.green, b.blue};
        h.Add(v, sizeof v);
        h.Add(rgb, sizeof rgb);
      }
    }
  }

 private:
  // The head as one query sees it.
  struct View {
    Vec3 eye;                  // the head's centre (world frame)
    Vec3 axis;                 // unit, along the camera's axis
    Eigen::Matrix3d to_robot;  // world to the robot's frame (directions)
  };

  // Adds the blob of `led`, at `local` (robot frame) from the head, with noise.
  void Report(CameraInstance& c, const LedMedium::Led& led, const Vec3& local,
              double distance) const {
    if (noise_.Drop(c.rng)) return;
    double bearing = FastAtan2(local.y(), local.x());
    if (bearing <= -M_PI) bearing = M_PI;  // (-pi, pi]
    double elevation = FastAtan2(local.z(), std::hypot(local.x(), local.y()));
    if (angle_noise_ > 0) {
      bearing = WrapAngle(bearing + c.rng.Gaussian(0, angle_noise_));
      elevation = std::clamp(elevation + c.rng.Gaussian(0, angle_noise_), -M_PI / 2, M_PI / 2);
    }
    const double noisy = noise_.ApplyNonNegative(distance, c.rng);
    c.mutable_blobs().push_back({led.color.r, led.color.g, led.color.b, static_cast<float>(noisy),
                                 static_cast<float>(bearing), static_cast<float>(elevation)});
  }

  LedMedium* medium_ = nullptr;
  double cos_half_fov_ = std::cos(DegToRad(kDefaultFov) / 2);
  double range_ = kDefaultRange;
  bool check_occlusions_ = true;
  NoiseModel noise_;
  double angle_noise_ = 0;
  InstanceStore<CameraInstance> instances_;
};

std::vector<AttributeDoc> CameraAttributes() {
  std::vector<AttributeDoc> a = {
      {"fov", "a number in (0, 180) (degrees)", "60",
       "the field of view: a cone of half this angle around the head's axis"},
      {"range", "a number > 0 (m)", "5", "how far from the head blobs are seen"},
  };
  for (auto& row : BlobCameraAttributes()) a.push_back(row);
  a.push_back({"angle_noise_std_dev", "a number >= 0 (rad)", "0",
               "standard deviation of gaussian noise on the bearing and on the elevation"});
  return a;
}

COLONY_REGISTER_SENSOR(
    PanTiltCameraSystem, "eyebot_pan_tilt_camera", "default",
    "the eye-bot's pan-tilt camera: coloured blobs (other robots' lit LEDs, landmarks, laser "
    "spots, its own laser's spot) in its field of view, each with its colour, distance, bearing "
    "and elevation in the robot's frame",
    DeviceInterface{"sensors/eyebot_pan_tilt_camera/eyebot_pan_tilt_camera.h",
                    "colony::EyebotPanTiltCamera",
                    {"blobs(): the blobs seen this tick, each: red, green, blue (0..255), distance "
                     "(m, from the head), bearing (rad, ccw from the front), elevation (rad, above "
                     "the horizontal plane)",
                     "pan(), tilt(): the head's pan and tilt when the blobs were taken (rad)"}},
    CameraAttributes());

void CameraInstance::DrawFieldOfView(const Simulation& sim, DrawList& list) const {
  const Space& space = sim.space();
  const Pose head = PanTiltFrame(space.pose(robot.index), *space.Get<PanTiltState>(robot.index));
  const Vec3 axis = head.orientation * Vec3::UnitX(), u = head.orientation * Vec3::UnitY(),
             v = head.orientation * Vec3::UnitZ();
  const double half = system->half_fov(), range = system->range();
  constexpr int kSides = 32;
  Vec3 rim[kSides];
  for (int k = 0; k < kSides; ++k) {
    const double t = 2 * M_PI * k / kSides;
    rim[k] = head.position +
             range * (std::cos(half) * axis + std::sin(half) * (std::cos(t) * u + std::sin(t) * v));
  }
  const Color color{255, 210, 40, 255};
  list.AddPolyline(rim, color, /*closed=*/true);
  for (int k = 0; k < kSides; k += kSides / 4) list.AddSegment(head.position, rim[k], color);
}

}  // namespace
}  // namespace colony
