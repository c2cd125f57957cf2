#pragma once
/// @file attractor.hpp
/// Attractor dynamics of the paper (eq. 1.17-1.19, docs/REACHING.md): a second-order system
/// follows an attractor point moved linearly between attractor points; the task trajectory is
/// tracked by resolved-rate IK at each step (a reaching rollout). Units: metres, radians, s.

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "taskmap/reaching/resolved_rate_ik.hpp"

namespace taskmap {

/// Parameters of eq. 1.19.
struct AttractorOptions {
  double relaxation_time = 0.2;  ///< T_mc, seconds (> 0)
  double damping = 1.0;          ///< xi (> 0); 1 gives the paper's non-overshooting response
  double dt = 0.01;              ///< sampling time Delta t, seconds (> 0)
  /// Throws Error naming the field when a value is out of range.
  void validate() const;
};

/// Coefficients a, b of eq. 1.18-1.19.
struct AttractorCoefficients {
  double a = 0.0;  ///< dt^2 / (T^2 + 2 T xi dt + dt^2)
  double b = 0.0;  ///< T^2 / (T^2 + 2 T xi dt + dt^2)
};

/// Eq. 1.19 (validates the options).
AttractorCoefficients attractorCoefficients(const AttractorOptions& options);

/// Eq. 1.17-1.18: x_{t+1} = x_t + a (r_{t+1} - x_t) + b (x_t - x_{t-1}).
Eigen::VectorXd attractorStep(const AttractorCoefficients& c, const Eigen::VectorXd& x,
                              const Eigen::VectorXd& x_previous, const Eigen::VectorXd& r_next);

/// The attractor point at time t (seconds, >= 0): linear interpolation from x0 through
/// points[0], points[1], ..., segment_time seconds per segment, then the last point.
Eigen::VectorXd attractorPoint(const Eigen::VectorXd& x0,
                               const std::vector<Eigen::VectorXd>& points, double segment_time,
                               double t);

/// Attractor trajectory of `steps` steps from rest at x0. The attractor point r(t) moves
/// linearly from x0 through points[0], points[1], ... (at least one, same size as x0), taking
/// segment_time seconds (> 0) per segment, then stays at the last point. Returns steps + 1
/// states, x0 first. Throws Error on sizes or values out of range.
std::vector<Eigen::VectorXd> attractorTrajectory(const AttractorOptions& options,
                                                 const Eigen::VectorXd& x0,
                                                 const std::vector<Eigen::VectorXd>& points,
                                                 double segment_time, int steps);

/// Options of a reaching rollout.
struct ReachOptions {
  AttractorOptions attractor;  ///< task-space dynamics
  IkOptions ik;                ///< resolved-rate IK gains
  int steps = 300;             ///< control steps (>= 1)
  double move_time = 1.0;      ///< seconds for the attractor point to travel to the target (> 0)
  /// Intermediate poses of the body (reference frame) the attractor point passes through on
  /// its way to the target, move_time / (via_points.size() + 1) seconds per segment.
  std::vector<Eigen::Isometry3d> via_points;
  double position_tolerance = 1e-3;     ///< metres: reached when the final error is below
  double orientation_tolerance = 1e-2;  ///< radians: reached when the final error is below
  /// Throws Error naming the field when a value is out of range.
  void validate() const;
};

/// Outcome of a rollout.
enum class ReachStatus {
  kReached,     ///< final pose within tolerance and never closer than 0 to an obstacle
  kNotReached,  ///< final pose error above tolerance
  kCollided     ///< some pair penetrated (signed distance < 0) during the rollout
};

/// A reaching rollout: joint trajectory and summary.
struct ReachResult {
  ReachStatus status = ReachStatus::kNotReached;  ///< outcome
  std::string message;                            ///< one line for people
  std::vector<Eigen::VectorXd> q;                 ///< steps + 1 configurations, q0 first
  std::vector<Eigen::Isometry3d> palm;            ///< palm pose in the reference frame per step
  double position_error = 0.0;                    ///< final |p_target - p|, metres
  double orientation_error = 0.0;                 ///< final rotation angle to the target, radians
  double min_clearance = 0.0;       ///< smallest signed pair distance over the rollout, metres
  std::string min_clearance_pair;   ///< the pair where it occurred ("" without pairs)
  int min_clearance_step = 0;       ///< the step where it occurred
  double joint_limit_margin = 0.0;  ///< smallest distance to a joint limit over the rollout
};

/// Task variables of a pose: position (metres) and rotation vector (radians) of
/// frame^T pose.linear(), the orientation relative to the fixed rotation `frame`.
Eigen::Matrix<double, 6, 1> taskVariables(const Eigen::Isometry3d& pose,
                                          const Eigen::Matrix3d& frame);

/// Pose of the task variables x (inverse of taskVariables): translation x[0:3], rotation
/// frame * exp(x[3:6]).
Eigen::Isometry3d goalPose(const Eigen::VectorXd& x, const Eigen::Matrix3d& frame);

/// One control step of the rollout: the IK (tasks: position, orientation of one body) tracks
/// the attractor state moving from x to x_next (task variables relative to `frame`) with
/// feedback on x; kin must hold the current configuration. Returns q_{t+1}. With `trace`, the
/// IK step's intermediate values are recorded for its derivative (ik_step_derivative.hpp).
Eigen::VectorXd reachStep(const ResolvedRateIK& ik, const Kinematics& kin,
                          const Eigen::Matrix3d& frame, double dt, const Eigen::VectorXd& x,
                          const Eigen::VectorXd& x_next, IkStepTrace* trace = nullptr);

/// Moves `body` (usually the palm) to `target` (its pose in the `reference` body frame, -1 =
/// world) from q0 with attractor dynamics on (position, rotation vector relative to the target)
/// and resolved-rate IK with the joint-limit and (when given) collision null-space terms.
/// Throws Error on invalid options, a wrong q0 size, or q0 outside the joint limits.
ReachResult reach(const RobotModel& robot, const CollisionModel* collisions, int body,
                  int reference, const Eigen::Isometry3d& target, const Eigen::VectorXd& q0,
                  const ReachOptions& options);

}  // namespace taskmap
