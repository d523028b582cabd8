// Simulated battery: every tick the charge falls by
//   idle_power x dt + motion_energy x (|left wheel travel| + |right wheel travel|) / 2
// (J), the wheel travel being what the engine reports the wheels did in that
// tick. When it reaches 0 and stop_when_empty is set, the robot loses power
// (DriveState::powered = false) and the steering actuator stops its wheels.
// Each instance writes only its own robot's drive, so chunks run in parallel.
#include <algorithm>
#include <cmath>

#include "core/device.h"
#include "core/simulation.h"
#include "sensors/battery/battery.h"

namespace colony {
namespace {

// marXbot defaults (seed 000, 2.2.1: 38 Wh, up to 7 h moving). The split
// between idle and motion is our choice: 2.4 W for the electronics (the
// scanner alone draws 2 W) and 10 J per metre of travel, so driving at top
// speed (0.3 m/s) draws 2.4 + 3 = 5.4 W and empties the battery in 7.04 h;
// standing still it lasts 15.8 h.
constexpr double kCapacity = 38.0 * 3600.0;  // J
constexpr double kIdlePower = 2.4;           // W
constexpr double kMotionEnergy = 10.0;       // J/m

struct BatteryInstance : Battery, InstanceBase {
  using Interface = Battery;
  double charge = 0;  // J, the true state
  void Set(double level, double capacity, bool empty) {
    level_ = level;
    capacity_ = capacity;
    empty_ = empty;
  }
};

class BatterySystem : public SensorSystem {
 public:
  void Configure(const ConfigNode& node) override {
    capacity_ = node.GetDouble("capacity", kCapacity, Range::Positive());
    initial_level_ = node.GetDouble("initial_level", 1.0, Range::Between(0, 1));
    idle_power_ = node.GetDouble("idle_power", kIdlePower, Range::NonNegative());
    motion_energy_ = node.GetDouble("motion_energy", kMotionEnergy, Range::NonNegative());
    stop_when_empty_ = node.GetBool("stop_when_empty", true);
    noise_ = NoiseModel::Read(node);
  }

  Sensor* Attach(EntityHandle robot, const RandomStream& rng) override {
    BatteryInstance& b = instances_.Add(robot, rng);
    b.charge = initial_level_ * capacity_;
    b.Set(initial_level_, capacity_, b.charge <= 0);
    // Empty from the start: no power from the first tick.
    DriveState* drive = sim().space().drive(robot.index);
    if (b.empty() && stop_when_empty_ && drive) drive->powered = false;
    return &b;
  }
  void Detach(Sensor* s) override { instances_.Remove(static_cast<Battery*>(s)); }
  size_t size() const override { return instances_.size(); }

  void Update(size_t begin, size_t end) override {
    Space& space = sim().space();
    const double idle = idle_power_ * sim().dt();
    for (size_t k = begin; k < end; ++k) {
      BatteryInstance& b = instances_[k];
      if (!b.alive) continue;
      DriveState* drive = space.drive(b.robot.index);
      double used = idle;
      if (drive)
        used += motion_energy_ * 0.5 *
                (std::abs(drive->travelled_left) + std::abs(drive->travelled_right));
      b.charge = std::max(0.0, b.charge - used);
      const bool empty = b.charge <= 0;
      if (empty && stop_when_empty_ && drive) drive->powered = false;
      double level = b.charge / capacity_;
      if (noise_.enabled()) level = std::clamp(noise_.Apply(level, b.rng), 0.0, 1.0);
      b.Set(level, capacity_, empty);
    }
  }

  void Hash(StateHasher& h) const override {
    for (size_t k = 0; k < instances_.size(); ++k) {
      const BatteryInstance& b = instances_[k];
      if (!b.alive) continue;
      h.AddDouble(b.charge);
      h.AddDouble(b.level());
    }
  }

 private:
  double capacity_ = kCapacity, initial_level_ = 1, idle_power_ = kIdlePower,
         motion_energy_ = kMotionEnergy;
  bool stop_when_empty_ = true;
  NoiseModel noise_;
  InstanceStore<BatteryInstance> instances_;
};

std::vector<AttributeDoc> BatteryAttributes() {
  std::vector<AttributeDoc> a = {
      {"capacity", "a number > 0 (J)", "136800 (38 Wh)", "energy of a full battery"},
      {"initial_level", "a number in [0, 1]", "1",
       "charge at the start, as a fraction of capacity"},
      {"idle_power", "a number >= 0 (W)", "2.4", "drain while the robot exists, moving or not"},
      {"motion_energy", "a number >= 0 (J/m)", "10",
       "extra drain per metre travelled (mean of the two wheels' travel)"},
      {"stop_when_empty", "true, false", "true",
       "an empty battery cuts the robot's power: its wheels stop"},
  };
  for (auto& n : NoiseModel::Attributes(/*with_drop=*/false)) a.push_back(n);
  return a;
}

COLONY_REGISTER_SENSOR(
    BatterySystem, "battery", "default",
    "battery level in [0, 1], falling with time (idle_power) and with wheel travel "
    "(motion_energy); an empty battery stops the robot",
    DeviceInterface{
        "sensors/battery/battery.h",
        "colony::Battery",
        {"level(): charge left, 0 (empty) .. 1 (full), noise included",
         "remaining_energy(): level() x capacity() (J)", "capacity(): energy of a full battery (J)",
         "empty(): the true charge is 0 (the wheels stop)"}},
    BatteryAttributes());

}  // namespace
}  // namespace colony
