// Simulated LEDs: the colours set by the controller are written to the
// entity's LEDs in the space, where cameras and renderers see them.
#include <algorithm>

#include "actuators/leds/leds.h"
#include "core/device.h"
#include "core/simulation.h"

namespace colony {
namespace {

struct LedInstance : Leds, InstanceBase {
  using Interface = Leds;
  std::vector<Color>& mutable_colors() { return colors_; }
};

class LedSystem : public ActuatorSystem {
 public:
  void Configure(const ConfigNode& node) override {
    initial_ = node.GetColor("color", Color::Black());
  }
  Actuator* Attach(EntityHandle robot, const RandomStream& rng) override {
    const size_t n = sim().space().leds(robot.index).size();
    if (n == 0) throw AttachError("it has no LEDs");
    LedInstance& l = instances_.Add(robot, rng);
    l.mutable_colors().assign(n, initial_);
    // Lit from the start, not only after the first tick.
    auto leds = sim().space().leds(robot.index);
    std::fill(leds.begin(), leds.end(), initial_);
    return &l;
  }
  void Detach(Actuator* a) override { instances_.Remove(static_cast<Leds*>(a)); }
  size_t size() const override { return instances_.size(); }

  void Act(size_t begin, size_t end) override {
    Space& space = sim().space();
    for (size_t k = begin; k < end; ++k) {
      LedInstance& l = instances_[k];
      if (!l.alive) continue;
      auto leds = space.leds(l.robot.index);
      std::copy(l.colors().begin(), l.colors().end(), leds.begin());
    }
  }

 private:
  Color initial_ = Color::Black();
  InstanceStore<LedInstance> instances_;
};

COLONY_REGISTER_ACTUATOR(
    LedSystem, "leds", "default", "the robot's RGB LEDs (marXbot: 12 on the ring + the beacon)",
    DeviceInterface{
        "actuators/leds/leds.h",
        "colony::Leds",
        {"count(): how many LEDs",
         "SetSingleColor(index, color), SetAllColors(color): colony::Color (r, g, b, 0..255)",
         "colors(): the colours set"}},
    (std::vector<AttributeDoc>{{"color", kColorAccepted, "black", "colour at start"}}));

}  // namespace
}  // namespace colony
