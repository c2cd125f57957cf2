// Shared bookkeeping of the two descents on the attractor points (trajectory_optimizer.cpp,
// trajectory_bfgs.cpp): the per-iteration history and report, the convergence test and the
// closing status message.
#pragma once

#include <cmath>
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

/// Records the cost `c` of iteration r.iterations and reports it to options.on_iteration.
inline void reportIteration(TrajectoryOptimization& r, const TrajectoryCost& c,
                            const TrajectoryOptimizerOptions& options) {
  recordIteration(r, c);
  if (options.on_iteration) options.on_iteration(r.iterations, c);
}

/// Counts an accepted iteration of cost `c` (the cost before it: `previous`) and reports it;
/// true, with r.status kConverged, when it lowered the cost by less than
/// options.relative_tolerance * |previous|.
inline bool acceptIteration(TrajectoryOptimization& r, const TrajectoryCost& c, double previous,
                            const TrajectoryOptimizerOptions& options) {
  ++r.iterations;
  reportIteration(r, c, options);
  if (previous - c.total < options.relative_tolerance * std::abs(previous)) {
    r.status = TrajectoryStatus::kConverged;
    return true;
  }
  return false;
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
