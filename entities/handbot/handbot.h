// The hand-bot: figures from ../shared/ROBOTS.md and seeds 000 (2.3) and 003
// (5.2); where the sources give none, our choices (entities/handbot/README.md).
#pragma once

namespace colony::handbot {

// Hull: a cylinder standing on the floor (it cannot drive). The docking ring
// with its 12 RGB LEDs sits at the marXbot's ring height, so a foot-bot's
// gripper reaches it.
inline constexpr double kHullRadius = 0.085;        // m (our choice: the marXbot's)
inline constexpr double kHullHeight = 0.25;         // m (our choice)
inline constexpr double kMass = 2.0;                // kg, whole robot (our choice)
inline constexpr int kRingLedCount = 12;            // ROBOTS.md
inline constexpr double kLedRingRadius = 0.075;     // m
inline constexpr double kLedRingElevation = 0.13;   // m
inline constexpr int kProximityCount = 24;          // the marXbot's ring (count not in the sources)
inline constexpr double kProximityElevation = 0.055;
inline constexpr double kProximityRange = 0.10;
// Rope launcher: a tube on top of the hull. The rope leaves from its top.
inline constexpr double kLauncherRadius = 0.02;     // m (our choice)
inline constexpr double kLauncherHeight = 0.08;     // m (our choice)
inline constexpr double kHeight = kHullHeight + kLauncherHeight;
inline constexpr double kRopeMaxLength = 2.7;       // m (seed 000: the magnet reaches 270 cm)
inline constexpr double kRopeMaxClimbSpeed = 0.1;   // m/s (our choice)
inline constexpr double kRopeMotorForce = 50;       // N (our choice: lifts the robot and a 2 kg load)

}  // namespace colony::handbot
