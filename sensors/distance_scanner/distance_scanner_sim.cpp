// Simulated rotating distance scanner. The rotor turns by pi x
// scans_per_second x dt per tick (a scan is half a turn: with two sensors of
// each type opposite each other, each type then covers 360 degrees). Every
// sensor samples m times per half turn (m = 60 at 1 scan/s, 30 at 2 scans/s:
// about 60 samples per second, the 3 and 6 degree resolutions of seed 000);
// each sample is one horizontal ray in the scan plane from the sensor's face
// against the footprints of the solid bodies whose height spans the plane.
//
// The Sharp sensors' response is modelled as a voltage V(d) of the distance d
// from the sensor's face that rises as d falls down to the sensor's minimum
// range, where it peaks, and falls again below it:
//   d >= min: V = Vp (min + b) / (d + b)         (the datasheets' 1/(d + b) law)
//   d <  min: V = Vp (f0 + (1 - f0) d / min)     (the fold: f0 Vp at contact)
// The robot inverts the monotonic branch, d = (min + b) Vp / V - b, so an
// object nearer than min reads farther than it is. Beyond max (or a voltage
// below V(max)) there is no reading; a ray meeting a surface more obliquely
// than max_incidence gives none either (the sensors see such surfaces, and
// corners that reflect the beam away, as holes).
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "core/device.h"
#include "core/entity_type.h"
#include "core/geometry2d.h"
#include "core/simulation.h"
#include "sensors/distance_scanner/distance_scanner.h"

namespace colony {
namespace {

// The response curve of one sensor type (distances from the sensor's face).
struct SharpCurve {
  double min_range = 0, max_range = 0;  // m: the monotonic branch
  double offset = 0;                    // b (m)
  double peak_voltage = 0;              // Vp (V), at min_range
  double contact_fraction = 0;          // f0: V at contact / Vp

  double Voltage(double d) const {
    if (d >= min_range) return peak_voltage * (min_range + offset) / (d + offset);
    return peak_voltage *
           (contact_fraction + (1.0 - contact_fraction) * std::max(d, 0.0) / min_range);
  }
  // The distance the robot computes from a voltage (monotonic branch).
  double Distance(double v) const { return (min_range + offset) * peak_voltage / v - offset; }
};

// GP2D120-like (the GP2Y3A001K0F of the marXbot, 4-30 cm): its datasheet
// linearises the output against 1 / (d + 0.42 cm); about 2.75 V at 4 cm.
constexpr SharpCurve kShortCurve{0.04, 0.30, 0.0042, 2.75, 0.2};
// GP2Y0A02-like (the GP2Y3A002K0F, 20-150 cm): about 2.5 V at 20 cm and
// 0.45 V at 150 cm, which b = 8.5 cm reproduces.
constexpr SharpCurve kLongCurve{0.20, 1.50, 0.085, 2.5, 0.2};

constexpr int kSensors = 4;
constexpr float kNoReading = DistanceScanner::kNoReading;
using Reading = DistanceScanner::Reading;
using SensorType = DistanceScanner::SensorType;

// A body a ray may hit, relative to the robot's axis.
struct Candidate {
  Vec2 center;   // of its footprint's bounding circle, from the robot's axis (m)
  double bound;  // radius of that circle (m)
  double near;   // distance from the axis to the circle (m)
  uint32_t slot;
};

struct ScannerInstance : DistanceScanner, InstanceBase {
  using Interface = DistanceScanner;
  const RingMount* mount = nullptr;
  uint64_t next_sample = 0;   // index of the next sample (sample k: rotor at k x bin width)
  uint64_t first_sample = 0;  // the first sample this instance took
  std::array<std::vector<float>, 2> filling;  // the scan being read
  std::vector<Reading>& mutable_readings() { return readings_; }
  std::array<std::vector<float>, 2>& mutable_scans() { return scans_; }
  void Publish() {
    std::swap(scans_[0], filling[0]);
    std::swap(scans_[1], filling[1]);
    ++scans_completed_;
  }
  void SetRotor(double angle) { rotor_angle_ = angle; }
  void SetBinWidth(double w) { bin_width_ = w; }
};

class DistanceScannerSystem : public SensorSystem {
 public:
  void Configure(const ConfigNode& node) override {
    // At least 0.01: at most 12,000 bins per scan (0.03 degrees each).
    scans_per_second_ = node.GetDouble("scans_per_second", 1.0, Range::Between(0.01, 2.0));
    curves_[0] = ReadRange(node, "short_range", kShortCurve);
    curves_[1] = ReadRange(node, "long_range", kLongCurve);
    cos_max_incidence_ =
        std::cos(DegToRad(node.GetDouble("max_incidence", 70.0, Range::Between(0, 90))));
    noise_ = NoiseModel::Read(node);
    // m samples per sensor per half turn, even so that the long-range
    // sensors (a quarter turn from the short ones) fall on the same bins.
    per_half_turn_ = 2 * std::max<int64_t>(1, std::llround(30.0 / scans_per_second_));
    bins_ = 2 * per_half_turn_;
    bin_width_ = 2.0 * M_PI / bins_;
    samples_per_second_ = per_half_turn_ * scans_per_second_;
    rotor_.resize(bins_);
    bin_angle_.resize(bins_);
    for (int64_t i = 0; i < bins_; ++i) {
      rotor_[i] = Vec2(std::cos(i * bin_width_), std::sin(i * bin_width_));
      bin_angle_[i] = static_cast<float>(WrapAngle(i * bin_width_));
    }
  }

  // The scan and the one being read, of both sensor types.
  size_t BytesPerRobot() const override { return 4 * static_cast<size_t>(bins_) * sizeof(float); }

  Sensor* Attach(EntityHandle robot, const RandomStream& rng) override {
    const RingMount* mount = sim().MountsOf(robot).Ring("distance_scanner");
    if (!mount) throw AttachError("it has no distance scanner");
    if (mount->count != kSensors) throw AttachError("its distance scanner does not have 4 sensors");
    ScannerInstance& s = instances_.Add(robot, rng);
    s.mount = mount;
    s.SetBinWidth(bin_width_);
    for (int t = 0; t < 2; ++t) {
      s.mutable_scans()[t].assign(bins_, kNoReading);
      s.filling[t].assign(bins_, kNoReading);
    }
    // Every rotor started at angle 0 at time 0; one added later joins in phase.
    s.next_sample = SampleAt(sim().time()) + 1;
    s.first_sample = s.next_sample;
    s.mutable_readings().reserve(kSensors *
                                 (static_cast<size_t>(sim().dt() * samples_per_second_) + 2));
    return &s;
  }
  void Detach(Sensor* s) override { instances_.Remove(static_cast<DistanceScanner*>(s)); }
  size_t size() const override { return instances_.size(); }

  // Each sensor sweeps a narrow wedge during a tick (18 degrees at 1 scan/s
  // and 10 ticks/s), so each gathers from the spatial index only the bodies
  // near the bounding box of its wedge, keeps those that can meet a ray
  // inside it (culled by height, distance and angle), sorted by how near they
  // come to the robot's axis. The rays are radial (they start on the rotor's
  // rim and point away from the axis), so a ray stops at the first candidate
  // beyond its best hit or its sensor's range.
  void Update(size_t begin, size_t end) override {
    const Space& space = sim().space();
    const uint64_t last = SampleAt((sim().tick() + 1) * sim().dt());
    const int64_t quarter = per_half_turn_ / 2;  // bins in a quarter turn
    std::vector<uint32_t> gathered;              // per chunk
    std::array<std::vector<Candidate>, kSensors> candidates;
    gathered.reserve(256);
    for (auto& v : candidates) v.reserve(256);
    for (size_t k = begin; k < end; ++k) {
      ScannerInstance& s = instances_[k];
      if (!s.alive) continue;
      s.mutable_readings().clear();
      if (s.next_sample > last) continue;
      const Pose& pose = space.pose(s.robot.index);
      const RingMount& m = *s.mount;
      const Vec2 c = pose.position.head<2>();
      const double z = pose.position.z() + m.elevation;
      const double yaw = YawOf(pose.orientation);
      const double cy = std::cos(yaw), sy = std::sin(yaw);
      // Sensor j looks j quarter turns (j x m / 2 bins) ccw from the rotor.
      // Bin arithmetic is incremental: a 64-bit division per ray would cost
      // more than the ray.
      auto bin_of = [&](int64_t rotor_bin, int j) {
        const int64_t b = rotor_bin + j * quarter;
        return b >= bins_ ? b - bins_ : b;
      };
      auto world = [&](int64_t bin) {
        const Vec2& l = rotor_[bin];
        return Vec2(cy * l.x() - sy * l.y(), sy * l.x() + cy * l.y());
      };
      const int64_t first_bin = static_cast<int64_t>(s.next_sample % bins_);
      const int64_t last_bin = static_cast<int64_t>(last % bins_);
      const bool narrow = static_cast<double>(last - s.next_sample) * bin_width_ <= M_PI / 2;
      if (narrow) {
        for (int j = 0; j < kSensors; ++j) {
          const Wedge wedge{world(bin_of(first_bin, j)), world(bin_of(last_bin, j)),
                            m.radius + curves_[j % 2].max_range};
          Collect(space, s.robot.index, c, z, wedge, gathered, candidates[j]);
        }
      } else {
        // A tick sweeps a quarter turn or more: one full circle for all.
        const Wedge all{Vec2::Zero(), Vec2::Zero(),
                        m.radius + std::max(curves_[0].max_range, curves_[1].max_range)};
        Collect(space, s.robot.index, c, z, all, gathered, candidates[0]);
        for (int j = 1; j < kSensors; ++j) candidates[j] = candidates[0];
      }
      int64_t rotor_bin = first_bin;
      int64_t phase =
          static_cast<int64_t>(s.next_sample % per_half_turn_);  // sample's place in its half turn
      for (uint64_t sample = s.next_sample; sample <= last; ++sample) {
        for (int j = 0; j < kSensors; ++j) {
          const int64_t bin = bin_of(rotor_bin, j);
          const int type = j % 2;
          const float distance =
              Measure(space, candidates[j], c, world(bin), m.radius, type, s.rng);
          s.filling[type][bin] = distance;
          s.mutable_readings().push_back(
              {bin_angle_[bin], distance, static_cast<uint8_t>(j), static_cast<SensorType>(type)});
        }
        // A scan ends every half turn; publish it if this robot read all of it.
        if (phase == 0 && sample + 1 >= s.first_sample + per_half_turn_) s.Publish();
        if (++rotor_bin == bins_) rotor_bin = 0;
        if (++phase == per_half_turn_) phase = 0;
      }
      s.next_sample = last + 1;
      s.SetRotor(static_cast<double>(last_bin) * bin_width_);
    }
  }

  void Hash(StateHasher& h) const override {
    for (size_t k = 0; k < instances_.size(); ++k) {
      const ScannerInstance& s = instances_[k];
      if (!s.alive) continue;
      h.AddU64(s.scans_completed());
      for (const Reading& r : s.readings()) {
        const float v[2] = {r.angle, r.distance};
        h.Add(v, sizeof v);
      }
      for (const SensorType type : {DistanceScanner::kShortRange, DistanceScanner::kLongRange}) {
        h.Add(s.scan(type).data(), s.scan(type).size() * sizeof(float));
      }
    }
  }

 private:
  // The rays of one sensor during a tick: from the robot's axis, between
  // directions u0 and u1 (ccw, at most a quarter turn apart), up to `reach`
  // (m); u0 = u1 = 0 stands for the whole circle.
  struct Wedge {
    Vec2 u0, u1;
    double reach;
    bool whole() const { return u0.isZero(); }
  };

  // The bodies that can meet a ray of `wedge` (the robot's own excepted),
  // relative to the axis c, nearest first.
  static void Collect(const Space& space, uint32_t self, const Vec2& c, double z,
                      const Wedge& wedge, std::vector<uint32_t>& gathered,
                      std::vector<Candidate>& out) {
    // The wedge's bounding box: the apex, the two ends of the arc, and the
    // arc's extreme points along the axes that lie within it.
    Vec2 lo = c, hi = c;
    Vec2 mid = Vec2::Zero();
    if (wedge.whole()) {
      lo -= Vec2(wedge.reach, wedge.reach);
      hi += Vec2(wedge.reach, wedge.reach);
    } else {
      mid = (wedge.u0 + wedge.u1).normalized();
      auto include = [&](const Vec2& u) {
        const Vec2 p = c + wedge.reach * u;
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      };
      include(wedge.u0);
      include(wedge.u1);
      for (const Vec2& e : {Vec2(1, 0), Vec2(0, 1), Vec2(-1, 0), Vec2(0, -1)}) {
        if (Cross(wedge.u0, e) >= 0 && Cross(e, wedge.u1) >= 0 && e.dot(mid) > 0) include(e);
      }
    }
    gathered.clear();
    space.Gather(lo.x(), lo.y(), hi.x(), hi.y(), gathered);
    out.clear();
    for (uint32_t o : gathered) {
      if (o == self) continue;
      const Vec3& op = space.pose(o).position;
      const Geometry& og = space.geometry(o);
      if (!(z >= op.z() && z < op.z() + og.height())) continue;
      const Vec2 rel = op.head<2>() - c;
      const double bound = og.BoundingRadius();
      const double near = rel.norm() - bound;
      if (near >= wedge.reach) continue;
      // A disc meeting a ray at an angle within [u0, u1] lies at most its
      // radius clockwise of u0's line, ccw of u1's line and behind the
      // wedge's middle direction.
      if (!wedge.whole() && (Cross(wedge.u0, rel) < -bound || Cross(rel, wedge.u1) < -bound ||
                             rel.dot(mid) < -bound)) {
        continue;
      }
      out.push_back({rel, bound, near, o});
    }
    std::sort(out.begin(), out.end(), [](const Candidate& a, const Candidate& b) {
      return a.near < b.near || (a.near == b.near && a.slot < b.slot);
    });
  }

  static double Cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

  // The index of the last sample taken at or before time t.
  uint64_t SampleAt(double t) const {
    return static_cast<uint64_t>(std::floor(t * samples_per_second_ + 1e-9));
  }

  static SharpCurve ReadRange(const ConfigNode& node, const char* attribute, SharpCurve curve) {
    const auto range =
        node.GetPair(attribute, {curve.min_range, curve.max_range}, Range::Positive());
    if (range[0] >= range[1]) {
      node.Error(attribute, node.GetString(attribute, ""),
                 "the minimum range must be below the maximum; accepted: \"min,max\" with 0 < min "
                 "< max (m)");
      return curve;
    }
    curve.min_range = range[0];
    curve.max_range = range[1];
    return curve;
  }

  // The distance (from the robot's axis) the robot computes for one ray along
  // `dir` from the point `radius` from the axis, or kNoReading.
  float Measure(const Space& space, const std::vector<Candidate>& candidates, const Vec2& axis,
                const Vec2& dir, double radius, int type, RandomStream& rng) const {
    const SharpCurve& curve = curves_[type];
    const Vec2 origin = axis + radius * dir;
    const double reach = radius + curve.max_range;
    double best = kNoHit;  // along the ray from the sensor's face
    uint32_t hit = 0;
    for (const Candidate& k : candidates) {
      // A hit on this body (and on every later one) lies at least k.near
      // from the axis, i.e. k.near - radius along the ray.
      if (k.near > std::min(reach, radius + best)) break;
      // Cheap rejection by the bounding circle.
      if (k.center.dot(dir) <= -k.bound ||
          std::abs(k.center.x() * dir.y() - k.center.y() * dir.x()) >= k.bound) {
        continue;
      }
      const double t = RayFootprint(origin, dir, space.pose(k.slot), space.geometry(k.slot));
      if (t < best) {
        best = t;
        hit = k.slot;
      }
    }
    if (best > curve.max_range) return kNoReading;
    if (-dir.dot(SurfaceNormal(space.pose(hit), space.geometry(hit), origin + best * dir, dir)) <
        cos_max_incidence_) {
      return kNoReading;
    }
    const double voltage = curve.Voltage(best);
    if (voltage < curve.Voltage(curve.max_range)) return kNoReading;
    double d = curve.Distance(voltage);
    if (noise_.enabled()) {
      if (noise_.Drop(rng)) return kNoReading;
      d = std::clamp(noise_.Apply(d, rng), curve.min_range, curve.max_range);
    }
    return static_cast<float>(radius + d);
  }

  // Outward unit normal of a footprint at boundary point p (a ray starting
  // inside the footprint gets -dir: it faces the surface head-on).
  static Vec2 SurfaceNormal(const Pose& pose, const Geometry& g, const Vec2& p, const Vec2& dir) {
    if (g.shape == ShapeKind::kCylinder) {
      const Vec2 n = p - pose.position.head<2>();
      const double len = n.norm();
      return len > 1e-12 ? Vec2(n / len) : Vec2(-dir);
    }
    const Rect rect = RectOf(pose, g);
    const Vec2 local = rect.ToLocal(p);
    const double fx = std::abs(local.x()) / rect.half.x(), fy = std::abs(local.y()) / rect.half.y();
    if (std::max(fx, fy) < 1.0 - 1e-9) return -dir;
    // The face the point lies on, in the world frame.
    const Vec2 n_local =
        fx >= fy ? Vec2(std::copysign(1.0, local.x()), 0) : Vec2(0, std::copysign(1.0, local.y()));
    return Vec2(rect.cos_yaw * n_local.x() - rect.sin_yaw * n_local.y(),
                rect.sin_yaw * n_local.x() + rect.cos_yaw * n_local.y());
  }

  double scans_per_second_ = 1;
  std::array<SharpCurve, 2> curves_{kShortCurve, kLongCurve};
  double cos_max_incidence_ = 0;
  NoiseModel noise_;
  int64_t per_half_turn_ = 60, bins_ = 120;
  double bin_width_ = 0, samples_per_second_ = 60;
  std::vector<Vec2> rotor_;       // unit vector of the rotor at each bin
  std::vector<float> bin_angle_;  // each bin's angle wrapped to (-pi, pi]
  InstanceStore<ScannerInstance> instances_;
};

std::vector<AttributeDoc> ScannerAttributes() {
  std::vector<AttributeDoc> a = {
      {"scans_per_second", "a number in [0.01, 2]", "1",
       "full 360-degree scans per second (half a rotor turn each); bins of 3 degrees x "
       "scans_per_second"},
      {"short_range", "\"min,max\", 0 < min < max (m)", "0.04,0.3",
       "monotonic range of the two short-range sensors, from their faces"},
      {"long_range", "\"min,max\", 0 < min < max (m)", "0.2,1.5",
       "monotonic range of the two long-range sensors, from their faces"},
      {"max_incidence", "a number in [0, 90] (degrees)", "70",
       "a surface met more obliquely than this gives no reading"},
  };
  for (auto& n : NoiseModel::Attributes()) a.push_back(n);
  return a;
}

COLONY_REGISTER_SENSOR(
    DistanceScannerSystem, "distance_scanner", "default",
    "rotating scanner of 4 Sharp IR sensors (2 short, 2 long range): (angle, distance) "
    "readings with each sensor's dead zone and folded response curve",
    DeviceInterface{
        "sensors/distance_scanner/distance_scanner.h",
        "colony::DistanceScanner",
        {"readings(): this tick's readings, each: angle (rad, ccw from the front), distance (m, or "
         "kNoReading = -1), sensor (0..3), type (kShortRange, kLongRange)",
         "scan(type): the last complete scan of a sensor type, one distance (m) per bin of "
         "bin_width() rad",
         "bin_width(): angle between two bins (rad)", "scans_completed(): complete scans so far",
         "rotor_angle(): the rotor's angle from the front, [0, 2 pi) (rad)"}},
    ScannerAttributes(), {"footbot_distance_scanner"});

}  // namespace
}  // namespace colony
