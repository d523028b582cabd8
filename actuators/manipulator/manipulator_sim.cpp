// Simulated manipulator actuator: writes the controller's commands into the
// robot's ManipulatorState (elevation clamped to the limits, rotation wrapped
// to (-pi, pi], tilt limited to its range with a warning once per robot). The
// engine moves the head towards them at the state's speeds, switches the
// magnet over switch_time and holds what the engaged magnet touches; only
// engines that simulate the manipulator accept it (dynamics3d, kinematics2d,
// dynamics2d),
// elsewhere it is a load-time error. XML attributes override the robot's
// limits.
#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>

#include "actuators/manipulator/manipulator.h"
#include "actuators/manipulator/manipulator_state.h"
#include "core/device.h"
#include "core/log.h"
#include "core/simulation.h"

namespace colony {
namespace {

struct ManipulatorInstance : ManipulatorActuator, InstanceBase {
  using Interface = ManipulatorActuator;
  void SetLimits(const ManipulatorState& m) {
    min_elevation_ = m.min_elevation;
    max_elevation_ = m.max_elevation;
    min_tilt_ = m.min_tilt;
    max_tilt_ = m.max_tilt;
  }
  bool warned_tilt = false;
};

class ManipulatorSystem : public ActuatorSystem {
 public:
  void Configure(const ConfigNode& node) override {
    auto read = [&](const char* name, const Range& range) -> std::optional<double> {
      if (!node.Has(name)) return std::nullopt;
      return node.GetDouble(name, 0, range);
    };
    const size_t problems = node.context().diagnostics.size();
    min_elevation_ = read("min_elevation", Range::NonNegative());
    max_elevation_ = read("max_elevation", Range::Positive());
    elevation_speed_ = read("elevation_speed", Range::Positive());
    rotation_speed_ = read("rotation_speed", Range::Positive());
    tilt_speed_ = read("tilt_speed", Range::Positive());
    switch_time_ = read("switch_time", Range::Positive());
    // The range must stay non-empty, also against the default of the bound
    // that is not given (when both values could be read).
    const ManipulatorState defaults;
    const double lo = min_elevation_.value_or(defaults.min_elevation);
    const double hi = max_elevation_.value_or(defaults.max_elevation);
    if (node.context().diagnostics.size() == problems && lo >= hi &&
        (min_elevation_ || max_elevation_)) {
      const char* bad = max_elevation_ ? "max_elevation" : "min_elevation";
      node.Error(bad, node.GetString(bad, ""),
                 "min_elevation (" + FormatNumber(lo) + ") must be below max_elevation (" +
                     FormatNumber(hi) + "); accepted: 0 <= min_elevation < max_elevation (m)");
    }
  }

  std::vector<std::string> NeededComponents() const override {
    return {ManipulatorState::kComponentName};
  }

  Actuator* Attach(EntityHandle robot, const RandomStream& rng) override {
    ManipulatorState* m = sim().space().Get<ManipulatorState>(robot.index);  // checked by the host
    if (min_elevation_) m->min_elevation = *min_elevation_;
    if (max_elevation_) m->max_elevation = *max_elevation_;
    if (elevation_speed_) m->elevation_speed = *elevation_speed_;
    if (rotation_speed_) m->rotation_speed = *rotation_speed_;
    if (tilt_speed_) m->tilt_speed = *tilt_speed_;
    if (switch_time_) m->switch_time = *switch_time_;
    if (m->min_elevation >= m->max_elevation) {
      throw AttachError("its manipulator's elevation range [" + FormatNumber(m->min_elevation) +
                        ", " + FormatNumber(m->max_elevation) + "] is empty");
    }
    ManipulatorInstance& a = instances_.Add(robot, rng);
    a.SetLimits(*m);
    return &a;
  }
  void Detach(Actuator* a) override { instances_.Remove(static_cast<ManipulatorActuator*>(a)); }
  size_t size() const override { return instances_.size(); }

  void Act(size_t begin, size_t end) override {
    Space& space = sim().space();
    for (size_t k = begin; k < end; ++k) {
      ManipulatorInstance& a = instances_[k];
      if (!a.alive) continue;
      ManipulatorState& m = *space.Get<ManipulatorState>(a.robot.index);
      const double elevation =
          std::isfinite(a.elevation_target()) ? a.elevation_target() : m.elevation;
      m.target_elevation = std::clamp(elevation, m.min_elevation, m.max_elevation);
      m.target_rotation =
          WrapAngle(std::isfinite(a.rotation_target()) ? a.rotation_target() : m.rotation);
      m.target_tilt = LimitedTilt(a, space.id(a.robot.index), m);
      m.want_magnet = a.magnet_wanted();
    }
  }

 private:
  // The tilt the controller asked for, within the robot's range (a warning,
  // once per robot, when it is not); where the head is when it is not a
  // finite number.
  static double LimitedTilt(ManipulatorInstance& a, const std::string& id,
                            const ManipulatorState& m) {
    const double asked = a.tilt_target();
    if (!std::isfinite(asked)) return m.tilt;
    if (asked >= m.min_tilt && asked <= m.max_tilt) return asked;
    const double used = std::clamp(asked, m.min_tilt, m.max_tilt);
    if (!a.warned_tilt) {
      a.warned_tilt = true;
      LogWarning("robot '" + id + "': manipulator tilt " + FormatNumber(asked) + " rad (" +
                 FormatNumber(RadToDeg(asked)) + " degrees) is outside its range, [" +
                 FormatNumber(m.min_tilt) + ", " + FormatNumber(m.max_tilt) +
                 "] rad; the head goes to " + FormatNumber(used) +
                 " rad instead (said once per robot)");
    }
    return used;
  }

  // Overrides of the robot's limits; none: keep the robot's.
  std::optional<double> min_elevation_, max_elevation_, elevation_speed_, rotation_speed_,
      tilt_speed_, switch_time_;
  InstanceStore<ManipulatorInstance> instances_;
};

COLONY_REGISTER_ACTUATOR(
    ManipulatorSystem, "manipulator", "default",
    "the marXbot's magnetic construction manipulator: head elevation, head rotation (magnet side / "
    "IR side), head tilt, switchable magnet (needs an engine that simulates it: dynamics3d, "
    "without the tilt, kinematics2d, dynamics2d)",
    DeviceInterface{
        "actuators/manipulator/manipulator.h",
        "colony::ManipulatorActuator",
        {"SetElevation(elevation): the magnet's centre above the floor (m)",
         "SetRotation(angle) (rad), SetMagnetSide(), SetIrSide(): the head's rotation",
         "SetTilt(angle): the head's pitch (rad)", "EngageMagnet(), DisengageMagnet()",
         "min_elevation(), max_elevation() (m), min_tilt(), max_tilt() (rad): the limits"}},
    (std::vector<AttributeDoc>{
        {"min_elevation", "a number >= 0 (m), below max_elevation", "the robot's (marXbot: 0.03)",
         "lowest height of the magnet's centre above the floor"},
        {"max_elevation", "a number > 0 (m), above min_elevation", "the robot's (marXbot: 0.2)",
         "highest height of the magnet's centre above the floor"},
        {"elevation_speed", "a number > 0 (m/s)", "the robot's (marXbot: 0.05)",
         "how fast the head moves up and down"},
        {"rotation_speed", "a number > 0 (rad/s)", "the robot's (marXbot: 1)",
         "how fast the head turns"},
        {"tilt_speed", "a number > 0 (rad/s)", "the robot's (marXbot: 1)",
         "how fast the head tilts"},
        {"switch_time", "a number > 0 (s)", "the robot's (marXbot: 1)",
         "how long the magnet takes to switch over"},
    }));

}  // namespace
}  // namespace colony
