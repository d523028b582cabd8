// Simulated eye-bot pan-tilt actuator: writes the targets into the robot's
// PanTiltState and turns the head toward them for one tick, at the unit's
// speeds (the engines do not simulate the head: it is light, and its motors
// hold it wherever the body is). A tilt outside [0, pi/2] goes to the
// nearest limit, with a warning once per robot.
#include <algorithm>
#include <cmath>
#include <string>

#include "actuators/eyebot_pan_tilt/eyebot_pan_tilt.h"
#include "core/device.h"
#include "core/log.h"
#include "core/simulation.h"
#include "core/text.h"
#include "entities/eyebot/eyebot.h"

namespace colony {
namespace {

struct PanTiltInstance : EyebotPanTiltActuator, InstanceBase {
  using Interface = EyebotPanTiltActuator;
  void Start(const PanTiltState& unit) {
    target_pan_ = unit.target_pan;
    target_tilt_ = unit.target_tilt;
    pan_ = unit.pan;
    tilt_ = unit.tilt;
  }
  void SetTargetTilt(double tilt) { target_tilt_ = tilt; }
  void SetHead(double pan, double tilt) {
    pan_ = pan;
    tilt_ = tilt;
  }
  bool warned_tilt = false, warned_pan = false;
};

// `from` moved toward `to` by at most `step`.
double Toward(double from, double to, double step) {
  return std::abs(to - from) <= step ? to : from + std::copysign(step, to - from);
}

class PanTiltSystem : public ActuatorSystem {
 public:
  void Configure(const ConfigNode&) override {}
  std::vector<std::string> NeededComponents() const override {
    return {PanTiltState::kComponentName};
  }
  Actuator* Attach(EntityHandle robot, const RandomStream& rng) override {
    PanTiltInstance& a = instances_.Add(robot, rng);
    a.Start(*sim().space().Get<PanTiltState>(robot.index));
    return &a;
  }
  void Detach(Actuator* a) override { instances_.Remove(static_cast<EyebotPanTiltActuator*>(a)); }
  size_t size() const override { return instances_.size(); }

  void Act(size_t begin, size_t end) override {
    Space& space = sim().space();
    const double dt = sim().dt();
    for (size_t k = begin; k < end; ++k) {
      PanTiltInstance& a = instances_[k];
      if (!a.alive) continue;
      PanTiltState& unit = *space.Get<PanTiltState>(a.robot.index);
      const std::string& id = space.id(a.robot.index);
      if (std::isfinite(a.target_pan())) {
        unit.target_pan = a.target_pan();
      } else if (!a.warned_pan) {
        a.warned_pan = true;
        LogWarning("robot '" + id + "': pan " + FormatNumber(a.target_pan()) +
                   " is not a number; the head keeps its target, " + FormatNumber(unit.target_pan) +
                   " rad (said once per robot)");
      }
      unit.target_tilt = LimitedTilt(a, id, unit.target_tilt);
      a.SetTargetTilt(unit.target_tilt);
      // One tick of motion at the unit's speeds; pan the shorter way round.
      const double pan_step = unit.pan_speed * dt;
      const double to_go = WrapAngle(unit.target_pan - unit.pan);
      unit.pan = std::abs(to_go) <= pan_step ? unit.target_pan
                                             : WrapAngle(unit.pan + std::copysign(pan_step, to_go));
      unit.tilt = Toward(unit.tilt, unit.target_tilt, unit.tilt_speed * dt);
      a.SetHead(unit.pan, unit.tilt);
    }
  }

 private:
  // The tilt the controller asked for, within [0, pi/2] (a warning, once per
  // robot, when it is not); `previous` when it is not a number.
  static double LimitedTilt(PanTiltInstance& a, const std::string& id, double previous) {
    const double asked = a.target_tilt();
    if (asked >= 0 && asked <= M_PI / 2) return asked;
    const double used = std::isnan(asked) ? previous : std::clamp(asked, 0.0, M_PI / 2);
    if (!a.warned_tilt) {
      a.warned_tilt = true;
      LogWarning("robot '" + id + "': tilt " + FormatNumber(asked) + " rad (" +
                 FormatNumber(RadToDeg(asked)) +
                 " degrees) is outside the pan-tilt unit's range, [0, 1.5708] rad (0 straight "
                 "down to 90 degrees, horizontal); it goes to " +
                 FormatNumber(used) + " rad (" + FormatNumber(RadToDeg(used)) +
                 " degrees) instead (said once per robot)");
    }
    return used;
  }

  InstanceStore<PanTiltInstance> instances_;
};

COLONY_REGISTER_ACTUATOR(
    PanTiltSystem, "eyebot_pan_tilt", "default",
    "the eye-bot's pan-tilt head (camera and laser): pan (rad, any value, "
    "wrapped) and tilt (rad, 0 straight down to pi/2 horizontal), reached at "
    "the unit's speeds",
    DeviceInterface{
        "actuators/eyebot_pan_tilt/eyebot_pan_tilt.h",
        "colony::EyebotPanTiltActuator",
        {"SetPan(angle): any angle, wrapped, reached the shorter way round (rad)",
         "SetTilt(angle): 0 straight down .. pi/2 horizontal (rad)",
         "target_pan(), target_tilt(), pan(), tilt(): the targets and where the head is (rad)"}},
    (std::vector<AttributeDoc>{}));

}  // namespace
}  // namespace colony
