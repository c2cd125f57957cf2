#pragma once
/// @file hand_drive.hpp
/// How the physics models drive a hand's joints: the validator's MuJoCo actuators, the closing
/// check's Bullet motors and the hold filter's efforts read this one definition
/// (docs/VALIDATION.md, "Parameters"; docs/history/validation-2026-11.md, "Grippers driven by a
/// revolute joint").

#include <limits>
#include <vector>

#include "taskmap/hands/hand_model.hpp"

namespace taskmap {

/// The drive's numbers (defaults: the hold test's, docs/VALIDATION.md "Parameters").
struct DriveOptions {
  double kp_revolute = 5.0;       ///< N m / rad, position gain of a dexterous hand's joints
  double kp_prismatic = 20000.0;  ///< N / m, position gain of a parallel jaw
  double jaw_force = 70.0;        ///< N, the force each jaw (or gripper finger tip) presses with
  /// A hand whose only actuated joint is revolute, with two or more fingers (a Robotiq 2F-85's
  /// linkage), is driven like parallel jaws: each finger's tip presses with jaw_force. false:
  /// kp_revolute without a force limit, as for dexterous hands (DexGraspBench).
  bool revolute_gripper_force = true;
};

/// A position servo: effort = clamp(kp (target - q), -limit, limit).
struct JointDrive {
  double kp = 0.0;  ///< N m / rad (revolute) or N / m (prismatic)
  double limit = std::numeric_limits<double>::infinity();  ///< N m or N; infinity: none
};

/// The drive of a one-joint revolute gripper's actuator.
struct RevoluteGripper {
  /// m / rad: sum over the fingers of the closing speed of the finger's tip per radian of the
  /// actuated joint, at the middle of its range; 0 when the hand is not a revolute gripper.
  double lever = 0.0;
  double torque = 0.0;  ///< N m: jaw_force x lever, the actuator's force limit
  double kp = 0.0;      ///< N m / rad: kp_prismatic x squares
  /// m^2 / rad^2: the sum of the tips' squared closing speeds per radian, what maps a jaw's
  /// N / m, N s / m and kg to the joint's N m / rad, N m s / rad and kg m^2
  double squares = 0.0;
};

/// The revolute gripper drive of `hand`: lever 0 unless it has exactly one actuated joint,
/// revolute, at least two fingers and a tip that closes (option revolute_gripper_force off:
/// lever 0 too). A finger's tip is the origin of its deepest link; its closing speed is the
/// component of its velocity (central difference in the actuated joint, mimic joints following)
/// toward the tips' centroid.
RevoluteGripper revoluteGripper(const HandModel& hand, const DriveOptions& options);

/// The drive of each actuated joint (HandModel::jointNames() order) in a model that couples
/// mimic joints rigidly to their driver (MuJoCo equalities, the hold filter): prismatic:
/// kp_prismatic, limit jaw_force x (1 + sum of |multiplier| of the prismatic mimic joints it
/// drags along); the revolute gripper's (revoluteGripper); any other revolute: kp_revolute,
/// no limit.
std::vector<JointDrive> actuatorDrives(const HandModel& hand, const DriveOptions& options);

/// The drive of each URDF joint (HandModel::joints() order; fixed joints kp 0) in a model that
/// servos every joint on its own toward its target (the closing check's Bullet motors, mimic
/// joints following their driver's target): prismatic: kp_prismatic, limit jaw_force; a
/// revolute gripper's joint that moves finger tips: kp_prismatic x the sum of the tips' squared
/// closing speeds per radian of this joint, limit jaw_force x the sum of those speeds (each tip
/// presses with jaw_force, as with the actuator of actuatorDrives); its other joints (the
/// linkage's rest, which the real four-bar holds rigid): the actuator's gain and force limit;
/// any other revolute joint: kp_revolute, no limit.
std::vector<JointDrive> jointDrives(const HandModel& hand, const DriveOptions& options);

}  // namespace taskmap
