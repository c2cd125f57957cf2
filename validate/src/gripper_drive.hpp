#pragma once
/// @file gripper_drive.hpp
/// Private to the validate stage: the drive of a gripper whose one actuated joint is revolute
/// (a Robotiq 2F-85's linkage), as a force-limited drive like the parallel jaws'
/// (docs/VALIDATION.md, "Grippers driven by a revolute joint").

#include "taskmap/meshes/hand_model.hpp"

namespace taskmap::detail {

/// A revolute gripper's position actuator.
struct GripperDrive {
  /// m / rad: sum over the fingers of the closing speed of the finger's tip per radian of the
  /// joint, at the middle of its range.
  double lever = 0.0;
  double torque = 0.0;  ///< N m: jaw force x lever, the actuator's force limit
  double kp = 0.0;      ///< N m / rad: the jaws' gain kp_prismatic x sum of squared tip speeds
};

/// The drive when `hand` has exactly one actuated joint, revolute, and at least two fingers;
/// otherwise a drive of lever 0 (not a revolute gripper). A finger's tip is the origin of its
/// deepest link; its closing speed is the component of the tip's velocity (central difference)
/// toward the tips' centroid. jaw_force in N per finger, kp_prismatic in N / m.
GripperDrive revoluteGripperDrive(const HandModel& hand, double jaw_force, double kp_prismatic);

}  // namespace taskmap::detail
