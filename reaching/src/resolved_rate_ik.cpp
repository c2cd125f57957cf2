// Resolved-rate IK, eq. 1.1-1.2 with the null-space criteria eq. 1.8 and 1.16.
#include "taskmap/reaching/resolved_rate_ik.hpp"

#include <cassert>
#include <cmath>

#include <Eigen/Cholesky>

#include "taskmap/core/error.hpp"
#include "taskmap/core/pose.hpp"
#include "taskmap/reaching/robot_costs.hpp"

namespace taskmap {

void IkOptions::validate(int dofs) const {
  const auto check = [](double v, const char* name) {
    if (!(v >= 0.0) || !std::isfinite(v))
      throw Error(std::string("IK options: ") + name + " must be finite and >= 0");
  };
  check(feedback_gain, "feedback_gain");
  check(joint_limit_gain, "joint_limit_gain");
  check(collision_gain, "collision_gain");
  check(damping, "damping");
  if (joint_weights.size() != 0 && (joint_weights.size() != dofs || !joint_weights.allFinite() ||
                                    joint_weights.minCoeff() <= 0.0))
    throw Error("IK options: joint_weights needs " + std::to_string(dofs) +
                " finite values > 0 (or none for weights proportional to the joint ranges)");
}

double jointLimitCost(const RobotModel& robot, const Eigen::VectorXd& q,
                      Eigen::VectorXd* gradient) {
  return jointLimitCost(q, robot.lower(), robot.upper(), gradient);
}

double jointLimitMargin(const RobotModel& robot, const Eigen::VectorXd& q) {
  return std::min((q - robot.lower()).minCoeff(), (robot.upper() - q).minCoeff());
}

ResolvedRateIK::ResolvedRateIK(const RobotModel& robot, std::vector<TaskSpec> tasks,
                               const CollisionModel* collisions, const IkOptions& options)
    : robot_(&robot), tasks_(std::move(tasks)), collisions_(collisions), options_(options) {
  options.validate(robot.dofs());
  const int bodies = static_cast<int>(robot.bodies().size());
  for (const TaskSpec& t : tasks_) {
    if (t.kind == TaskKind::kJoint) {
      if (t.dof < 0 || t.dof >= robot.dofs())
        throw Error("IK task: joint index " + std::to_string(t.dof) + " out of range 0.." +
                    std::to_string(robot.dofs() - 1));
      rows_ += 1;
    } else if (t.kind == TaskKind::kCenterOfMass) {
      Kinematics(robot).centerOfMass();  // throws when the model has no mass
      rows_ += 3;
    } else {
      if (t.body < 0 || t.body >= bodies || t.reference < -1 || t.reference >= bodies)
        throw Error("IK task: body or reference index out of range (bodies: " +
                    std::to_string(bodies) + ", reference -1 for the world)");
      rows_ += 3;
    }
  }
  if (rows_ == 0) throw Error("IK: give at least one task");
  if (options.joint_weights.size() == robot.dofs()) {
    weights_ = options.joint_weights;
  } else {
    weights_ = robot.upper() - robot.lower();
    weights_ /= weights_.mean();
  }
}

void ResolvedRateIK::taskError(const Kinematics& kin, const std::vector<TaskGoal>& goals,
                               Eigen::VectorXd& error, Eigen::MatrixXd& jacobian) const {
  if (goals.size() != tasks_.size())
    throw Error("IK: " + std::to_string(goals.size()) + " goals for " +
                std::to_string(tasks_.size()) + " tasks; give one goal per task");
  error.resize(rows_);
  jacobian.setZero(rows_, robot_->dofs());
  int row = 0;
  for (size_t i = 0; i < tasks_.size(); ++i) {
    const TaskSpec& t = tasks_[i];
    const TaskGoal& g = goals[i];
    switch (t.kind) {
      case TaskKind::kPosition:
        error.segment<3>(row) = g.position - kin.relativePosition(t.body, t.reference);
        jacobian.middleRows<3>(row) = kin.relativePositionJacobian(t.body, t.reference);
        row += 3;
        break;
      case TaskKind::kOrientation:
        // Rotation vector from the current to the desired orientation, reference frame.
        error.segment<3>(row) =
            rotationLog(g.rotation * kin.relativeRotation(t.body, t.reference).transpose());
        jacobian.middleRows<3>(row) = kin.relativeAngularJacobian(t.body, t.reference);
        row += 3;
        break;
      case TaskKind::kCenterOfMass:
        error.segment<3>(row) = g.position - kin.centerOfMass();
        jacobian.middleRows<3>(row) = kin.centerOfMassJacobian();
        row += 3;
        break;
      case TaskKind::kJoint:
        error[row] = g.value - kin.q()[t.dof];
        jacobian(row, t.dof) = 1.0;
        row += 1;
        break;
    }
  }
}

IkVelocity ResolvedRateIK::velocity(const Kinematics& kin,
                                    const std::vector<TaskGoal>& goals) const {
  return velocity(kin, goals, std::vector<bool>(robot_->dofs(), false));
}

IkVelocity ResolvedRateIK::velocity(const Kinematics& kin, const std::vector<TaskGoal>& goals,
                                    const std::vector<bool>& locked) const {
  return velocity(kin, goals, locked, nullptr);
}

IkVelocity ResolvedRateIK::velocity(const Kinematics& kin, const std::vector<TaskGoal>& goals,
                                    const std::vector<bool>& locked, IkStepTrace* trace) const {
  assert(static_cast<int>(locked.size()) == robot_->dofs());
  IkVelocity out;
  Eigen::MatrixXd j;
  taskError(kin, goals, out.task_error, j);
  Eigen::VectorXd w_inv = weights_.cwiseInverse();
  for (int i = 0; i < robot_->dofs(); ++i) {
    if (locked[i]) {
      j.col(i).setZero();
      w_inv[i] = 0.0;
    }
  }
  Eigen::VectorXd xdot(rows_);
  int row = 0;
  for (size_t i = 0; i < tasks_.size(); ++i) {
    if (tasks_[i].kind == TaskKind::kJoint) {
      xdot[row++] = goals[i].rate;
    } else {
      xdot.segment<3>(row) = goals[i].velocity;
      row += 3;
    }
  }
  xdot += options_.feedback_gain * out.task_error;
  // Eq. 1.2: J# = W^-1 J^T (J W^-1 J^T + lambda^2 E)^-1, N = E - J# J.
  const Eigen::MatrixXd jw = j * w_inv.asDiagonal();  // J W^-1
  Eigen::MatrixXd a = jw * j.transpose();
  a.diagonal().array() += options_.damping * options_.damping;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(a);
  out.qdot = jw.transpose() * ldlt.solve(xdot);
  // Null-space term -N W^-1 grad H^T, with N W^-1 g = W^-1 g - J# (J W^-1 g).
  Eigen::VectorXd grad_jl;
  out.joint_limit_cost = jointLimitCost(*robot_, kin.q(), &grad_jl);
  Eigen::VectorXd grad = options_.joint_limit_gain * grad_jl;
  if (collisions_) {
    Eigen::VectorXd grad_c;
    out.collision_cost = collisions_->cost(kin, &grad_c);
    grad += options_.collision_gain * grad_c;
    if (trace) trace->collision_gradient = std::move(grad_c);
  }
  const Eigen::VectorXd wg = w_inv.cwiseProduct(grad);
  out.qdot -= wg - jw.transpose() * ldlt.solve(j * wg);
  if (trace) {
    trace->multiplier = ldlt.solve(xdot + j * wg);
    trace->locked = locked;
    trace->jacobian = std::move(j);
    trace->w_inv = std::move(w_inv);
    trace->task_error = out.task_error;
    trace->collision_cost = out.collision_cost;
    if (!collisions_) trace->collision_gradient.resize(0);
    trace->gradient = std::move(grad);
    trace->qdot = out.qdot;
  }
  return out;
}

Eigen::VectorXd ResolvedRateIK::step(const Kinematics& kin, const std::vector<TaskGoal>& goals,
                                     double dt, IkVelocity* out) const {
  return step(kin, goals, dt, out, nullptr);
}

Eigen::VectorXd ResolvedRateIK::step(const Kinematics& kin, const std::vector<TaskGoal>& goals,
                                     double dt, IkVelocity* out, IkStepTrace* trace) const {
  if (!(dt > 0.0) || !std::isfinite(dt)) throw Error("IK step: dt must be > 0 seconds");
  std::vector<bool> locked(robot_->dofs(), false);
  IkVelocity v;
  Eigen::VectorXd q;
  for (int pass = 0; pass <= robot_->dofs(); ++pass) {
    v = velocity(kin, goals, locked, trace);
    // Respect the velocity limits by scaling the whole step (keeps its direction).
    int fastest = 0;
    const double ratio =
        v.qdot.cwiseAbs().cwiseQuotient(robot_->velocityLimits()).maxCoeff(&fastest);
    v.qdot /= std::max(1.0, ratio);
    if (trace) {
      trace->scale = std::max(1.0, ratio);
      trace->scale_joint = ratio > 1.0 ? fastest : -1;
    }
    q = kin.q() + dt * v.qdot;
    bool changed = false;
    for (int i = 0; i < robot_->dofs(); ++i) {
      if (!locked[i] && (q[i] < robot_->lower()[i] || q[i] > robot_->upper()[i])) {
        locked[i] = changed = true;
      }
    }
    if (!changed) break;
  }
  if (trace) {
    trace->clamped.assign(robot_->dofs(), false);
    for (int i = 0; i < robot_->dofs(); ++i)
      trace->clamped[i] = q[i] < robot_->lower()[i] || q[i] > robot_->upper()[i];
  }
  q = q.cwiseMax(robot_->lower()).cwiseMin(robot_->upper());
  if (out) *out = std::move(v);
  return q;
}

}  // namespace taskmap
