// Shared bookkeeping of the two descents on the attractor points (trajectory_optimizer.cpp,
// trajectory_bfgs.cpp): the per-iteration history and the closing status message.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "taskmap/reaching/trajectory_optimizer.hpp"

namespace taskmap::detail {

/// Appends an iteration's cost to r.history without its gradient and configurations.
inline void recordIteration(TrajectoryOptimization& r, TrajectoryCost c) {
  c.gradient.resize(0);
  c.q.clear();
  r.history.push_back(std::move(c));
}

/// Sets r.message from r.status and r.iterations, stores the final points and cost.
inline void finishDescent(TrajectoryOptimization& r, std::vector<Eigen::VectorXd> points,
                          TrajectoryCost cost) {
  r.message = r.status == TrajectoryStatus::kConverged
                  ? "converged after " + std::to_string(r.iterations) + " iterations"
                  : "stopped at the iteration limit (" + std::to_string(r.iterations) + ")";
  r.points = std::move(points);
  r.cost = std::move(cost);
}

}  // namespace taskmap::detail
