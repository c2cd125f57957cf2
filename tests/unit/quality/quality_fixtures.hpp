#pragma once
/// @file quality_fixtures.hpp
/// Random contact sets shared by the quality tests and the scipy helper.

#include <vector>

#include <Eigen/Geometry>

#include "taskmap/meshes/contact.hpp"
#include "taskmap/meshes/random.hpp"

namespace taskmap::testing {

/// Semi-axes of the test ellipsoid (metres): a box-like object of 10 x 6 x 4 cm.
inline Eigen::Vector3d ellipsoidAxes() {
  return {0.05, 0.03, 0.02};
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
