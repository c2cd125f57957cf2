#pragma once
/// @file quality_fixtures.hpp
/// Random contact sets and an analytic wrench set shared by the quality tests, benchmark and
/// the scipy helper.

#include <cmath>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "taskmap/core/contact.hpp"
#include "taskmap/core/random.hpp"

namespace taskmap::testing {

/// Semi-axes of the test ellipsoid (metres): a box-like object of 10 x 6 x 4 cm.
inline Eigen::Vector3d ellipsoidAxes() {
  return {0.05, 0.03, 0.02};
}

/// A pressing contact (depth in metres) at `point` with the unit normal along `normal`.
inline Contact makeContact(Eigen::Vector3d point, Eigen::Vector3d normal, double depth = 1e-3) {
  Contact c;
  c.point = point;
  c.normal = normal.normalized();
  c.depth = depth;
  return c;
}

/// n contacts on the ellipsoid surface about the origin, outward normals, depth > 0.
/// With `tilt` > 0 the normals are perturbed (still unit), like noisy simulated contacts.
inline std::vector<Contact> randomContacts(Rng& rng, int n, double tilt = 0.0) {
  const Eigen::Vector3d ax = ellipsoidAxes();
  std::vector<Contact> out;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d d = rng.direction();
    Contact c;
    c.point = ax.cwiseProduct(d);
    c.normal = d.cwiseQuotient(ax).normalized();
    if (tilt > 0.0) c.normal = (c.normal + tilt * rng.direction()).normalized();
    c.depth = rng.uniform(1e-4, 2e-3);
    c.link = i;
    out.push_back(c);
  }
  return out;
}

/// The 6-simplex with vertices -e_1..-e_6 and (1,...,1), one per column. Its 7 facets: opposite
/// (1,...,1) the facet sum x = -1, at distance 1/sqrt 6 from the origin; opposite -e_k the
/// hyperplane 6 x_k - sum_{i != k} x_i = 1 (it contains -e_i, i != k, and (1,...,1)), at
/// distance 1/sqrt(36 + 5) = 1/sqrt 41. The origin is inside, so epsilon = 1/sqrt 41.
inline Eigen::Matrix<double, 6, Eigen::Dynamic> simplexWrenches() {
  Eigen::Matrix<double, 6, Eigen::Dynamic> w(6, 7);
  w.leftCols(6) = -Eigen::Matrix<double, 6, 6>::Identity();
  w.col(6).setOnes();
  return w;
}

/// 6-D volume of the simplex spanned by the 7 columns of w: |det(v_1 - v_0, ...)| / 6!.
inline double simplexVolume(const Eigen::Matrix<double, 6, Eigen::Dynamic>& w) {
  Eigen::Matrix<double, 6, 6> d;
  for (int k = 0; k < 6; ++k) d.col(k) = w.col(k + 1) - w.col(0);
  return std::abs(d.determinant()) / 720.0;
}

/// Applies the rigid motion x -> R x + t to points and normals.
inline std::vector<Contact> moved(const std::vector<Contact>& contacts,
                                  const Eigen::Isometry3d& motion) {
  std::vector<Contact> out = contacts;
  for (Contact& c : out) {
    c.point = motion * c.point;
    c.normal = motion.linear() * c.normal;
  }
  return out;
}

}  // namespace taskmap::testing
