// Simulated eye-bot propulsion actuator: writes the command into the
// robot's QuadrotorState, which its physics model flies (pointmass3d,
// dynamics3d: entities/eyebot/flight.h). What a command leaves to "where
// the robot is" (a relative target, the heading or position to hold after a
// mode change) is taken from the robot's pose when the command is first
// applied. Speeds and turn rates beyond the robot's limits are written at
// the limit, with a warning once per robot and kind; a command with a value
// that is not finite is not written (the previous one stays), with a
// warning once per robot.
#include <algorithm>
#include <cmath>
#include <string>

#include "actuators/eyebot_propulsion/eyebot_propulsion.h"
#include "core/device.h"
#include "core/log.h"
#include "core/simulation.h"
#include "core/text.h"
#include "entities/eyebot/eyebot.h"

namespace colony {
namespace {

struct PropulsionInstance : EyebotPropulsionActuator, InstanceBase {
  using Interface = EyebotPropulsionActuator;
  void SetLimits(const QuadrotorState& q) {
    max_speed_ = q.max_speed;
    max_vertical_speed_ = q.max_vertical_speed;
    max_yaw_rate_ = q.max_yaw_rate;
    max_thrust_ = q.max_thrust;
  }
  // Fills in, from the robot's pose, what position mode takes from where
  // the robot is.
  void Resolve(const Pose& pose) {
    const double yaw = YawOf(pose.orientation);
    if (pending_yaw_) target_yaw_ = yaw;
    if (pending_ == Pending::kHere) {
      target_ = {pose.position.x(), pose.position.y(), pose.position.z()};
    } else if (pending_ == Pending::kRelative) {
      const double c = std::cos(yaw), s = std::sin(yaw);
      const auto& r = relative_;
      target_ = {pose.position.x() + c * r[0] - s * r[1], pose.position.y() + s * r[0] + c * r[1],
                 pose.position.z() + r[2]};
    }
    pending_ = Pending::kNone;
    pending_yaw_ = false;
  }
  bool warned_speed = false, warned_vertical = false, warned_yaw_rate = false,
       warned_not_finite = false;
};

bool Finite(const std::array<double, 3>& v) {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

class EyebotPropulsionSystem : public ActuatorSystem {
 public:
  void Configure(const ConfigNode&) override {}
  std::vector<std::string> NeededComponents() const override {
    return {QuadrotorState::kComponentName};
  }
  Actuator* Attach(EntityHandle robot, const RandomStream& rng) override {
    PropulsionInstance& a = instances_.Add(robot, rng);
    a.SetLimits(*sim().space().Get<QuadrotorState>(robot.index));
    return &a;
  }
  void Detach(Actuator* a) override {
    instances_.Remove(static_cast<EyebotPropulsionActuator*>(a));
  }
  size_t size() const override { return instances_.size(); }

  void Act(size_t begin, size_t end) override {
    Space& space = sim().space();
    for (size_t k = begin; k < end; ++k) {
      PropulsionInstance& a = instances_[k];
      if (!a.alive) continue;
      const uint32_t s = a.robot.index;
      QuadrotorState& q = *space.Get<QuadrotorState>(s);
      switch (a.mode()) {
        case EyebotPropulsionActuator::Mode::kOff:
          q.mode = QuadrotorState::Mode::kOff;
          break;
        case EyebotPropulsionActuator::Mode::kPosition:
          a.Resolve(space.pose(s));
          if (!Finite(a.target_position()) || !std::isfinite(a.target_yaw())) {
            WarnNotFinite(space, a, "target position or yaw");
            break;
          }
          q.mode = QuadrotorState::Mode::kPosition;
          q.target_position =
              Vec3(a.target_position()[0], a.target_position()[1], a.target_position()[2]);
          q.target_yaw = WrapAngle(a.target_yaw());
          break;
        case EyebotPropulsionActuator::Mode::kSpeed:
          if (!Finite(a.velocity()) || !std::isfinite(a.yaw_rate())) {
            WarnNotFinite(space, a, "velocity or yaw rate");
            break;
          }
          q.mode = QuadrotorState::Mode::kSpeed;
          q.target_velocity = WithinLimits(space, a, q);
          q.target_yaw_rate = YawRateWithinLimit(space, a, q);
          break;
      }
    }
  }

 private:
  static void WarnNotFinite(const Space& space, PropulsionInstance& a, const char* what) {
    if (a.warned_not_finite) return;
    a.warned_not_finite = true;
    LogWarning("robot '" + space.id(a.robot.index) + "': eyebot_propulsion " + what +
               " is not a finite number; the command is ignored and the robot keeps its "
               "previous one (said once per robot)");
  }

  // The commanded velocity, its horizontal part at most max_speed and its
  // vertical part at most max_vertical_speed.
  static Vec3 WithinLimits(const Space& space, PropulsionInstance& a, const QuadrotorState& q) {
    Vec3 v(a.velocity()[0], a.velocity()[1], a.velocity()[2]);
    const double horizontal = v.head<2>().norm();
    if (horizontal > q.max_speed) {
      if (!a.warned_speed) {
        a.warned_speed = true;
        LogWarning("robot '" + space.id(a.robot.index) + "': horizontal speed " +
                   FormatNumber(horizontal) + " m/s is beyond its max_speed, " +
                   FormatNumber(q.max_speed) + " m/s; it flies at that (said once per robot)");
      }
      v.head<2>() *= q.max_speed / horizontal;
    }
    if (std::abs(v.z()) > q.max_vertical_speed) {
      if (!a.warned_vertical) {
        a.warned_vertical = true;
        LogWarning("robot '" + space.id(a.robot.index) + "': vertical speed " +
                   FormatNumber(v.z()) + " m/s is beyond its max_vertical_speed, " +
                   FormatNumber(q.max_vertical_speed) +
                   " m/s; it flies at that (said once per robot)");
      }
      v.z() = std::clamp(v.z(), -q.max_vertical_speed, q.max_vertical_speed);
    }
    return v;
  }

  static double YawRateWithinLimit(const Space& space, PropulsionInstance& a,
                                   const QuadrotorState& q) {
    const double rate = a.yaw_rate();
    if (std::abs(rate) <= q.max_yaw_rate) return rate;
    if (!a.warned_yaw_rate) {
      a.warned_yaw_rate = true;
      LogWarning("robot '" + space.id(a.robot.index) + "': yaw rate " + FormatNumber(rate) +
                 " rad/s is beyond its max_yaw_rate, " + FormatNumber(q.max_yaw_rate) + " rad/s (" +
                 FormatNumber(RadToDeg(q.max_yaw_rate)) +
                 " degrees/s); it turns at that (said once per robot)");
    }
    return std::clamp(rate, -q.max_yaw_rate, q.max_yaw_rate);
  }

  InstanceStore<PropulsionInstance> instances_;
};

COLONY_REGISTER_ACTUATOR(
    EyebotPropulsionSystem, "eyebot_propulsion", "default",
    "the eye-bot's rotors through its flight computer: fly to and hold a position and heading, "
    "or fly at a velocity and turn rate (world frame), or stop the rotors",
    DeviceInterface{
        "actuators/eyebot_propulsion/eyebot_propulsion.h",
        "colony::EyebotPropulsionActuator",
        {"SetTargetPosition(x, y, z) (m, world frame), SetTargetYaw(yaw) (rad), "
         "SetRelativePosition(forward, left, up) (m): position control",
         "SetVelocity(vx, vy, vz) (m/s, world frame), SetYawRate(rate) (rad/s): speed control",
         "Off(): rotors off; mode(): kOff, kPosition or kSpeed",
         "max_speed(), max_vertical_speed() (m/s), max_yaw_rate() (rad/s), max_thrust() (N): the "
         "limits"}},
    (std::vector<AttributeDoc>{}));

}  // namespace
}  // namespace colony
