// The marXbot (foot-bot): figures from ../shared/ROBOTS.md.
#pragma once

#include <cmath>

namespace colony::marxbot {

inline constexpr double kBodyRadius = 0.085;            // m
inline constexpr double kBodyHeight = 0.147;            // m, base without the manipulator
inline constexpr double kWheelBase = 0.14;              // m, between the treels
inline constexpr double kWheelRadius = 0.029;           // m
inline constexpr double kMaxSpeed = 0.30;               // m/s
inline constexpr double kMass = 1.8;                    // kg (for dynamics engines)
inline constexpr double kHeightWithManipulator = 0.29;  // m (seed 004, 3.3)
inline constexpr double kManipulatorMass = 0.4;         // kg (no figure in the sources; our choice)
// The construction manipulator's head: a box in front of the body, turning
// about its own vertical axis, whose outer face (+x at rotation 0) is the
// magnet and whose opposite face carries the 6 IR sensors. Its mass is part
// of kManipulatorMass (the rest, the piston and motors, rides in the body).
inline constexpr double kHeadDepth = 0.03;   // m, along the head's x axis
inline constexpr double kHeadWidth = 0.05;   // m
inline constexpr double kHeadHeight = 0.03;  // m, also the magnet face's height
inline constexpr double kHeadMass = 0.15;    // kg
// The head's vertical pivot (rotation axis, through the head's centre): just
// in front of the body, on the robot's x axis (m from the robot's axis).
inline constexpr double kHeadPivotX = kBodyRadius + 0.5 * kHeadDepth;
// Tilt: the head pitches about its own horizontal axis across it (its y
// axis, through its centre); positive tilt turns the magnet face down and
// the IR face up. +pi/2: the magnet looks straight down (it lies on a
// pocket's top with the head at its lowest); -pi/2: the IR face lies flat,
// looking down. No figures in the sources: range and speed are choices.
inline constexpr double kMinTilt = -M_PI / 2, kMaxTilt = M_PI / 2;  // rad
inline constexpr double kTiltSpeed = 1.0;                           // rad/s
// What the magnet holds when fully engaged, besides cubes (dynamics3d): a
// pocket whose top is within kMagnetReach of the magnet face's centre, the
// face looking down (within kMagnetMaxSlant of straight down) and its centre
// over the pocket near its ferromagnetic strip: within kMagnetStripReach of
// the pocket's long axis (the strip runs along it; 3 cm of the pocket's 3.5
// cm half-width, so that a robot whose body touches a pocket across its path
// holds it: its face's centre is then 2 to 3 cm off the axis) and within its
// length.
inline constexpr double kMagnetReach = 0.01;         // m
inline constexpr double kMagnetMaxSlant = M_PI / 6;  // rad
inline constexpr double kMagnetStripReach = 0.03;    // m

inline constexpr int kProximityCount = 24;  // 15 degrees apart
inline constexpr double kProximityElevation =
    0.055;  // m above the floor ("about 6 cm": below a 6 cm cube's top)
inline constexpr double kProximityRange = 0.10;  // m from the body's surface
inline constexpr int kGroundCount = 8;           // 45 degrees apart, under the base
inline constexpr double kGroundRadius = 0.065;   // m from the axis
// Light sensors: a ring like the proximity ring (the layout ARGoS gives the foot-bot).
inline constexpr int kLightCount = 24;           // 15 degrees apart from 7.5 degrees
inline constexpr double kLightElevation = 0.06;  // m above the floor
// Rotating distance scanner (seed 000, 2.2.3): 4 Sharp sensors on a rotor of
// 130 mm diameter, looking out through its rim, scan plane 9 cm above the floor.
inline constexpr int kScannerSensorCount = 4;        // short, long, short, long, 90 degrees apart
inline constexpr double kScannerRadius = 0.065;      // m from the axis to the sensors' faces
inline constexpr double kScannerElevation = 0.09;    // m above the floor
inline constexpr double kScannerRange = 1.5;         // m, the long-range sensors' reach
inline constexpr int kRingLedCount = 12;             // RGB LEDs on the docking ring
inline constexpr int kLedCount = kRingLedCount + 1;  // plus the beacon (last)
inline constexpr double kLedRingRadius = 0.075;      // m
inline constexpr double kLedRingElevation = 0.13;    // m

}  // namespace colony::marxbot
