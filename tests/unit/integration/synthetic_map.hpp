#pragma once
// Synthetic task maps for the integration tests and benchmark: grasps on three "handle bars"
// of a basket (left, right, top), each a 2-D manifold (along the bar, around the bar) in pose
// space with a little noise, epsilons in [0, 0.3] (some 0), and one cluster per bar.

#include <cmath>
#include <cstdint>

#include "taskmap/core/pose.hpp"
#include "taskmap/core/random.hpp"
#include "taskmap/mapstore/task_map_data.hpp"

namespace taskmap {
namespace testing {

/// A pose near one of the bars (bar 0..2), drawn from rng.
inline Pose barPose(Rng& rng, int bar, double noise = 0.003) {
  static const Eigen::Vector3d kCentres[3] = {
      {-0.15, 0.0, 0.15}, {0.15, 0.0, 0.15}, {0.0, 0.0, 0.30}};
  static const Eigen::Vector3d kAxes[3] = {{0, 0, 1}, {0, 0, 1}, {1, 0, 0}};
  const Eigen::Vector3d a = kAxes[bar];
  const Eigen::Vector3d u = a.unitOrthogonal();
  const Eigen::Vector3d v = a.cross(u);
  const double t = rng.uniform(-0.1, 0.1);
  const double phi = rng.uniform(0.0, 2.0 * M_PI);
  const Eigen::Vector3d radial = std::cos(phi) * u + std::sin(phi) * v;
  Pose p;
  p.position = kCentres[bar] + t * a + 0.06 * radial;
  for (int k = 0; k < 3; ++k) p.position[k] += noise * rng.normal();
  // Palm z-axis approaches the bar, x-axis along the bar.
  Eigen::Matrix3d r;
  r.col(2) = -radial;
  r.col(0) = a;
  r.col(1) = r.col(2).cross(r.col(0));
  const Eigen::Vector3d tilt(noise * 10 * rng.normal(), noise * 10 * rng.normal(),
                             noise * 10 * rng.normal());
  p.orientation = Eigen::Quaterniond(rotationExp(tilt) * r).normalized();
  if (p.orientation.w() < 0) p.orientation.coeffs() *= -1.0;
  return p;
}

/// A map of n grasps spread over the three bars, with clustering (one cluster per bar).
inline TaskMapData syntheticMap(std::size_t n, std::uint64_t seed = 7, double rho = 0.1) {
  TaskMapData m;
  m.generator = "synthetic";
  m.object.name = "synthetic basket";
  m.object.vertices.resize(0, 3);
  m.grasps.rotation_scale = rho;
  m.grasps.pose.resize(static_cast<Eigen::Index>(n), 7);
  m.grasps.epsilon.resize(n);
  m.grasps.force_closure.resize(n);
  m.grasps.volume.assign(n, 0.0);
  m.grasps.contact_offsets.assign(n + 1, 0);
  m.grasps.contacts_available = false;
  m.grasps.contact_points.resize(0, 3);
  m.grasps.contact_normals.resize(0, 3);
  ClusteringResult c;
  c.rotation_scale = rho;
  c.clusters.resize(3);
  c.labels.resize(n);
  Rng rng(seed, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const int bar = static_cast<int>(i % 3);
    const Pose p = barPose(rng, bar);
    m.grasps.pose.row(static_cast<Eigen::Index>(i)) = p.toVector7().transpose();
    const double eps = rng.uniform() < 0.1 ? 0.0 : rng.uniform(0.0, 0.3);
    m.grasps.epsilon[i] = eps;
    m.grasps.force_closure[i] = eps > 0 ? 1 : 0;
    c.labels[i] = bar;
    auto& s = c.clusters[static_cast<std::size_t>(bar)];
    ++s.size;
    if (s.representative < 0 || eps > s.best_epsilon) {
      s.representative = static_cast<int>(i);
      s.best_epsilon = eps;
    }
  }
  // Joints (none) and a structurally valid chain dendrogram, so that writeMap accepts the map.
  m.grasps.joints.resize(static_cast<Eigen::Index>(n), 0);
  c.linkage.resize(n > 0 ? static_cast<Eigen::Index>(n - 1) : 0, 4);
  for (Eigen::Index r = 0; r < c.linkage.rows(); ++r) {
    const double a = r == 0 ? 0.0 : static_cast<double>(n) + static_cast<double>(r - 1);
    c.linkage.row(r) << a, static_cast<double>(r + 1), 0.01 * static_cast<double>(r),
        static_cast<double>(r + 2);
  }
  m.clustering = c;
  return m;
}

/// A uniformly random pose in the box around the basket.
inline Pose randomPose(Rng& rng) {
  Pose p;
  p.position =
      Eigen::Vector3d(rng.uniform(-0.3, 0.3), rng.uniform(-0.2, 0.2), rng.uniform(0.0, 0.4));
  p.orientation = rng.rotation();
  return p;
}

/// The synthetic map of n grasps with every grasp stored twice (grasps i and n + i equal, no
/// clustering): equal distances, for tie-breaking tests.
inline TaskMapData duplicatedMap(std::size_t n) {
  const TaskMapData data = syntheticMap(n);
  TaskMapData twice = data;
  twice.grasps.pose.conservativeResize(static_cast<Eigen::Index>(2 * n), 7);
  twice.grasps.pose.bottomRows(static_cast<Eigen::Index>(n)) = data.grasps.pose;
  twice.grasps.epsilon.insert(twice.grasps.epsilon.end(), data.grasps.epsilon.begin(),
                              data.grasps.epsilon.end());
  twice.clustering.reset();
  return twice;
}

}  // namespace testing
}  // namespace taskmap
