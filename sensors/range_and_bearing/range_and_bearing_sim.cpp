// Simulated range-and-bearing receiver: every message of this tick whose
// sender is within the sender's range (3D distance between the two devices),
// except the robot's own, in the order the medium's index gives them; with
// the medium's occlusion check, a message whose straight path crosses a
// solid body other than sender and receiver is lost. Then each message may
// be dropped (drop_probability) and its range and bearing made noisy.
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/device.h"
#include "core/simulation.h"
#include "core/thread_pool.h"
#include "media/fast_math.h"
#include "media/occlusion.h"
#include "media/range_and_bearing/range_and_bearing_medium.h"
#include "sensors/range_and_bearing/range_and_bearing.h"

namespace colony {
namespace {

struct RabReceiverInstance : RangeAndBearingSensor, InstanceBase {
  using Interface = RangeAndBearingSensor;
  std::vector<Packet>& mutable_packets() { return packets_; }
};

// Per-thread working memory of a query (kept between ticks: no allocation
// once warmed up).
struct Scratch {
  std::vector<uint32_t> heard;  // indices of messages in range
  std::vector<float> x, y, z;   // where their senders are in the receiver's frame
  std::vector<float> horizontal, range, bearing, elevation;
  Occluders occluders;
};

constexpr float kPi = static_cast<float>(M_PI);

class RabSensorSystem : public SensorSystem {
 public:
  void Configure(const ConfigNode& node) override {
    medium_ = dynamic_cast<RangeAndBearingMedium*>(sim().MediumFor(node, "range_and_bearing"));
    noise_ = NoiseModel::Read(node);
    bearing_noise_ = node.GetDouble("bearing_noise_std_dev", 0, Range::NonNegative());
  }
  Sensor* Attach(EntityHandle robot, const RandomStream& rng) override {
    return &instances_.Add(robot, rng);
  }
  void Detach(Sensor* s) override { instances_.Remove(static_cast<RangeAndBearingSensor*>(s)); }
  size_t size() const override { return instances_.size(); }

  void Update(size_t begin, size_t end) override {
    ChunkScratch<Scratch> chunk_scratch;  // this thread's (no allocation once warm)
    Scratch& scratch = *chunk_scratch;
    const Space& space = sim().space();
    const RangeAndBearingMedium& medium = *medium_;
    const RangeAndBearingMedium::Message* messages = medium.messages();
    const double reach = medium.max_range();
    const bool occlusions = medium.check_occlusions();
    std::vector<uint32_t>& heard = scratch.heard;
    for (size_t k = begin; k < end; ++k) {
      // Instances and their packet buffers are scattered in memory: ask for
      // the next ones early (the instance four ahead, the buffer of the one
      // two ahead).
      if (k + 4 < end) __builtin_prefetch(&instances_[k + 4]);
      if (k + 2 < end) __builtin_prefetch(instances_[k + 2].packets().data(), 1);
      RabReceiverInstance& r = instances_[k];
      auto& packets = r.mutable_packets();
      packets.clear();
      if (!r.alive) continue;
      const uint32_t self = r.robot.index;
      // Heights are stored as floats in the index: so is the receiver's, so
      // that robots on the same floor have an elevation of exactly 0.
      Vec3 p = RangeAndBearingPoint(space, self);
      p.z() = static_cast<float>(p.z());
      // Messages whose sender is within its range of this receiver, without
      // a branch per candidate (in or out of range is unpredictable).
      size_t n = 0;
      medium.ForEachCandidateRun(p.x(), p.y(), reach, [&](uint32_t b, uint32_t e) {
        if (heard.size() < n + (e - b)) heard.resize(2 * (n + (e - b)));
        uint32_t* out = heard.data();
        for (uint32_t i = b; i < e; ++i) {
          const auto& m = messages[i];
          const double dx = m.x - p.x(), dy = m.y - p.y(), dz = m.z - p.z();
          out[n] = i;
          n += dx * dx + dy * dy + dz * dz <= m.range2;
        }
      });
      if (n == 0) continue;
      // The robot's own message (distance 0) is always in range.
      size_t kept = 0;
      double farthest2 = 0;
      for (size_t j = 0; j < n; ++j) {
        const auto& m = messages[heard[j]];
        if (m.slot == self) continue;
        __builtin_prefetch(medium.payload_bytes() + m.data - sizeof(uint32_t));  // read at the end
        heard[kept++] = heard[j];
        farthest2 =
            std::max(farthest2, (m.x - p.x()) * (m.x - p.x()) + (m.y - p.y()) * (m.y - p.y()));
      }
      n = kept;
      if (occlusions && n > 0) {
        scratch.occluders.clear();
        medium.occluders().Gather(p.x(), p.y(), std::sqrt(farthest2), self, scratch.occluders);
        if (scratch.occluders.size() > 0) {
          kept = 0;
          for (size_t j = 0; j < n; ++j) {
            const auto& m = messages[heard[j]];
            if (!scratch.occluders.Blocked(p, Vec3(m.x, m.y, m.z), m.slot))
              heard[kept++] = heard[j];
          }
          n = kept;
        }
      }
      // Into the receiver's frame with the distances, then bearing and
      // elevation of all of them in one branch-free loop (vectorized).
      if (scratch.x.size() < n) {
        for (auto* v : {&scratch.x, &scratch.y, &scratch.z, &scratch.horizontal, &scratch.range,
                        &scratch.bearing, &scratch.elevation}) {
          v->resize(2 * n);
        }
      }
      float* __restrict x = scratch.x.data();
      float* __restrict y = scratch.y.data();
      float* __restrict z = scratch.z.data();
      float* __restrict horizontal = scratch.horizontal.data();
      float* __restrict range = scratch.range.data();
      float* __restrict bearing = scratch.bearing.data();
      float* __restrict elevation = scratch.elevation.data();
      const Eigen::Matrix3d to_local = space.pose(self).orientation.toRotationMatrix().transpose();
      for (size_t j = 0; j < n; ++j) {
        const auto& m = messages[heard[j]];
        const Vec3 l = to_local * Vec3(m.x - p.x(), m.y - p.y(), m.z - p.z());
        const double horizontal2 = l.x() * l.x() + l.y() * l.y();
        x[j] = static_cast<float>(l.x());
        y[j] = static_cast<float>(l.y());
        z[j] = static_cast<float>(l.z());
        const double h = std::sqrt(horizontal2);
        horizontal[j] = static_cast<float>(h);
        range[j] = static_cast<float>(l.z() == 0 ? h : std::sqrt(horizontal2 + l.z() * l.z()));
      }
      for (size_t j = 0; j < n; ++j) {
        const float b = FastAtan2f(y[j], x[j]);
        bearing[j] = b <= -kPi ? kPi : b;  // (-pi, pi]
        elevation[j] = FastAtan2f(z[j], horizontal[j]);
      }
      // Losses and noise, drawn packet by packet in order.
      for (size_t j = 0; j < n; ++j) {
        if (noise_.Drop(r.rng)) continue;
        float rg = range[j], br = bearing[j];
        if (noise_.kind != NoiseModel::Kind::kNone)
          rg = static_cast<float>(noise_.ApplyNonNegative(rg, r.rng));
        if (bearing_noise_ > 0)
          br = static_cast<float>(WrapAngle(br + r.rng.Gaussian(0, bearing_noise_)));
        packets.push_back({rg, br, elevation[j], medium.payload(messages[heard[j]])});
      }
    }
  }

  void Hash(StateHasher& h) const override {
    for (size_t k = 0; k < instances_.size(); ++k) {
      if (!instances_[k].alive) continue;
      for (const auto& p : instances_[k].packets()) {
        const float v[3] = {p.range, p.bearing, p.elevation};
        h.Add(v, sizeof v);
        h.Add(p.data.data(), p.data.size());
      }
    }
  }

 private:
  RangeAndBearingMedium* medium_ = nullptr;
  NoiseModel noise_;
  double bearing_noise_ = 0;
  InstanceStore<RabReceiverInstance> instances_;
};

std::vector<AttributeDoc> RabSensorAttributes() {
  std::vector<AttributeDoc> a = {
      {"medium", "the id of a <range_and_bearing> in <media>",
       "the only one, or one with default settings", "which medium the messages come from"},
      {"noise", "none, gaussian, uniform", "none", "noise added to each message's range"},
      {"noise_std_dev", "a number >= 0 (m)", "0",
       "standard deviation of gaussian noise on the range"},
      {"noise_range", "\"min,max\" (m)", "0,0", "bounds of uniform noise on the range"},
      {"drop_probability", "a number in [0, 1]", "0", "probability that a message is lost"},
      {"bearing_noise_std_dev", "a number >= 0 (rad)", "0",
       "standard deviation of gaussian noise on the bearing"},
  };
  return a;
}

COLONY_REGISTER_SENSOR(
    RabSensorSystem, "range_and_bearing", "default",
    "range-and-bearing receiver: the messages of the robots within range this tick, each "
    "with the sender's range, bearing and elevation in the robot's frame",
    DeviceInterface{"sensors/range_and_bearing/range_and_bearing.h",
                    "colony::RangeAndBearingSensor",
                    {"packets(): every message received this tick, each: range (m, centre to "
                     "centre), bearing (rad, ccw from the front), elevation (rad), data (the "
                     "sender's bytes, valid until the next tick)"}},
    RabSensorAttributes());

}  // namespace
}  // namespace colony
