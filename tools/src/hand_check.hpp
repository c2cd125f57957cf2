#pragma once
/// @file hand_check.hpp
/// What `taskmap hand-info` derives from a hand model: the fully closed configuration, points
/// of every collision shape in the palm frame, and warnings about set-ups that cannot grasp.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "taskmap/meshes/hand_model.hpp"

namespace taskmap::cli {

/// Joint values (jointNames() order) with every closing joint at its closed limit and the
/// other joints at their preshape value.
Eigen::VectorXd closedConfiguration(const HandModel& hand);

/// Points on the boundary of a collision shape in its own frame (box corners, 26 points of a
/// sphere, two rings of a cylinder, hull vertices), metres.
std::vector<Eigen::Vector3d> shapePoints(const CollisionShape& shape);

/// Farthest point of `link`'s shapes along the approach axis at joint values q, metres in the
/// palm frame (-infinity for a link without geometry).
double frontOf(const HandModel& hand, const Eigen::VectorXd& q, int link);

/// Warnings: no finger link reaches in front of the palm (approach coordinate > 0) anywhere on
/// the closing motion from the preshape to the closed configuration; palm-rigid geometry more
/// than 1 cm in front of the palm frame (the palm cannot touch what it grasps).
std::vector<std::string> handWarnings(const HandModel& hand);

}  // namespace taskmap::cli
