// Forward kinematics (one pass from the root), Jacobians from the joint axes, eq. 1.3-1.5.
#include "taskmap/reaching/kinematics.hpp"

#include <cassert>
#include <string>

#include "taskmap/core/error.hpp"
#include "taskmap/core/pose.hpp"

namespace taskmap {

Kinematics::Kinematics(const RobotModel& robot)
    : robot_(&robot),
      poses_(robot.bodies().size()),
      axis_world_(robot.dofs()),
      origin_world_(robot.dofs()),
      prismatic_(robot.dofs(), false) {
  for (const RobotBody& b : robot.bodies())
    if (b.dof >= 0) prismatic_[b.dof] = b.joint == JointType::kPrismatic;
  update(robot.midConfiguration());
}

void Kinematics::update(const Eigen::VectorXd& q) {
  if (q.size() != robot_->dofs())
    throw Error("kinematics: configuration has " + std::to_string(q.size()) + " values, robot '" +
                robot_->name() + "' has " + std::to_string(robot_->dofs()) + " joints");
  if (!q.allFinite()) throw Error("kinematics: configuration has a non-finite value");
  q_ = q;
  const auto& bodies = robot_->bodies();
  for (size_t i = 0; i < bodies.size(); ++i) {
    const RobotBody& b = bodies[i];
    Eigen::Isometry3d joint_frame =
        b.parent >= 0 ? Eigen::Isometry3d(poses_[b.parent] * b.origin) : b.origin;
    if (b.dof >= 0) {
      axis_world_[b.dof] = joint_frame.linear() * b.axis;
      origin_world_[b.dof] = joint_frame.translation();
      if (b.joint == JointType::kRevolute)
        joint_frame.linear() = joint_frame.linear() * Eigen::AngleAxisd(q[b.dof], b.axis).matrix();
      else
        joint_frame.translation() += axis_world_[b.dof] * q[b.dof];
    }
    poses_[i] = joint_frame;
  }
}

void Kinematics::pointJacobian(int body, const Eigen::Vector3d& point,
                               Eigen::Ref<Eigen::Matrix3Xd> out) const {
  assert(out.cols() == robot_->dofs());
  out.setZero();
  if (body < 0) return;
  for (int d : robot_->bodyDofs()[body]) {
    out.col(d) = prismatic_[d] ? axis_world_[d]
                               : Eigen::Vector3d(axis_world_[d].cross(point - origin_world_[d]));
  }
}

void Kinematics::addJacobianTransposeTimes(int body, const Eigen::Vector3d& point,
                                           const Eigen::Vector3d& f,
                                           Eigen::Ref<Eigen::VectorXd> g) const {
  if (body < 0) return;
  for (int d : robot_->bodyDofs()[body]) {
    // (a x (p - o)) . f = a . ((p - o) x f)
    g[d] += prismatic_[d] ? axis_world_[d].dot(f)
                          : axis_world_[d].dot((point - origin_world_[d]).cross(f));
  }
}

Eigen::Matrix3Xd Kinematics::pointJacobian(int body, const Eigen::Vector3d& point) const {
  Eigen::Matrix3Xd j(3, robot_->dofs());
  pointJacobian(body, point, j);
  return j;
}

Eigen::Matrix3Xd Kinematics::angularJacobian(int body) const {
  Eigen::Matrix3Xd j = Eigen::Matrix3Xd::Zero(3, robot_->dofs());
  if (body < 0) return j;
  for (int d : robot_->bodyDofs()[body])
    if (!prismatic_[d]) j.col(d) = axis_world_[d];
  return j;
}

Eigen::Matrix<double, 6, Eigen::Dynamic> Kinematics::jacobian(int body) const {
  Eigen::Matrix<double, 6, Eigen::Dynamic> j(6, robot_->dofs());
  j.topRows<3>() = pointJacobian(body, poses_[body].translation());
  j.bottomRows<3>() = angularJacobian(body);
  return j;
}

void Kinematics::addJacobianAdjoint(int body,
                                    const Eigen::Matrix<double, 6, Eigen::Dynamic>& adjoint,
                                    Eigen::Ref<Eigen::VectorXd> g) const {
  assert(adjoint.cols() == robot_->dofs() && g.size() == robot_->dofs());
  if (body < 0) return;
  // Along the chain (root first), for a joint k before or at joint d: dJp_d/dq_k = a_k x Jp_d,
  // dJr_d/dq_k = a_k x a_d (revolute k); for k after d: dJp_d/dq_k = a_d x Jp_k (revolute d).
  // Hence g_k = a_k . sum_{d >= k} (Jp_d x Gp_d + Jr_d x Gr_d) + Jp_k . sum_{d < k} (Gp_d x a_d).
  const std::vector<int>& chain = robot_->bodyDofs()[body];
  const Eigen::Vector3d p = poses_[body].translation();
  const int m = static_cast<int>(chain.size());
  std::vector<Eigen::Vector3d> jp(m);
  for (int i = 0; i < m; ++i) {
    const int d = chain[i];
    jp[i] = prismatic_[d] ? axis_world_[d]
                          : Eigen::Vector3d(axis_world_[d].cross(p - origin_world_[d]));
  }
  Eigen::Vector3d suffix = Eigen::Vector3d::Zero(), prefix = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> after(m);
  for (int i = m - 1; i >= 0; --i) {
    const int d = chain[i];
    suffix += jp[i].cross(adjoint.col(d).head<3>());
    if (!prismatic_[d]) suffix += axis_world_[d].cross(adjoint.col(d).tail<3>());
    after[i] = suffix;
  }
  for (int i = 0; i < m; ++i) {
    const int k = chain[i];
    if (!prismatic_[k]) g[k] += axis_world_[k].dot(after[i]);
    g[k] += jp[i].dot(prefix);
    if (!prismatic_[k]) prefix += adjoint.col(k).head<3>().cross(axis_world_[k]);
  }
}

Eigen::Vector3d Kinematics::relativePosition(int body, int reference) const {
  if (reference < 0) return poses_[body].translation();
  const Eigen::Isometry3d& r = poses_[reference];
  return r.linear().transpose() * (poses_[body].translation() - r.translation());
}

Eigen::Matrix3Xd Kinematics::relativePositionJacobian(int body, int reference) const {
  const Eigen::Vector3d p2 = poses_[body].translation();
  if (reference < 0) return pointJacobian(body, p2);
  const Eigen::Isometry3d& r = poses_[reference];
  // Eq. 1.4: r_12 = r_02 - r_01; d/dt (A_10 r_12) = A_10 (J_T2 - J_T1 + [r_12]x J_R1) qdot.
  const Eigen::Vector3d r12 = p2 - r.translation();
  return r.linear().transpose() *
         (pointJacobian(body, p2) - pointJacobian(reference, r.translation()) +
          skewMatrix(r12) * angularJacobian(reference));
}

Eigen::Matrix3d Kinematics::relativeRotation(int body, int reference) const {
  if (reference < 0) return poses_[body].linear();
  return poses_[reference].linear().transpose() * poses_[body].linear();
}

Eigen::Matrix3Xd Kinematics::relativeAngularJacobian(int body, int reference) const {
  if (reference < 0) return angularJacobian(body);
  // Eq. 1.5: omega_12 in frame 1 = A_10 (J_R2 - J_R1) qdot.
  return poses_[reference].linear().transpose() *
         (angularJacobian(body) - angularJacobian(reference));
}

namespace {

double robotMass(const RobotModel& robot) {
  double m = 0.0;
  for (const RobotBody& b : robot.bodies())
    if (b.role != BodyRole::kEnvironment) m += b.mass;
  if (!(m > 0.0))
    throw Error("robot '" + robot.name() +
                "' has no mass; the centre of mass needs <inertial> "
                "elements in the URDF");
  return m;
}

}  // namespace

Eigen::Vector3d Kinematics::centerOfMass() const {
  const double total = robotMass(*robot_);
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  const auto& bodies = robot_->bodies();
  for (size_t i = 0; i < bodies.size(); ++i)
    if (bodies[i].role != BodyRole::kEnvironment && bodies[i].mass > 0.0)
      c += bodies[i].mass * (poses_[i] * bodies[i].com);
  return c / total;
}

Eigen::Matrix3Xd Kinematics::centerOfMassJacobian() const {
  const double total = robotMass(*robot_);
  Eigen::Matrix3Xd j = Eigen::Matrix3Xd::Zero(3, robot_->dofs());
  const auto& bodies = robot_->bodies();
  for (size_t i = 0; i < bodies.size(); ++i)
    if (bodies[i].role != BodyRole::kEnvironment && bodies[i].mass > 0.0)
      j += (bodies[i].mass / total) * pointJacobian(static_cast<int>(i), poses_[i] * bodies[i].com);
  return j;
}

}  // namespace taskmap
