// BFGS on the attractor points (docs/REACHING.md T5): direction -H g, Armijo backtracking from
// the full step, inverse-Hessian update from the accepted step and the gradient change.
#include "taskmap/reaching/trajectory_bfgs.hpp"

#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "descent_record.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

Eigen::VectorXd stack(const std::vector<Eigen::VectorXd>& points) {
  Eigen::VectorXd v(6 * static_cast<Eigen::Index>(points.size()));
  for (std::size_t j = 0; j < points.size(); ++j)
    v.segment<6>(6 * static_cast<Eigen::Index>(j)) = points[j];
  return v;
}

std::vector<Eigen::VectorXd> unstack(const Eigen::VectorXd& v) {
  std::vector<Eigen::VectorXd> points(static_cast<std::size_t>(v.size() / 6));
  for (std::size_t j = 0; j < points.size(); ++j)
    points[j] = v.segment<6>(6 * static_cast<Eigen::Index>(j));
  return points;
}

/// BFGS update of the inverse Hessian with step s and gradient change y (s^T y > 0).
void updateInverseHessian(Eigen::MatrixXd& h, const Eigen::VectorXd& s, const Eigen::VectorXd& y) {
  const double rho = 1.0 / s.dot(y);
  const Eigen::MatrixXd i = Eigen::MatrixXd::Identity(s.size(), s.size());
  h = (i - rho * s * y.transpose()) * h * (i - rho * y * s.transpose()) + rho * s * s.transpose();
}

struct LineSearch {
  bool accepted = false;
  int halvings = 0;
  Eigen::VectorXd x;
  TrajectoryCost cost;
};

/// Backtracking from x + d: halve until C drops by 1e-4 alpha |g^T d| (Armijo), at most 30 times.
LineSearch search(const TrajectoryProblem& problem, const Eigen::VectorXd& x,
                  const Eigen::VectorXd& d, const TrajectoryCost& current) {
  LineSearch r;
  const double slope = current.gradient.dot(d);
  double alpha = 1.0;
  for (; r.halvings < 30; ++r.halvings, alpha *= 0.5) {
    r.x = x + alpha * d;
    r.cost = evaluateTrajectory(problem, unstack(r.x), false);
    if (r.cost.total < current.total + 1e-4 * alpha * slope) {
      r.accepted = true;
      return r;
    }
  }
  return r;
}

}  // namespace

TrajectoryOptimization optimizeTrajectoryBfgs(const TrajectoryProblem& problem,
                                              std::vector<Eigen::VectorXd> points,
                                              const TrajectoryOptimizerOptions& options) {
  options.validate();
  TrajectoryOptimization r;
  TrajectoryCost current = evaluateTrajectory(problem, points, true);
  detail::reportIteration(r, current, options);  // iteration 0: the start
  Eigen::VectorXd x = stack(points);
  const Eigen::Index n = x.size();
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(n, n);  // zero: steepest descent of initial_step
  r.status = TrajectoryStatus::kIterationLimit;
  for (r.iterations = 0; r.iterations < options.max_iterations;) {
    const Eigen::VectorXd& g = current.gradient;
    const double gnorm = g.norm();
    if (!(gnorm > 0.0)) {
      r.status = TrajectoryStatus::kConverged;
      break;
    }
    Eigen::VectorXd d = -h * g;
    if (!(d.dot(g) < 0.0)) d = -options.initial_step * g / gnorm;  // first step or lost descent
    LineSearch ls = search(problem, x, d, current);
    if (!ls.accepted) {
      r.status = TrajectoryStatus::kConverged;
      break;
    }
    const double previous = current.total;
    TrajectoryCost next = evaluateTrajectory(problem, unstack(ls.x), true);
    const Eigen::VectorXd s = ls.x - x, y = next.gradient - g;
    const double sy = s.dot(y);
    if (sy > 1e-12 * s.norm() * y.norm() && ls.halvings <= 10) {
      if (h.isZero(0.0))
        h = (sy / y.squaredNorm()) * Eigen::MatrixXd::Identity(n, n);  // Shanno-Phua
      updateInverseHessian(h, s, y);
    } else {
      h.setZero();  // restart from a steepest-descent step
    }
    x = ls.x;
    current = std::move(next);
    if (detail::acceptIteration(r, current, previous, options)) break;
  }
  detail::finishDescent(r, unstack(x), std::move(current));
  return r;
}

}  // namespace taskmap
