// Simulated omnidirectional camera: the coloured points of the LED medium
// (lit LEDs of other entities, landmarks) around the robot, each a blob with
// its colour, its horizontal distance from the camera's axis and its bearing
// in the robot's frame. The camera sits on the robot's axis, `elevation`
// above its base, looking all around through a mirror whose vertical field
// spans `aperture` degrees above and below its horizontal plane.
#include <cmath>
#include <limits>
#include <vector>

#include "core/device.h"
#include "core/drawing.h"
#include "core/simulation.h"
#include "core/thread_pool.h"
#include "media/fast_math.h"
#include "media/led/led_medium.h"
#include "media/occlusion.h"
#include "sensors/omnidirectional_camera/omnidirectional_camera.h"

namespace colony {
namespace {

constexpr double kDefaultRange = 1.5;        // m
constexpr double kDefaultAperture = 70.0;    // degrees either side of the horizontal
constexpr double kDefaultElevation = 0.288;  // m above the robot's base

class CameraSystem;

struct CameraInstance : OmnidirectionalCamera, InstanceBase, FieldOfView {
  using Interface = OmnidirectionalCamera;
  std::vector<Blob>& mutable_blobs() { return blobs_; }
  const CameraSystem* system = nullptr;
  // Its range: a circle around the robot's axis at the camera's height.
  void DrawFieldOfView(const Simulation& sim, DrawList& list) const override;
};

// Per-thread working memory of a query (no allocation once warmed up).
struct Scratch {
  Occluders occluders;
};

class CameraSystem : public SensorSystem {
 public:
  void Configure(const ConfigNode& node) override {
    medium_ = dynamic_cast<LedMedium*>(sim().MediumFor(node, "led"));
    range_ = node.GetDouble("range", kDefaultRange, Range::Positive());
    const double aperture = node.GetDouble("aperture", kDefaultAperture, {0.0, 90.0, true});
    elevation_ = node.GetDouble("elevation", kDefaultElevation);
    check_occlusions_ = node.GetBool("check_occlusions", true);
    noise_ = NoiseModel::Read(node);
    bearing_noise_ = node.GetDouble("bearing_noise_std_dev", 0, Range::NonNegative());
    // |height difference| <= distance * tan(aperture); at 90 degrees everything.
    slope_ =
        aperture >= 90.0 ? std::numeric_limits<double>::infinity() : std::tan(DegToRad(aperture));
    if (medium_) {
      medium_->RequestReach(range_);
      if (check_occlusions_) medium_->RequestOcclusions();
    }
  }
  Sensor* Attach(EntityHandle robot, const RandomStream& rng) override {
    CameraInstance& c = instances_.Add(robot, rng);
    c.system = this;
    return &c;
  }
  void Detach(Sensor* s) override { instances_.Remove(static_cast<OmnidirectionalCamera*>(s)); }
  double range() const { return range_; }
  double elevation() const { return elevation_; }
  size_t size() const override { return instances_.size(); }

  void Update(size_t begin, size_t end) override {
    ChunkScratch<Scratch> chunk_scratch;  // this thread's (no allocation once warm)
    Scratch& scratch = *chunk_scratch;
    const Space& space = sim().space();
    const LedMedium& medium = *medium_;
    const auto& leds = medium.leds();
    const double range2 = range_ * range_;
    for (size_t k = begin; k < end; ++k) {
      CameraInstance& c = instances_[k];
      auto& blobs = c.mutable_blobs();
      blobs.clear();
      if (!c.alive) continue;
      const uint32_t self = c.robot.index;
      const Pose& pose = space.pose(self);
      const Eigen::Matrix3d rotation = pose.orientation.toRotationMatrix();
      const Eigen::Matrix3d to_local = rotation.transpose();
      const Vec3 camera = pose.position + rotation * Vec3(0, 0, elevation_);
      bool gathered = false;
      medium.ForEachCandidateRun(camera.x(), camera.y(), range_, [&](uint32_t b, uint32_t e) {
        for (uint32_t i = b; i < e; ++i) {
          const LedMedium::Led& led = leds[i];
          if (led.owner == self) continue;
          const Vec3 l =
              to_local * Vec3(led.x - camera.x(), led.y - camera.y(), led.z - camera.z());
          const double d2 = l.x() * l.x() + l.y() * l.y();
          if (d2 > range2) continue;
          const double distance = std::sqrt(d2);
          if (std::abs(l.z()) > distance * slope_) continue;  // outside the mirror's field
          if (check_occlusions_) {
            if (!gathered) {
              scratch.occluders.clear();
              medium.occluders().Gather(camera.x(), camera.y(), range_, self, scratch.occluders);
              gathered = true;
            }
            if (scratch.occluders.Blocked(camera, Vec3(led.x, led.y, led.z), led.owner)) continue;
          }
          if (noise_.Drop(c.rng)) continue;
          double bearing = FastAtan2(l.y(), l.x());
          if (bearing <= -M_PI) bearing = M_PI;  // (-pi, pi]
          const double noisy = noise_.ApplyNonNegative(distance, c.rng);
          if (bearing_noise_ > 0) bearing = WrapAngle(bearing + c.rng.Gaussian(0, bearing_noise_));
          blobs.push_back({led.color.r, led.color.g, led.color.b, static_cast<float>(noisy),
                           static_cast<float>(bearing)});
        }
      });
    }
  }

  void Hash(StateHasher& h) const override {
    for (size_t k = 0; k < instances_.size(); ++k) {
      if (!instances_[k].alive) continue;
      for (const auto& b : instances_[k].blobs()) {
        const float v[2] = {b.distance, b.bearing};
        const uint8_t rgb[3] = {b.red, b.green, b.blue};
        h.Add(v, sizeof v);
        h.Add(rgb, sizeof rgb);
      }
    }
  }

 private:
  LedMedium* medium_ = nullptr;
  double range_ = kDefaultRange;
  double elevation_ = kDefaultElevation;
  double slope_ = 0;
  bool check_occlusions_ = true;
  NoiseModel noise_;
  double bearing_noise_ = 0;
  InstanceStore<CameraInstance> instances_;
};

std::vector<AttributeDoc> CameraAttributes() {
  std::vector<AttributeDoc> a = {
      {"range", "a number > 0 (m)", "1.5", "how far (horizontally) blobs are seen"},
      {"aperture", "a number in (0, 90] (degrees)", "70",
       "half-height of the mirror's vertical field: blobs more than this above or below the "
       "camera's "
       "horizontal plane are not seen"},
      {"elevation", "a number (m)", "0.288", "height of the camera above the robot's base"},
  };
  for (auto& row : BlobCameraAttributes()) a.push_back(row);
  a.push_back({"bearing_noise_std_dev", "a number >= 0 (rad)", "0",
               "standard deviation of gaussian noise on the bearing"});
  return a;
}

COLONY_REGISTER_SENSOR(
    CameraSystem, "omnidirectional_camera", "default",
    "coloured blobs around the robot (other entities' lit LEDs, landmarks, visible pockets, laser "
    "spots), each with its "
    "colour, distance and bearing in the robot's frame",
    DeviceInterface{
        "sensors/omnidirectional_camera/omnidirectional_camera.h",
        "colony::OmnidirectionalCamera",
        {"blobs(): the blobs seen this tick, each: red, green, blue (0..255), distance (m, "
         "horizontal, from the camera's axis), bearing (rad, ccw from the front, (-pi, pi])"}},
    CameraAttributes(), {"colored_blob_omnidirectional_camera"});

void CameraInstance::DrawFieldOfView(const Simulation& sim, DrawList& list) const {
  const Pose& pose = sim.space().pose(robot.index);
  const Vec3 camera = pose.position + pose.orientation * Vec3(0, 0, system->elevation());
  list.AddCircle(camera, system->range(), Color{255, 210, 40, 255});
}

}  // namespace
}  // namespace colony
