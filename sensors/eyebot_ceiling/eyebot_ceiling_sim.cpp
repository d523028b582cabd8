// Simulated eye-bot ceiling sensor: the attachment's state as the physics
// model left it (CeilingAttachmentState), and the gap between the top of the
// body and the space's ceiling. No noise: a contact switch and the
// attachment's own rangefinder, exact at these distances.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/device.h"
#include "core/simulation.h"
#include "entities/eyebot/eyebot.h"
#include "sensors/eyebot_ceiling/eyebot_ceiling.h"

namespace colony {
namespace {

struct CeilingSensorInstance : EyebotCeilingSensor, InstanceBase {
  using Interface = EyebotCeilingSensor;
  void Set(bool attached, double distance) {
    attached_ = attached;
    ceiling_distance_ = distance;
  }
};

class EyebotCeilingSensorSystem : public SensorSystem {
 public:
  void Configure(const ConfigNode&) override {}
  std::vector<std::string> NeededComponents() const override {
    return {CeilingAttachmentState::kComponentName};
  }
  Sensor* Attach(EntityHandle robot, const RandomStream& rng) override {
    return &instances_.Add(robot, rng);
  }
  void Detach(Sensor* s) override { instances_.Remove(static_cast<EyebotCeilingSensor*>(s)); }
  size_t size() const override { return instances_.size(); }
  void Update(size_t begin, size_t end) override {
    const Space& space = sim().space();
    const auto& ceiling = space.ceiling();
    for (size_t k = begin; k < end; ++k) {
      CeilingSensorInstance& c = instances_[k];
      if (!c.alive) continue;
      const uint32_t s = c.robot.index;
      const double top = space.pose(s).position.z() + space.geometry(s).height();
      c.Set(space.Get<CeilingAttachmentState>(s)->attached,
            ceiling ? std::max(0.0, ceiling->z - top) : std::numeric_limits<double>::infinity());
    }
  }
  void Hash(StateHasher& h) const override {
    for (size_t k = 0; k < instances_.size(); ++k) {
      const CeilingSensorInstance& c = instances_[k];
      if (!c.alive) continue;
      const double v[2] = {c.attached() ? 1.0 : 0.0, c.ceiling_distance()};
      h.Add(v, sizeof v);
    }
  }

 private:
  InstanceStore<CeilingSensorInstance> instances_;
};

COLONY_REGISTER_SENSOR(EyebotCeilingSensorSystem, "eyebot_ceiling", "default",
                       "the eye-bot's ceiling attachment: whether it holds, and the distance "
                       "from the top of the body to the ceiling (m)",
                       DeviceInterface{"sensors/eyebot_ceiling/eyebot_ceiling.h",
                                       "colony::EyebotCeilingSensor",
                                       {"attached(): the robot holds to the ceiling (rotors off)",
                                        "ceiling_distance(): from the top of the body to the "
                                        "ceiling (m); +infinity with no ceiling"}},
                       (std::vector<AttributeDoc>{}));

}  // namespace
}  // namespace colony
