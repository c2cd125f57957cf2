#pragma once
// Closed, outward-oriented test solids shared by the unit tests and benchmarks.

#include <cmath>

#include "taskmap/core/constants.hpp"
#include "taskmap/core/triangle_mesh.hpp"

namespace taskmap::testing {

/// Axis-aligned box with full extents (sx, sy, sz) centred at `centre`, metres.
inline TriangleMesh makeBox(double sx, double sy, double sz,
                            const Eigen::Vector3d& centre = Eigen::Vector3d::Zero()) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i)
    m.vertices.push_back(centre + Eigen::Vector3d((i & 1 ? 0.5 : -0.5) * sx,
                                                  (i & 2 ? 0.5 : -0.5) * sy,
                                                  (i & 4 ? 0.5 : -0.5) * sz));
  const int f[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                        {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (const auto& t : f) m.faces.emplace_back(t[0], t[1], t[2]);
  return m;
}

/// Cylinder of radius r and length h along `axis` (0 = x, 1 = y, 2 = z), centred at the
/// origin, with n sides.
inline TriangleMesh makeCylinder(double r, double h, int n, int axis = 2) {
  TriangleMesh m;
  auto put = [&](double x, double y, double z) {
    Eigen::Vector3d v(x, y, z);
    // Map the local z axis to `axis` by a cyclic permutation (keeps orientation).
    if (axis == 0) v = Eigen::Vector3d(z, x, y);
    if (axis == 1) v = Eigen::Vector3d(y, z, x);
    m.vertices.push_back(v);
  };
  for (int i = 0; i < n; ++i) {
    const double a = 2 * kPi * i / n;
    put(r * std::cos(a), r * std::sin(a), -0.5 * h);
    put(r * std::cos(a), r * std::sin(a), 0.5 * h);
  }
  put(0, 0, -0.5 * h);
  put(0, 0, 0.5 * h);
  const int cb = 2 * n, ct = 2 * n + 1;
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    const int b0 = 2 * i, t0 = 2 * i + 1, b1 = 2 * j, t1 = 2 * j + 1;
    m.faces.emplace_back(b0, b1, t1);
    m.faces.emplace_back(b0, t1, t0);
    m.faces.emplace_back(cb, b1, b0);
    m.faces.emplace_back(ct, t0, t1);
  }
  return m;
}

}  // namespace taskmap::testing
