// Reverse-mode derivative of one reaching step, docs/REACHING.md T3 (eq. T3.1-T3.6).
#include "taskmap/reaching/ik_step_derivative.hpp"

#include <cassert>
#include <cmath>

#include <Eigen/Cholesky>

#include "taskmap/core/error.hpp"
#include "taskmap/core/pose.hpp"

namespace taskmap {
namespace {

/// Right Jacobian of SO(3): exp(w + dw) = exp(w) exp(J_r(w) dw).
Eigen::Matrix3d rightJacobian(const Eigen::Vector3d& w) {
  const double t = w.norm();
  double a, b;  // (1 - cos t) / t^2, (t - sin t) / t^3
  if (t < 1e-4) {
    a = 0.5 - t * t / 24.0;
    b = 1.0 / 6.0 - t * t / 120.0;
  } else {
    a = (1.0 - std::cos(t)) / (t * t);
    b = (t - std::sin(t)) / (t * t * t);
  }
  const Eigen::Matrix3d s = skewMatrix(w);
  return Eigen::Matrix3d::Identity() - a * s + b * s * s;
}

bool sameTask(const TaskSpec& t, TaskKind kind, int body, int reference) {
  return t.kind == kind && t.body == body && t.reference == reference;
}

}  // namespace

ReachStepDerivative::ReachStepDerivative(const ResolvedRateIK& ik, const Eigen::Matrix3d& frame,
                                         double dt, double hessian_epsilon)
    : ik_(&ik), frame_(frame), dt_(dt), epsilon_(hessian_epsilon), scratch_(ik.robot()) {
  const auto& tasks = ik.tasks();
  if (tasks.size() != 2 || tasks[0].kind != TaskKind::kPosition ||
      !sameTask(tasks[1], TaskKind::kOrientation, tasks[0].body, tasks[0].reference))
    throw Error(
        "reach step derivative: the IK needs reachStep's tasks (position, orientation "
        "of one body)");
  body_ = tasks[0].body;
  reference_ = tasks[0].reference;
  if (reference_ >= 0 && !ik.robot().bodyDofs()[reference_].empty())
    throw Error(
        "reach step derivative: the reference body moves with the joints; use the "
        "finite-difference step derivative");
  if (!(dt > 0.0) || !(hessian_epsilon > 0.0) || hessian_epsilon > 1e-2)
    throw Error("reach step derivative: dt must be > 0 s and hessian_epsilon in (0, 1e-2]");
}

ReachStepAdjoint ReachStepDerivative::vectorJacobian(const Kinematics& kin,
                                                     const Eigen::VectorXd& x,
                                                     const Eigen::VectorXd& x_next,
                                                     const IkStepTrace& t,
                                                     const Eigen::VectorXd& lambda) {
  const RobotModel& robot = ik_->robot();
  const int n = robot.dofs();
  assert(lambda.size() == n && t.jacobian.rows() == 6 && t.qdot.size() == n);
  ReachStepAdjoint out;
  // T3.1: q_{t+1} = clamp(q + dt qdot / s); clamped rows carry no derivative.
  Eigen::VectorXd lam = lambda;
  for (int i = 0; i < n; ++i)
    if (t.clamped[i]) lam[i] = 0.0;
  out.q = lam;
  // T3.2: velocity scaling s = |qdot_m| / vmax_m (m held), qdot_s = qdot / s.
  Eigen::VectorXd u = dt_ * lam / t.scale;
  if (t.scale_joint >= 0) {
    const int m = t.scale_joint;
    const double sign = t.qdot[m] >= 0.0 ? 1.0 : -1.0;
    u[m] -= t.qdot.dot(dt_ * lam) / (t.scale * t.scale) * sign / robot.velocityLimits()[m];
  }
  // T3.3: qdot = D J^T y - D g, y = A^-1 (xdot + J D g), A = J D J^T + lambda^2 E.
  const Eigen::MatrixXd& j = t.jacobian;
  const Eigen::VectorXd& d = t.w_inv;
  const Eigen::MatrixXd jd = j * d.asDiagonal();
  Eigen::MatrixXd a = jd * j.transpose();
  const double damping = ik_->options().damping;
  a.diagonal().array() += damping * damping;
  const Eigen::VectorXd du = d.cwiseProduct(u);
  const Eigen::VectorXd z = Eigen::LDLT<Eigen::MatrixXd>(a).solve(j * du);  // adjoint of xdot
  const Eigen::VectorXd& y = t.multiplier;
  const Eigen::VectorXd dg = d.cwiseProduct(t.gradient);
  const Eigen::VectorXd g_bar = jd.transpose() * z - du;
  Eigen::Matrix<double, 6, Eigen::Dynamic> j_bar =
      y * du.transpose() + z * dg.transpose() - (z * y.transpose() + y * z.transpose()) * jd;
  // T3.4: through J(q); the task Jacobian is A_ref J_world with a fixed reference.
  if (reference_ >= 0) {
    const Eigen::Matrix3d r = kin.pose(reference_).linear();
    j_bar.topRows<3>() = r * j_bar.topRows<3>().eval();
    j_bar.bottomRows<3>() = r * j_bar.bottomRows<3>().eval();
  }
  kin.addJacobianAdjoint(body_, j_bar, out.q);
  // T3.5: the task error e = (x_p - p(q), log(R_now R(q)^T)), e_bar = K z.
  const double k = ik_->options().feedback_gain;
  const Eigen::Vector3d ep_bar = k * z.head<3>(), er_bar = k * z.tail<3>();
  const Eigen::Vector3d e_r = t.task_error.tail<3>();
  const Eigen::Matrix3d jr_inv = rightJacobianInverse(e_r);
  out.q -= kin.relativePositionJacobian(body_, reference_).transpose() * ep_bar;
  out.q -=
      kin.relativeAngularJacobian(body_, reference_).transpose() * (jr_inv.transpose() * er_bar);
  // T3.6: through the null-space gradient g(q): the joint-limit Hessian is diagonal, the
  // collision Hessian enters as a directional central difference of eq. 1.16 along g_bar.
  const Eigen::VectorXd range = robot.upper() - robot.lower();
  out.q += ik_->options().joint_limit_gain * g_bar.cwiseQuotient(range.cwiseProduct(range));
  const double g_norm = g_bar.norm();
  // H_coll(q) = 0 means every pair lies in the zero zone (eq. 1.9; all terms are >= 0): the
  // Hessian is zero there (up to the zone boundary, a kink), and the difference is skipped.
  if (ik_->collisions() && ik_->options().collision_gain > 0.0 && g_norm > 0.0 &&
      t.collision_cost > 0.0) {
    const Eigen::VectorXd dir = g_bar / g_norm;
    Eigen::VectorXd plus, minus;
    scratch_.update(kin.q() + epsilon_ * dir);
    ik_->collisions()->cost(scratch_, &plus);
    scratch_.update(kin.q() - epsilon_ * dir);
    ik_->collisions()->cost(scratch_, &minus);
    out.q += ik_->options().collision_gain * g_norm / (2.0 * epsilon_) * (plus - minus);
  }
  // T3.7: the goals from x and x_next (reachStep): feedback on x, feed-forward velocities.
  const Eigen::Matrix3d r_now = frame_ * rotationExp(x.tail<3>());
  const Eigen::Matrix3d r_rel = kin.relativeRotation(body_, reference_);
  const Eigen::Vector3d phi =
      rotationLog(frame_ * rotationExp(x_next.tail<3>()) * r_now.transpose());
  const Eigen::Matrix3d v_inv = rightJacobianInverse(phi);
  const Eigen::Vector3d vr_bar = z.tail<3>() / dt_;
  out.x.head<3>() = ep_bar - z.head<3>() / dt_;
  out.x_next.head<3>() = z.head<3>() / dt_;
  out.x.tail<3>() =
      rightJacobian(x.tail<3>()).transpose() * (r_rel.transpose() * (jr_inv.transpose() * er_bar) -
                                                r_now.transpose() * (v_inv.transpose() * vr_bar));
  out.x_next.tail<3>() = rightJacobian(x_next.tail<3>()).transpose() *
                         (r_now.transpose() * (v_inv.transpose() * vr_bar));
  return out;
}

}  // namespace taskmap
