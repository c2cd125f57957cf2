#pragma once
/// @file trajectory_optimizer.hpp
/// Trajectory optimisation over attractor points (paper section 1.5, Table 1.1, docs/REACHING.md
/// "Trajectory optimisation", T1-T4): the reaching rollout (attractor dynamics + resolved-rate IK)
/// is driven by K attractor points; the cost sums joint-space path length, end-effector velocity at
/// the end, collision and joint-limit costs along the trajectory and an optional terminal cost (the
/// task map). The gradient with respect to the attractor points comes from a forward pass and a
/// backward (adjoint) pass through the attractor dynamics and the IK. Units: metres, radians, s.

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "taskmap/reaching/attractor.hpp"

namespace taskmap {

/// Weights of the trajectory cost terms (docs/REACHING.md T1), each >= 0.
struct TrajectoryCostWeights {
  double path_length = 1.0;   ///< w_p on sum |q_{t+1} - q_t|^2 / dt (rad^2/s)
  double end_velocity = 1.0;  ///< w_v on |v_T|^2, v_T = (p_T - p_{T-1}) / dt (m^2/s^2)
  double collision = 1.0;     ///< w_c on dt sum_t H_coll(q_t) (eq. 1.10)
  double joint_limit = 1.0;   ///< w_jl on dt sum_t H_jl(q_t) (eq. 1.8)
  /// Throws Error naming the field when a weight is negative or not finite.
  void validate() const;
};

/// Terminal cost c(q_T) on the final configuration: returns the cost and, when gradient is not
/// null, writes dc/dq_T (dofs() entries). kin holds q_T.
using TerminalCost = std::function<double(const Kinematics& kin, Eigen::VectorXd* gradient)>;

/// Linearisation of the IK step in the backward pass.
enum class StepDerivative {
  kAnalytic,          ///< reverse-mode products through the step (ik_step_derivative.hpp)
  kFiniteDifferences  ///< differences of lambda^T F, 2 (dofs + 12) steps each (the oracle)
};

/// Finite differences of a Jacobian.
enum class FiniteDifferences {
  kCentral,  ///< 2 evaluations per input, error O(eps^2)
  kForward,  ///< 1 evaluation per input, error O(eps)
};

/// One trajectory optimisation problem. The pointers must outlive every call using it.
struct TrajectoryProblem {
  const RobotModel* robot = nullptr;           ///< the robot (required)
  const CollisionModel* collisions = nullptr;  ///< pairs along the trajectory (optional)
  int body = -1;                               ///< controlled body, usually the palm
  int reference = -1;                          ///< reference body of the task, -1 = world
  Eigen::VectorXd q0;                          ///< start configuration, inside the limits
  /// Orientation the rotation-vector task variables are measured from (taskVariables()).
  Eigen::Matrix3d frame = Eigen::Matrix3d::Identity();
  ReachOptions reach;             ///< dynamics, IK gains, steps, move_time (via_points unused)
  TrajectoryCostWeights weights;  ///< cost weights
  TerminalCost terminal;          ///< optional terminal cost (the task map, eq. 1.22)
  /// How the backward pass linearises one IK step (docs/REACHING.md T3).
  StepDerivative step_derivative = StepDerivative::kAnalytic;
  /// Finite differences: step of the differences of lambda^T F (kFiniteDifferences); analytic:
  /// step of the directional central difference of the collision gradient. Radians.
  double step_jacobian_epsilon = 1e-6;
  /// kFiniteDifferences only: which differences.
  FiniteDifferences step_jacobian_differences = FiniteDifferences::kCentral;
  /// Throws Error naming the problem (missing robot, sizes, limits, options).
  void validate() const;
};

/// Cost terms of one rollout and (optionally) the gradient with respect to the points.
struct TrajectoryCost {
  double total = 0.0;         ///< sum of the weighted terms
  double path_length = 0.0;   ///< weighted path-length term
  double end_velocity = 0.0;  ///< weighted end-velocity term
  double collision = 0.0;     ///< weighted collision term
  double joint_limit = 0.0;   ///< weighted joint-limit term
  double terminal = 0.0;      ///< terminal cost (already weighted by its provider)
  /// d total / d points, 6 K entries (point k at rows 6k..6k+5); empty without gradient.
  Eigen::VectorXd gradient;
  std::vector<Eigen::VectorXd> q;  ///< steps + 1 configurations, q0 first
};

/// Task variables (taskVariables(pose, problem.frame)) of the body at q0.
Eigen::Matrix<double, 6, 1> startTaskVariables(const TrajectoryProblem& problem);

/// Rolls the problem out from the attractor points (each 6 task variables relative to
/// problem.frame, K >= 1) and evaluates the cost; with `gradient` also d cost / d points by the
/// backward pass. Throws Error on an invalid problem or points.
TrajectoryCost evaluateTrajectory(const TrajectoryProblem& problem,
                                  const std::vector<Eigen::VectorXd>& points, bool gradient);

/// Options of the descent on the attractor points.
struct TrajectoryOptimizerOptions {
  int max_iterations = 40;           ///< iterations (>= 1)
  double initial_step = 1e-2;        ///< first step length along -gradient, metres/radians (> 0)
  double relative_tolerance = 1e-6;  ///< stop when the cost decreases by less than this fraction
  /// Called with 0 and the start's cost, then after every iteration with its number (1-based)
  /// and the accepted rollout's cost (its terminal cost was the last one evaluated).
  std::function<void(int, const TrajectoryCost&)> on_iteration;
  /// Throws Error naming the field when a value is out of range.
  void validate() const;
};

/// Outcome of an optimisation.
enum class TrajectoryStatus {
  kConverged,      ///< relative decrease below the tolerance or no descent step found
  kIterationLimit  ///< max_iterations reached
};

/// Result of optimizeTrajectory.
struct TrajectoryOptimization {
  TrajectoryStatus status = TrajectoryStatus::kIterationLimit;  ///< outcome
  std::string message;                                          ///< one line for people
  std::vector<Eigen::VectorXd> points;                          ///< optimised attractor points
  TrajectoryCost cost;                  ///< cost (and rollout) at the optimised points
  std::vector<TrajectoryCost> history;  ///< cost terms per iteration (gradient cleared), 0 first
  int iterations = 0;                   ///< iterations run
};

/// Gradient descent with a backtracking (Armijo) line search and an adaptive step length on
/// the attractor points, from `points`. Throws Error on an invalid problem, points or options.
TrajectoryOptimization optimizeTrajectory(const TrajectoryProblem& problem,
                                          std::vector<Eigen::VectorXd> points,
                                          const TrajectoryOptimizerOptions& options);

}  // namespace taskmap
