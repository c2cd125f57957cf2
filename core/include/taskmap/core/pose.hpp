#pragma once
/// @file pose.hpp
/// Hand poses and the one pose metric of taskmap (docs/METHOD.md §4).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace taskmap {

/// Default rotation scale rho in metres per radian: about a palm-to-fingertip length, so that
/// rho * angle approximates fingertip travel. Maps store the rho they were built with.
constexpr double kDefaultRotationScale = 0.1;

/// Dimension of the Euclidean pose embedding (position, (rho/sqrt 2) * vec(R)).
constexpr int kEmbeddingDim = 12;

/// Embedded pose: a point in R^12 whose Euclidean distances are pose distances.
using PoseEmbedding = Eigen::Matrix<double, kEmbeddingDim, 1>;

/// 6-vector in the object frame: linear part (metres) then angular part (radians).
using Twist = Eigen::Matrix<double, 6, 1>;

/// A rigid pose: the hand's palm frame expressed in the object frame.
/// Position in metres; orientation a unit quaternion, q and -q being the same rotation.
struct Pose {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();               ///< metres, object frame
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< unit quaternion

  /// From (x, y, z, qw, qx, qy, qz); the quaternion is normalised. Throws Error on a
  /// non-finite value or a quaternion of norm below 1e-9.
  static Pose fromVector7(const Eigen::Matrix<double, 7, 1>& v);
  /// To (x, y, z, qw, qx, qy, qz), with qw >= 0 (canonical sign).
  Eigen::Matrix<double, 7, 1> toVector7() const;
  /// As a homogeneous transform (palm frame -> object frame).
  Eigen::Isometry3d toIsometry() const;
  /// From a homogeneous transform; the rotation part must be orthonormal.
  static Pose fromIsometry(const Eigen::Isometry3d& t);
};

/// Squared pose distance d^2 = |dp|^2 + rho^2 (2 sin(theta/2))^2, theta the geodesic angle.
/// Zero between q and -q. @param rho rotation scale, metres per radian (> 0).
double poseDistanceSquared(const Pose& a, const Pose& b, double rho);

/// Pose distance, the square root of poseDistanceSquared.
double poseDistance(const Pose& a, const Pose& b, double rho);

/// Geodesic angle between two orientations in radians, in [0, pi]; 0 between q and -q.
double rotationAngle(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b);

/// Embedding (p, (rho/sqrt 2) vec(R)) in which Euclidean distance equals poseDistance.
/// vec(R) stacks R column by column.
PoseEmbedding embedPose(const Pose& pose, double rho);

/// Inverse of embedPose: the pose whose embedding is nearest (rotation projected on SO(3)).
Pose unembedPose(const PoseEmbedding& e, double rho);

/// Rotation vector (axis * angle, radians, angle in [0, pi]) of a rotation matrix: log map.
Eigen::Vector3d rotationLog(const Eigen::Matrix3d& r);

/// Cross-product matrix [v]x of v: skewMatrix(v) * u == v.cross(u).
Eigen::Matrix3d skewMatrix(const Eigen::Vector3d& v);

/// Rotation matrix of a rotation vector (axis * angle, radians): exp map.
Eigen::Matrix3d rotationExp(const Eigen::Vector3d& w);

/// Right Jacobian inverse of SO(3), J_r^{-1}(w), with d log(R exp(dw)) = J_r^{-1}(log R) dw.
Eigen::Matrix3d rightJacobianInverse(const Eigen::Vector3d& w);

/// Mean orientation of a set (chordal L2 mean: eigenvector of the largest eigenvalue of
/// sum q q^T), sign-invariant. Throws Error on an empty set.
Eigen::Quaterniond meanOrientation(const std::vector<Eigen::Quaterniond>& qs);

}  // namespace taskmap
