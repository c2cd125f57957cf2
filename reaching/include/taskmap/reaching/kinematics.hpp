#pragma once
/// @file kinematics.hpp
/// Forward kinematics of every body, geometric Jacobians and the relative task descriptors of
/// the paper (eq. 1.3-1.5, docs/REACHING.md). World frame = the robot's root frame. Units:
/// metres, radians; Jacobians map joint velocities (rad/s, m/s) to m/s and rad/s.

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "taskmap/reaching/robot_model.hpp"

namespace taskmap {

/// Kinematic state of a RobotModel at one configuration. Holds a pointer to the model, which
/// must outlive it. Not thread-safe while update() runs; one instance per thread.
class Kinematics {
 public:
  /// Binds to a model; the state is the model's mid configuration until update().
  explicit Kinematics(const RobotModel& robot);

  /// Forward kinematics of every body at q (dofs() values). Throws Error on a size mismatch
  /// or a non-finite value.
  void update(const Eigen::VectorXd& q);
  /// Configuration of the last update().
  const Eigen::VectorXd& q() const { return q_; }
  /// The bound model.
  const RobotModel& robot() const { return *robot_; }
  /// Pose of a body frame in the world frame.
  const Eigen::Isometry3d& pose(int body) const { return poses_[body]; }

  /// Linear Jacobian (3 x dofs, world frame) of the point `point` (world coordinates) rigidly
  /// attached to `body`; zero for environment bodies. Writes into out (3 x dofs).
  void pointJacobian(int body, const Eigen::Vector3d& point,
                     Eigen::Ref<Eigen::Matrix3Xd> out) const;
  /// Allocating form of pointJacobian.
  Eigen::Matrix3Xd pointJacobian(int body, const Eigen::Vector3d& point) const;
  /// g += J(point)^T f: the joint-space image of a force f (world) at the point `point` (world
  /// coordinates) rigidly attached to `body`, without forming J. g has dofs() entries.
  void addJacobianTransposeTimes(int body, const Eigen::Vector3d& point, const Eigen::Vector3d& f,
                                 Eigen::Ref<Eigen::VectorXd> g) const;
  /// Angular (rotational) Jacobian of a body (3 x dofs, world frame).
  Eigen::Matrix3Xd angularJacobian(int body) const;
  /// Geometric Jacobian of the body frame origin: rows 0-2 linear, rows 3-5 angular (world).
  Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian(int body) const;

  /// g_k += sum_ij adjoint_ij dJ_ij/dq_k for the geometric Jacobian J = jacobian(body) (rows
  /// 0-2 linear, 3-5 angular, world frame): the reverse-mode product through the Jacobian's
  /// dependence on q along the kinematic chain (docs/REACHING.md T3, eq. T3.4). adjoint is
  /// 6 x dofs(), g has dofs() entries.
  void addJacobianAdjoint(int body, const Eigen::Matrix<double, 6, Eigen::Dynamic>& adjoint,
                          Eigen::Ref<Eigen::VectorXd> g) const;

  /// Position of `body` relative to `reference` expressed in the reference frame, eq. 1.3;
  /// reference -1 means the world.
  Eigen::Vector3d relativePosition(int body, int reference) const;
  /// Its Jacobian (3 x dofs), eq. 1.4: A_10 (J_T2 - J_T1 + [r_12]x J_R1).
  Eigen::Matrix3Xd relativePositionJacobian(int body, int reference) const;
  /// Orientation of `body` relative to `reference`: R_1^T R_2.
  Eigen::Matrix3d relativeRotation(int body, int reference) const;
  /// Jacobian (3 x dofs) of the relative angular velocity expressed in the reference frame,
  /// eq. 1.5: A_10 (J_R2 - J_R1).
  Eigen::Matrix3Xd relativeAngularJacobian(int body, int reference) const;

  /// Centre of mass of the robot and hand bodies (world, metres), eq. 1.6: sum m_i r_i / M.
  /// Throws Error when the model has no mass (a URDF without <inertial>).
  Eigen::Vector3d centerOfMass() const;
  /// Its Jacobian (3 x dofs), eq. 1.6: sum m_i J_T(r_i) / M.
  Eigen::Matrix3Xd centerOfMassJacobian() const;

 private:
  const RobotModel* robot_;
  Eigen::VectorXd q_;
  std::vector<Eigen::Isometry3d> poses_;
  std::vector<Eigen::Vector3d> axis_world_;    // per dof: joint axis in world
  std::vector<Eigen::Vector3d> origin_world_;  // per dof: joint frame origin in world
  std::vector<bool> prismatic_;                // per dof
};

}  // namespace taskmap
