// The marXbot (foot-bot): figures from ../shared/ROBOTS.md.
#pragma once

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
