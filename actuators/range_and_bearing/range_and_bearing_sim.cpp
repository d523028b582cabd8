// Simulated range-and-bearing emitter: every tick, during the act step, each
// robot's payload (or silence) is staged in its range-and-bearing medium,
// which indexes it by the robot's position after physics; receivers read it
// in the same tick's sense step.
#include "actuators/range_and_bearing/range_and_bearing.h"
#include "core/device.h"
#include "core/simulation.h"
#include "media/range_and_bearing/range_and_bearing_medium.h"

namespace colony {
namespace {

constexpr int64_t kDefaultDataSize = 10;   // bytes
constexpr int64_t kMaxDataSize = 1 << 16;  // bytes

struct RabEmitterInstance : RangeAndBearingActuator, InstanceBase {
  using Interface = RangeAndBearingActuator;
  void Init(size_t size) { data_.assign(size, 0); }
  uint32_t emitter = 0;
};

class RabActuatorSystem : public ActuatorSystem {
 public:
  void Configure(const ConfigNode& node) override {
    medium_ = dynamic_cast<RangeAndBearingMedium*>(sim().MediumFor(node, "range_and_bearing"));
    data_size_ = static_cast<size_t>(node.GetInt("data_size", kDefaultDataSize, 1, kMaxDataSize));
    range_ = node.GetDouble(
        "range", medium_ ? medium_->default_range() : RangeAndBearingMedium::kDefaultRange,
        Range::Positive());
  }
  // The payload, and the medium's staged and published copies of it.
  size_t BytesPerRobot() const override { return 3 * data_size_; }
  Actuator* Attach(EntityHandle robot, const RandomStream& rng) override {
    RabEmitterInstance& a = instances_.Add(robot, rng);
    a.Init(data_size_);
    a.emitter = medium_->AddEmitter(robot, range_, data_size_);
    return &a;
  }
  void Detach(Actuator* a) override {
    for (size_t k = 0; k < instances_.size(); ++k) {
      if (static_cast<Actuator*>(&instances_[k]) == a && instances_[k].alive) {
        medium_->RemoveEmitter(instances_[k].emitter);
      }
    }
    instances_.Remove(static_cast<RangeAndBearingActuator*>(a));
  }
  size_t size() const override { return instances_.size(); }

  void Act(size_t begin, size_t end) override {
    for (size_t k = begin; k < end; ++k) {
      // Each payload is a small heap block of its own: ask for the next ones
      // early (the instance four ahead, the payload of the one two ahead).
      if (k + 4 < end) __builtin_prefetch(&instances_[k + 4]);
      if (k + 2 < end) __builtin_prefetch(instances_[k + 2].data().data());
      const RabEmitterInstance& a = instances_[k];
      if (!a.alive) continue;
      medium_->Stage(a.emitter, a.sending(), a.data().data());
    }
  }

 private:
  RangeAndBearingMedium* medium_ = nullptr;
  size_t data_size_ = kDefaultDataSize;
  double range_ = RangeAndBearingMedium::kDefaultRange;
  InstanceStore<RabEmitterInstance> instances_;
};

COLONY_REGISTER_ACTUATOR(
    RabActuatorSystem, "range_and_bearing", "default",
    "range-and-bearing emitter: broadcasts a payload of data_size bytes every tick to the "
    "receivers within range",
    DeviceInterface{"actuators/range_and_bearing/range_and_bearing.h",
                    "colony::RangeAndBearingActuator",
                    {"size(): the payload's size (bytes, data_size)",
                     "SetData(bytes), SetByte(i, value): the payload sent every tick",
                     "Clear(): stop sending; data(), sending()"}},
    (std::vector<AttributeDoc>{
        {"data_size", "an integer in [1, 65536] (bytes)", "10", "size of the payload"},
        {"range", "a number > 0 (m)", "the medium's (3)", "how far the messages reach"},
        {"medium", "the id of a <range_and_bearing> in <media>",
         "the only one, or one with default settings", "which medium carries the messages"},
    }));

}  // namespace
}  // namespace colony
