#pragma once
/// @file resolved_rate_ik.hpp
/// Resolved-rate inverse kinematics of the paper (eq. 1.1-1.2, 1.8, docs/REACHING.md):
/// weighted generalized pseudo-inverse, closed-loop error feedback, null-space projection of
/// the joint-limit and collision gradients. Units: metres, radians, seconds.

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "taskmap/reaching/collision_model.hpp"
#include "taskmap/reaching/kinematics.hpp"

namespace taskmap {

/// Kind of a task descriptor (paper section 1.2.1.1).
enum class TaskKind {
  kPosition,     ///< 3 rows: position of body relative to reference, reference frame (eq. 1.4)
  kOrientation,  ///< 3 rows: angular velocity of body relative to reference (eq. 1.5)
  kJoint,        ///< 1 row: a single joint value
  kCenterOfMass  ///< 3 rows: centre of mass of the robot, world frame (eq. 1.6)
};

/// One task descriptor.
struct TaskSpec {
  TaskKind kind = TaskKind::kPosition;  ///< kind
  int body = -1;                        ///< controlled body (kPosition, kOrientation)
  int reference = -1;  ///< reference body, -1 for the world (kPosition, kOrientation)
  int dof = -1;        ///< joint index (kJoint)
};

/// Desired value and velocity of one task, expressed in the task's reference frame.
struct TaskGoal {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();      ///< kPosition: metres
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  ///< kOrientation: body in reference
  double value = 0.0;                                      ///< kJoint: radians or metres
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();      ///< feed-forward m/s or rad/s
  double rate = 0.0;                                       ///< kJoint feed-forward velocity
};

/// Gains of eq. 1.1.
struct IkOptions {
  double feedback_gain = 10.0;    ///< K of the closed-loop term K (x_d - x), 1/s (>= 0)
  double joint_limit_gain = 1.0;  ///< alpha for the joint-limit gradient (eq. 1.8), 1/s (>= 0)
  double collision_gain = 100.0;  ///< alpha for the collision gradient (eq. 1.16), 1/s (>= 0)
  /// Damping lambda of (J W^-1 J^T + lambda^2 E)^-1 against singularities (>= 0, 0 = exact).
  double damping = 1e-3;
  /// Diagonal of W; empty means proportional to the joint ranges (the paper's choice),
  /// normalised to mean 1. Entries > 0.
  Eigen::VectorXd joint_weights;
  /// Throws Error naming the field when a value is out of range for a robot with `dofs` joints.
  void validate(int dofs) const;
};

/// Result of one velocity evaluation.
struct IkVelocity {
  Eigen::VectorXd qdot;        ///< joint velocity, rad/s or m/s
  Eigen::VectorXd task_error;  ///< stacked task error x_d - x (rotation vectors for kOrientation)
  double joint_limit_cost = 0.0;  ///< H_jl (eq. 1.8)
  double collision_cost = 0.0;    ///< H_coll (eq. 1.10), 0 without a collision model
};

/// Intermediate values of one ResolvedRateIK::step() that its derivative needs
/// (ik_step_derivative.hpp, docs/REACHING.md T3). Values of the final pass (after locking).
struct IkStepTrace {
  std::vector<bool> locked;     ///< joints held still (would have left their range)
  Eigen::MatrixXd jacobian;     ///< task Jacobian J with the locked columns zeroed
  Eigen::VectorXd w_inv;        ///< diagonal of W^-1 with the locked entries zeroed
  Eigen::VectorXd task_error;   ///< x_d - x (rotation vectors for kOrientation)
  Eigen::VectorXd gradient;     ///< g = alpha_jl dH_jl/dq + alpha_c dH_coll/dq
  Eigen::VectorXd multiplier;   ///< y = (J W^-1 J^T + lambda^2 E)^-1 (xdot_d + K e + J W^-1 g)
  Eigen::VectorXd qdot;         ///< velocity of eq. 1.1 before the velocity-limit scaling
  double scale = 1.0;           ///< s = max(1, max_i |qdot_i| / qdot_max,i); the step uses qdot / s
  int scale_joint = -1;         ///< the joint i attaining s when s > 1, else -1
  std::vector<bool> clamped;    ///< joints clamped onto a limit after the last pass
  double collision_cost = 0.0;  ///< H_coll(q) (eq. 1.10), 0 without a collision model
  Eigen::VectorXd collision_gradient;  ///< dH_coll/dq (eq. 1.16), empty without a model
};

/// Joint limit cost H_jl = 1/2 sum ((q_i - q_mid,i) / (q_max,i - q_min,i))^2 (eq. 1.8) and its
/// gradient (when given).
double jointLimitCost(const RobotModel& robot, const Eigen::VectorXd& q, Eigen::VectorXd* gradient);

/// Smallest distance of q to a joint limit, min_i min(q_i - lower_i, upper_i - q_i).
double jointLimitMargin(const RobotModel& robot, const Eigen::VectorXd& q);

/// Resolved-rate IK over a stack of tasks. Holds pointers to the robot and the collision
/// model (optional), which must outlive it. Thread-safe for const use with separate Kinematics.
class ResolvedRateIK {
 public:
  /// Throws Error on invalid options or a task naming an unknown body or joint.
  ResolvedRateIK(const RobotModel& robot, std::vector<TaskSpec> tasks,
                 const CollisionModel* collisions, const IkOptions& options);

  int taskRows() const { return rows_; }                            ///< stacked task dimension
  const std::vector<TaskSpec>& tasks() const { return tasks_; }     ///< the task stack
  const IkOptions& options() const { return options_; }             ///< the options
  const Eigen::VectorXd& weights() const { return weights_; }       ///< diagonal of W
  const RobotModel& robot() const { return *robot_; }               ///< the robot
  const CollisionModel* collisions() const { return collisions_; }  ///< pairs or null

  /// Stacked task error x_d - x and task Jacobian at the state of kin.
  void taskError(const Kinematics& kin, const std::vector<TaskGoal>& goals, Eigen::VectorXd& error,
                 Eigen::MatrixXd& jacobian) const;
  /// Eq. 1.1: qdot = J# (xdot_d + K (x_d - x)) - N W^-1 (alpha_jl dH_jl/dq + alpha_c dH_coll/dq)^T.
  /// Throws Error when goals.size() differs from the number of tasks.
  IkVelocity velocity(const Kinematics& kin, const std::vector<TaskGoal>& goals) const;
  /// As velocity(), with the joints flagged in `locked` (dofs() entries) held still: their
  /// Jacobian columns and W^-1 entries are zeroed.
  IkVelocity velocity(const Kinematics& kin, const std::vector<TaskGoal>& goals,
                      const std::vector<bool>& locked) const;
  /// Integrates qdot with time step dt (seconds): q + dt qdot, scaled to the velocity limits.
  /// A joint that would leave its range is locked at its limit and the velocity recomputed
  /// without it (the other joints take over its share of the task).
  Eigen::VectorXd step(const Kinematics& kin, const std::vector<TaskGoal>& goals, double dt,
                       IkVelocity* out = nullptr) const;
  /// As step(), also recording the intermediate values its derivative needs into *trace.
  Eigen::VectorXd step(const Kinematics& kin, const std::vector<TaskGoal>& goals, double dt,
                       IkVelocity* out, IkStepTrace* trace) const;

 private:
  IkVelocity velocity(const Kinematics& kin, const std::vector<TaskGoal>& goals,
                      const std::vector<bool>& locked, IkStepTrace* trace) const;

  const RobotModel* robot_;
  std::vector<TaskSpec> tasks_;
  const CollisionModel* collisions_;
  IkOptions options_;
  Eigen::VectorXd weights_;
  int rows_ = 0;
};

}  // namespace taskmap
