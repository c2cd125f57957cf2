#pragma once
/// @file ik_step_derivative.hpp
/// Analytic reverse-mode derivative of one reaching control step q_{t+1} = F(q_t, x_t, x_{t+1})
/// (reachStep: attractor goals + resolved-rate IK step, eq. 1.1-1.2 with the null-space terms
/// of eq. 1.8 and 1.16, velocity scaling, joint locking and clamping): the vector-Jacobian
/// products (dF/dq_t)^T lambda, (dF/dx_t)^T lambda, (dF/dx_{t+1})^T lambda of the trajectory
/// optimiser's backward pass (docs/REACHING.md T3). Units: metres, radians, seconds.

#include <Eigen/Core>

#include "taskmap/reaching/attractor.hpp"

namespace taskmap {

/// Adjoints of the inputs of one reaching step for an adjoint lambda of its output q_{t+1}.
struct ReachStepAdjoint {
  Eigen::VectorXd q;                   ///< (dF/dq_t)^T lambda, dofs() entries
  Eigen::Matrix<double, 6, 1> x;       ///< (dF/dx_t)^T lambda (task variables)
  Eigen::Matrix<double, 6, 1> x_next;  ///< (dF/dx_{t+1})^T lambda (task variables)
};

/// Reverse-mode derivative of reachStep for one ResolvedRateIK (tasks: position, orientation of
/// one body relative to a reference that no joint moves). Holds pointers to the IK, which must
/// outlive it, and a scratch kinematic state: one instance per thread.
class ReachStepDerivative {
 public:
  /// `frame` and `dt` (seconds) as given to reachStep; `hessian_epsilon` (radians, in
  /// (0, 1e-2]) is the step of the directional central difference of the collision gradient.
  /// Throws Error when the IK's tasks are not reachStep's or the reference moves with q.
  ReachStepDerivative(const ResolvedRateIK& ik, const Eigen::Matrix3d& frame, double dt,
                      double hessian_epsilon = 1e-6);

  /// Vector-Jacobian products at the step's inputs: kin holds q_t, trace was recorded by
  /// reachStep(ik, kin, frame, dt, x, x_next, &trace), lambda has dofs() entries. The locked
  /// joints, the clamped joints and the velocity-scaling joint of the trace are held as they
  /// are (the derivative of the branch taken, as the finite differences see it).
  ReachStepAdjoint vectorJacobian(const Kinematics& kin, const Eigen::VectorXd& x,
                                  const Eigen::VectorXd& x_next, const IkStepTrace& trace,
                                  const Eigen::VectorXd& lambda);

 private:
  const ResolvedRateIK* ik_;
  Eigen::Matrix3d frame_;
  double dt_;
  double epsilon_;
  int body_ = -1, reference_ = -1;
  Kinematics scratch_;
};

}  // namespace taskmap
