#include "taskmap/core/pose.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include "taskmap/core/error.hpp"

namespace taskmap {
Eigen::Matrix3d skewMatrix(const Eigen::Vector3d& v) {
  Eigen::Matrix3d s;
  s << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return s;
}

Pose Pose::fromVector7(const Eigen::Matrix<double, 7, 1>& v) {
  if (!v.allFinite())
    throw Error("pose has a non-finite value; give x y z qw qx qy qz as finite numbers");
  Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);
  const double n = q.norm();
  if (n < 1e-9) throw Error("pose quaternion has zero norm; give a unit quaternion (qw qx qy qz)");
  Pose p;
  p.position = v.head<3>();
  p.orientation = Eigen::Quaterniond(q.coeffs() / n);
  return p;
}

Eigen::Matrix<double, 7, 1> Pose::toVector7() const {
  Eigen::Quaterniond q = orientation.normalized();
  if (q.w() < 0) q.coeffs() *= -1.0;
  Eigen::Matrix<double, 7, 1> v;
  v << position, q.w(), q.x(), q.y(), q.z();
  return v;
}

Eigen::Isometry3d Pose::toIsometry() const {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = orientation.normalized().toRotationMatrix();
  t.translation() = position;
  return t;
}

Pose Pose::fromIsometry(const Eigen::Isometry3d& t) {
  Pose p;
  p.position = t.translation();
  p.orientation = Eigen::Quaterniond(t.linear()).normalized();
  return p;
}

double rotationAngle(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  const double d = std::min(1.0, std::abs(a.normalized().dot(b.normalized())));
  return 2.0 * std::acos(d);
}

double poseDistanceSquared(const Pose& a, const Pose& b, double rho) {
  // (2 sin(theta/2))^2 = 4 (1 - cos^2(theta/2)) = 4 (1 - <qa,qb>^2): exact and sign-invariant.
  const double d = a.orientation.normalized().dot(b.orientation.normalized());
  const double chord2 = std::max(0.0, 4.0 * (1.0 - d * d));
  return (a.position - b.position).squaredNorm() + rho * rho * chord2;
}

double poseDistance(const Pose& a, const Pose& b, double rho) {
  return std::sqrt(poseDistanceSquared(a, b, rho));
}

PoseEmbedding embedPose(const Pose& pose, double rho) {
  PoseEmbedding e;
  const Eigen::Matrix3d r = pose.orientation.normalized().toRotationMatrix();
  e.head<3>() = pose.position;
  e.tail<9>() = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(r.data()) * (rho / std::sqrt(2.0));
  return e;
}

Pose unembedPose(const PoseEmbedding& e, double rho) {
  Eigen::Matrix3d m =
      Eigen::Map<const Eigen::Matrix3d>(e.tail<9>().data()) * (std::sqrt(2.0) / rho);
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d r = svd.matrixU() * svd.matrixV().transpose();
  if (r.determinant() < 0) {
    Eigen::Matrix3d u = svd.matrixU();
    u.col(2) *= -1.0;
    r = u * svd.matrixV().transpose();
  }
  Pose p;
  p.position = e.head<3>();
  p.orientation = Eigen::Quaterniond(r).normalized();
  return p;
}

Eigen::Vector3d rotationLog(const Eigen::Matrix3d& r) {
  const Eigen::AngleAxisd aa(Eigen::Quaterniond(r).normalized());
  return aa.axis() * aa.angle();
}

Eigen::Matrix3d rotationExp(const Eigen::Vector3d& w) {
  const double theta = w.norm();
  if (theta < 1e-12) return Eigen::Matrix3d::Identity() + skewMatrix(w);
  return Eigen::AngleAxisd(theta, w / theta).toRotationMatrix();
}

Eigen::Matrix3d rightJacobianInverse(const Eigen::Vector3d& w) {
  const double theta = w.norm();
  const Eigen::Matrix3d s = skewMatrix(w);
  double c;
  if (theta < 1e-4) {
    c = 1.0 / 12.0 + theta * theta / 720.0;
  } else {
    c = 1.0 / (theta * theta) - (1.0 + std::cos(theta)) / (2.0 * theta * std::sin(theta));
  }
  return Eigen::Matrix3d::Identity() + 0.5 * s + c * s * s;
}

Eigen::Quaterniond meanOrientation(const std::vector<Eigen::Quaterniond>& qs) {
  if (qs.empty()) throw Error("meanOrientation needs at least one orientation");
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  for (const auto& q : qs) {
    const Eigen::Vector4d v = q.normalized().coeffs();
    m += v * v.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> es(m);
  Eigen::Vector4d v = es.eigenvectors().col(3);
  Eigen::Quaterniond q(v[3], v[0], v[1], v[2]);
  if (q.w() < 0) q.coeffs() *= -1.0;
  return q.normalized();
}

}  // namespace taskmap
