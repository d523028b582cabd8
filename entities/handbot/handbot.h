// The hand-bot: figures from ../shared/ROBOTS.md and seeds 000 (2.3) and 003
// (5.2); where the sources give none, our choices (entities/handbot/README.md).
#pragma once

namespace colony::handbot {

// Hull: a cylinder standing on the floor (it cannot drive). The docking ring
// with its 12 RGB LEDs sits at the marXbot's ring height, so a foot-bot's
// gripper reaches it.
inline constexpr double kHullRadius = 0.085;       // m (our choice: the marXbot's)
inline constexpr double kHullHeight = 0.25;        // m (our choice)
inline constexpr double kMass = 2.0;               // kg, whole robot (our choice)
inline constexpr int kRingLedCount = 12;           // ROBOTS.md
inline constexpr double kLedRingRadius = 0.075;    // m
inline constexpr double kLedRingElevation = 0.13;  // m
inline constexpr int kProximityCount = 24;         // the marXbot's ring (count not in the sources)
inline constexpr double kProximityElevation = 0.055;
inline constexpr double kProximityRange = 0.10;
// Rope launcher: a tube on top of the hull. The rope leaves from its top.
inline constexpr double kLauncherRadius = 0.02;  // m (our choice)
inline constexpr double kLauncherHeight = 0.08;  // m (our choice)
inline constexpr double kHeight = kHullHeight + kLauncherHeight;
inline constexpr double kRopeMaxLength = 2.7;      // m (seed 000: the magnet reaches 270 cm)
inline constexpr double kRopeMaxClimbSpeed = 0.1;  // m/s (our choice)
inline constexpr double kRopeMotorForce = 50;  // N (our choice: lifts the robot and a 2 kg load)
// N/m (our choice: a 2 mm nylon cord 2 m long; a 2 kg robot stretches it 4 mm)
inline constexpr double kRopeStiffness = 5000;

// Head: a box in front of the hull turning both arms about the robot's
// forward (x) axis. Each arm is a bar hinged on the head's front face,
// folded along the head (pointing sideways) at extension 0 and straight
// ahead at pi/2; a gripper at its end points along it, turns about it and
// closes its claws on what is in front of its tip (our layout, after seed
// 000 figure 2.9).
inline constexpr double kHeadDepth = 0.04, kHeadWidth = 0.12, kHeadHeight = 0.08;  // m (choice)
inline constexpr double kHeadX = kHullRadius + 0.5 * kHeadDepth;  // m, its centre ahead of the axis
inline constexpr double kHeadZ = 0.18;                            // m, above the base (choice)
inline constexpr double kShoulderY = 0.06;  // m, each arm's hinge from the head's middle
inline constexpr double kArmLength = 0.15, kArmThickness = 0.03;      // m (choice)
inline constexpr double kGripperLength = 0.06, kGripperWidth = 0.04;  // m (choice)
inline constexpr double kHeadMass = 0.2, kArmMass = 0.15,
                        kGripperMass = 0.15;  // kg (choice; the hull has the rest)
inline constexpr double kPartsMass = kHeadMass + 2 * (kArmMass + kGripperMass);
// Motors (seed 003): table 5.2 (head), 5.1 (arms), 5.4 (gripper rotation);
// the claws close at 0.03 m/s at their 3 cm tips (table 5.3): 1 rad/s.
inline constexpr double kHeadStallTorque = 1.44, kHeadNoLoadSpeed = 2.85, kHeadNominalSpeed = 1.54;
inline constexpr double kArmStallTorque = 2.27, kArmNoLoadSpeed = 2.61, kArmNominalSpeed = 2.29;
inline constexpr double kWristStallTorque = 0.265, kWristNoLoadSpeed = 0.604,
                        kWristNominalSpeed = 0.491;
inline constexpr double kClawSpeed = 1.0;  // rad/s
inline constexpr double kGraspForce = 25;  // N (table 5.3)
inline constexpr double kHoldingLimit =
    4 * 9.81;  // N: "the claws can apply a force up to 4 kg" (seed 000)
// N/m and N m/rad: how stiffly a grasp holds (our choice: rubber pads; a 2 kg
// robot hanging from one gripper sags 4 mm).
inline constexpr double kGraspStiffness = 5000;
inline constexpr double kClawReach = 0.03;  // m beyond the gripper's tip the claws close on

// Fans: the most yaw torque the two together give (our choice: turns the
// hanging robot, whose inertia about its axis is about 0.04 kg m^2 with the
// arms folded sideways, by a quarter turn in about 2 s).
inline constexpr double kFanTorque = 0.05;  // N m
// The fans' heading hold: a PD controller on the IMU's yaw and yaw rate.
inline constexpr double kFanHoldGain = 0.5, kFanHoldDamping = 0.2;  // N m per rad, N m per rad/s

}  // namespace colony::handbot
