#pragma once
/// @file hand_check.hpp
/// What `taskmap hand-info` derives from a hand model: the fully closed configuration, points
/// of every collision shape in the palm frame, and warnings about set-ups that cannot grasp.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "taskmap/hands/hand_model.hpp"

namespace taskmap {

/// Joint values (jointNames() order) with every closing joint at its closed limit and the
/// other joints at their preshape value.
Eigen::VectorXd closedConfiguration(const HandModel& hand);

/// Points on the boundary of a collision shape in its own frame (box corners, 26 points of a
/// sphere, two rings of a cylinder, hull vertices), metres.
std::vector<Eigen::Vector3d> shapePoints(const CollisionShape& shape);

/// Farthest point of `link`'s shapes along the approach axis at joint values q, metres in the
/// palm frame (-infinity for a link without geometry).
double frontOf(const HandModel& hand, const Eigen::VectorXd& q, int link);

/// Palm-fixed geometry more than this far (metres) in front of the palm frame "protrudes".
constexpr double kPalmFrontTolerance = 0.01;

/// What `hand-info` and `build` say about a hand before any trial.
struct HandReport {
  /// Set-ups that cannot grasp, each true of the hand: no finger reaches past the front of the
  /// palm-fixed geometry anywhere on the closing motion from the preshape to the closed
  /// configuration (the palm, or a link fixed to it such as an inflated self-collision
  /// capsule, touches the object first and the fingers never do); a collision mesh part whose
  /// convex decomposition failed (its hull is used).
  std::vector<std::string> warnings;
  /// Facts worth knowing that do not stop a grasp: palm-fixed geometry more than
  /// kPalmFrontTolerance in front of the palm frame while the fingers reach past it (the hand
  /// touches objects there; map poses are the palm frame's).
  std::vector<std::string> notes;
};

/// Checks a hand (a few forward-kinematics passes: milliseconds).
HandReport checkHand(const HandModel& hand);

}  // namespace taskmap
