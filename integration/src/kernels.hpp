#pragma once
// Private inline kernels shared by criteria.cpp and task_map.cpp.

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace taskmap {
namespace detail {

/// log of the rotation conj(qm) * q (= R_m^T R) as a rotation vector, angle in [0, pi].
/// qm_conj is the conjugate of the sample's unit quaternion, q the query's unit quaternion.
inline Eigen::Vector3d relativeLog(const Eigen::Quaterniond& qm_conj, const Eigen::Quaterniond& q) {
  Eigen::Quaterniond r = qm_conj * q;
  double w = r.w();
  Eigen::Vector3d v = r.vec();
  if (w < 0) {
    w = -w;
    v = -v;
  }
  const double s = v.norm();
  if (s < 1e-9) return (2.0 / w) * v;  // theta = 2 atan(s / w) = 2 s / w + O(s^3)
  return (2.0 * std::atan2(s, w) / s) * v;
}

}  // namespace detail
}  // namespace taskmap
