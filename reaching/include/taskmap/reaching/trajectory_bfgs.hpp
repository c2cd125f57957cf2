#pragma once
/// @file trajectory_bfgs.hpp
/// Quasi-Newton (BFGS) descent on the attractor points (docs/REACHING.md "Descent", T5): the same
/// cost and gradient as optimizeTrajectory (evaluateTrajectory), the direction -H g with H the
/// BFGS inverse-Hessian estimate, a backtracking Armijo line search from the full step. On the
/// map-driven reach the plain normalised-gradient descent zig-zags across the narrow valley the
/// proximity term digs along the manifold; BFGS learns that curvature from a few gradients (12
/// variables for two points) at no extra rollout per iteration.

#include <vector>

#include <Eigen/Core>

#include "taskmap/reaching/trajectory_optimizer.hpp"

namespace taskmap {

/// BFGS from `points`, with options' max_iterations, relative_tolerance and on_iteration
/// (same meaning as optimizeTrajectory); the first step is initial_step long along the
/// normalised steepest descent, H then starts from the scaled identity (s^T y / y^T y) I and is
/// reset to it whenever the curvature condition s^T y > 0 fails or a line search needs more than
/// 10 halvings. Units: metres and radians of the task variables. Throws Error on an invalid
/// problem, points or options.
TrajectoryOptimization optimizeTrajectoryBfgs(const TrajectoryProblem& problem,
                                              std::vector<Eigen::VectorXd> points,
                                              const TrajectoryOptimizerOptions& options);

}  // namespace taskmap
