// The eye-bot: figures from ../shared/ROBOTS.md and seed 003 (5.3); where the
// sources give none, our choices (entities/eyebot/README.md). Its components
// (core/component.h): the quadrotor's propulsion, the ceiling attachment,
// and the pan-tilt unit carrying the camera and the laser pointer.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "core/math.h"
#include "core/state_hash.h"

namespace colony {

class Space;

namespace eyebot {

// Body: a short cylinder the size of the protective ring around the rotors,
// its origin at the bottom of the landing feet (our choices: the sources
// give no size).
inline constexpr double kRadius = 0.25;  // m, the protective ring
inline constexpr double kHeight = 0.30;  // m, from the feet to the attachment plate on top
inline constexpr double kMass = 1.0;     // kg (our choice: the sources give only the thrust)
// Seed 003, 5.3.1: 4 rotors of up to 350 g of thrust each, 1.4 kg in all.
inline constexpr int kRotorCount = 4;
inline constexpr double kRotorThrust = 0.350 * 9.81;  // (standard gravity)              // N each
inline constexpr double kMaxThrust = kRotorCount * kRotorThrust;  // N: 13.73
// Flight envelope (our choices): fastest horizontal and vertical speed,
// largest acceleration the flight computer commands, fastest turn.
inline constexpr double kMaxSpeed = 2.0;          // m/s, horizontal
inline constexpr double kMaxVerticalSpeed = 1.0;  // m/s
inline constexpr double kMaxAcceleration = 3.0;   // m/s^2 (also bounded by the thrust)
inline constexpr double kMaxYawRate = M_PI / 2;   // rad/s
// Rotor hubs on the diagonals, half-way out to the ring (for drawing).
inline constexpr double kRotorArm = 0.15;     // m from the axis
inline constexpr double kRotorRadius = 0.10;  // m, a propeller disc
inline constexpr double kRotorZ = 0.20;       // m above the feet
// Devices.
inline constexpr int kProximityCount = 12;  // infrared distance sensors on the ring (our choice)
inline constexpr double kProximityElevation = 0.20;
inline constexpr double kProximityRange = 0.30;
inline constexpr int kScannerSensorCount = 4;  // the distance scanner (as the marXbot's)
inline constexpr double kScannerRadius = 0.05;
inline constexpr double kScannerElevation = 0.25;
// The RGB signalling LED, under the body on its axis (seed 003, 5.3.2).
inline constexpr double kLedElevation = 0.09;  // m: a collar under the body, above the head
// Pan-tilt unit under the body (seed 003, 5.3.2: 360 degrees of pan, tilt
// 90 degrees from vertical to horizontal); the camera and the laser look
// along the unit's axis from its centre.
inline constexpr double kPanTiltElevation = 0.06;  // m above the feet (centre of the head)
inline constexpr double kPanSpeed = M_PI;          // rad/s (our choice)
inline constexpr double kTiltSpeed = M_PI / 2;     // rad/s (our choice)
inline constexpr double kLaserRange = 10.0;        // m: a 5 mW red laser's spot stays visible
// How close under a ceiling the attachment plate must be to hold (m).
inline constexpr double kAttachDistance = 0.01;

}  // namespace eyebot

// The quadrotor's propulsion (component "quadrotor"): written by the
// eyebot_propulsion actuator, flown by the physics model (pointmass3d,
// dynamics3d), which writes back the thrust it used.
struct QuadrotorState {
  static constexpr const char* kComponentName = "quadrotor";
  enum class Mode : uint8_t {
    kOff,       // rotors stopped
    kPosition,  // fly to target_position and turn to target_yaw, then hold
    kSpeed,     // fly at target_velocity (world frame) and turn at target_yaw_rate
  };
  // Commands.
  Mode mode = Mode::kOff;
  Vec3 target_position = Vec3::Zero();  // m, world frame
  double target_yaw = 0;                // rad
  Vec3 target_velocity = Vec3::Zero();  // m/s, world frame
  double target_yaw_rate = 0;           // rad/s
  // Limits (entity).
  double max_thrust = eyebot::kMaxThrust;  // N, all rotors together
  double max_speed = eyebot::kMaxSpeed;
  double max_vertical_speed = eyebot::kMaxVerticalSpeed;
  double max_acceleration = eyebot::kMaxAcceleration;
  double max_yaw_rate = eyebot::kMaxYawRate;
  // State (model): the thrust the rotors gave last tick (N; 0 when off or
  // attached to the ceiling).
  double thrust = 0;
  void Hash(StateHasher& h) const {
    const double v[2] = {thrust, static_cast<double>(mode)};
    h.Add(v, sizeof v);
  }
};

// The ceiling attachment mechanism (component "ceiling_attachment"): the
// eyebot_ceiling actuator asks to attach or to let go; the model attaches
// when the top of the body touches a ceiling (within eyebot::kAttachDistance)
// and then holds the robot still with its rotors off.
struct CeilingAttachmentState {
  static constexpr const char* kComponentName = "ceiling_attachment";
  bool attach = false;    // command: hold on when touching a ceiling
  bool attached = false;  // state (model)
  void Hash(StateHasher& h) const { h.AddU64(attached ? 1 : 0); }
};

// The pan-tilt unit (component "pan_tilt") with its camera and red laser
// pointer: written by the eyebot_pan_tilt and eyebot_laser actuators (which
// also turn the unit toward its targets at its speeds; it is not simulated by
// the engines), read by the pan-tilt camera, the LED medium (the laser's
// spot) and renderers.
struct PanTiltState {
  static constexpr const char* kComponentName = "pan_tilt";
  // Pan: about the robot's vertical axis, counter-clockwise from its front
  // (rad, (-pi, pi]). Tilt: from straight down (0) to horizontal (pi/2).
  double pan = 0, tilt = 0;
  double target_pan = 0, target_tilt = 0;
  double pan_speed = eyebot::kPanSpeed, tilt_speed = eyebot::kTiltSpeed;  // rad/s
  Vec3 mount = Vec3(0, 0, eyebot::kPanTiltElevation);  // centre of the head, robot frame
  bool laser_on = false;
  double laser_range = eyebot::kLaserRange;  // m
  void Hash(StateHasher& h) const {
    const double v[3] = {pan, tilt, laser_on ? 1.0 : 0.0};
    h.Add(v, sizeof v);
  }
};

// The pan-tilt head's frame in the world, for a robot at `body`: origin at
// the head's centre, x along the camera's and the laser's axis, y to the
// camera's left, z its up.
inline Pose PanTiltFrame(const Pose& body, const PanTiltState& pt) {
  Pose frame;
  frame.position = body.position + body.orientation * pt.mount;
  frame.orientation = body.orientation * Quat(Eigen::AngleAxisd(pt.pan, Vec3::UnitZ())) *
                      Quat(Eigen::AngleAxisd(M_PI / 2 - pt.tilt, Vec3::UnitY()));
  frame.orientation.normalize();
  return frame;
}

// The anchor the eye-bot's physics models give (core/engine.h,
// PhysicsModel::Anchor): "pan_tilt", the head's frame (PanTiltFrame).
bool PanTiltAnchor(const Space& space, uint32_t slot, std::string_view name, Pose& pose);

// Where the laser of entity `slot` (which has a PanTiltState) first hits the
// floor or a solid entity, within its range; none when it is off or hits
// nothing. `entity` is the slot hit, or kFloor.
struct LaserSpot {
  static constexpr uint32_t kFloor = 0xFFFFFFFFu;
  Vec3 point = Vec3::Zero();
  uint32_t entity = kFloor;
  double distance = 0;  // m from the head
};
std::optional<LaserSpot> CastLaser(const Space& space, uint32_t slot);

// For the physics models, when the run starts: a warning if eye-bot `slot`
// was declared attached="true" but its top is not at a ceiling (it then
// flies, and holds once it touches one).
void WarnIfHeldAwayFromCeiling(const Space& space, uint32_t slot);

}  // namespace colony
