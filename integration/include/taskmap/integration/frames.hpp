#pragma once
/// @file frames.hpp
/// World-frame helpers and the chain rule to joint space (paper eq. 1.22).
///
/// Perturbation conventions (all 6-vectors are (linear, angular)):
/// - object-frame gradient g: hand pose x in the object frame, p <- p + dp, R <- exp(dw) R;
/// - world-frame hand gradient: p_wh <- p_wh + dp, R_wh <- exp(dw) R_wh, dp and dw in world
///   coordinates, i.e. the twist a geometric Jacobian (linear velocity of the palm origin,
///   angular velocity, both in world coordinates) produces: dx = J dq;
/// - world-frame object gradient: the same perturbation applied to the object's pose, the
///   hand held fixed in the world.

#include <Eigen/Core>

#include "taskmap/core/pose.hpp"

namespace taskmap {

/// Hand pose in the object frame from world-frame hand and object poses: T_wo^-1 T_wh.
Pose handInObject(const Pose& hand_world, const Pose& object_world);

/// Gradient w.r.t. the world-frame hand pose from an object-frame gradient:
/// (R_wo g_lin, R_wo g_ang).
Twist handGradientToWorld(const Twist& gradient_object, const Pose& object_world);

/// Gradient w.r.t. the world-frame object pose (hand fixed in the world) from an object-frame
/// gradient: (-R_wo g_lin, (R_wo g_lin) x (p_wh - p_wo) - R_wo g_ang).
Twist objectGradientToWorld(const Twist& gradient_object, const Pose& hand_world,
                            const Pose& object_world);

/// Joint-space gradient (eq. 1.22): J^T g, with g a world-frame hand gradient and J the 6 x n
/// geometric Jacobian of the palm (rows: linear, angular; world coordinates).
/// Throws Error if J does not have 6 rows.
Eigen::VectorXd chainToJoints(const Twist& gradient_world, const Eigen::MatrixXd& jacobian);

/// Joint-space gradient of a criterion given in the object frame, when both the hand and the
/// object move with the joints (for example an object held by the other arm):
/// J_hand^T g_hand_world + J_object^T g_object_world. Pass an empty J_object (0 columns) for
/// a fixed object. Throws Error on shape mismatches.
Eigen::VectorXd jointGradient(const Twist& gradient_object, const Pose& hand_world,
                              const Pose& object_world, const Eigen::MatrixXd& hand_jacobian,
                              const Eigen::MatrixXd& object_jacobian = Eigen::MatrixXd());

}  // namespace taskmap
