#pragma once
// Synthetic task maps for tests and benchmarks (no dependency on the pipeline): a basket-like
// object (a box with a U-shaped handle of three bars) and grasps around the bars.
//  - syntheticMap(n, seed, rho): n grasps spread over the three bars, one cluster per bar,
//    epsilons in [0, 0.3] (some 0); the runtime library's tests and benchmark.
//  - clusteredBasketMap(per_cluster, outliers, seed): with the basket mesh, outliers and
//    cluster summaries; the inspection, export and ACRONYM tests.
//  - duplicatedMap(n): every grasp twice, for tie-breaking tests.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

#include "taskmap/core/pose.hpp"
#include "taskmap/core/random.hpp"
#include "taskmap/mapstore/task_map_data.hpp"

namespace taskmap::testing {

/// A structurally valid chain dendrogram of n points (scipy format; point k+1 joins the cluster
/// so far at height step * k), so that writeMap accepts a map whose tests never read it.
inline LinkageMatrix chainLinkage(Eigen::Index n, double step) {
  LinkageMatrix z(n > 0 ? n - 1 : 0, 4);
  for (Eigen::Index r = 0; r < z.rows(); ++r) {
    const double a = r == 0 ? 0.0 : static_cast<double>(n + r - 1);
    z.row(r) << a, static_cast<double>(r + 1), step * static_cast<double>(r),
        static_cast<double>(r + 2);
  }
  return z;
}

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
  c.linkage = chainLinkage(static_cast<Eigen::Index>(n), 0.01);

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

// Appends an axis-aligned box [lo, hi] (8 vertices, 12 outward triangles).
inline void appendBox(std::vector<Eigen::Vector3d>& v, std::vector<Eigen::Vector3i>& f,
                      const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const int base = static_cast<int>(v.size());
  for (int i = 0; i < 8; ++i)
    v.emplace_back((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(), (i & 4) ? hi.z() : lo.z());
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    f.emplace_back(base + q[0], base + q[1], base + q[2]);
    f.emplace_back(base + q[0], base + q[2], base + q[3]);
  }
}

// Basket: body 0.30 x 0.20 x 0.12 m, handle bars at x = +-0.14 rising to z = 0.30, top bar.
inline MapObject basketObject() {
  std::vector<Eigen::Vector3d> v;
  std::vector<Eigen::Vector3i> f;
  appendBox(v, f, {-0.15, -0.10, 0.0}, {0.15, 0.10, 0.12});
  appendBox(v, f, {-0.15, -0.01, 0.12}, {-0.13, 0.01, 0.30});
  appendBox(v, f, {0.13, -0.01, 0.12}, {0.15, 0.01, 0.30});
  appendBox(v, f, {-0.15, -0.01, 0.28}, {0.15, 0.01, 0.30});
  MapObject o;
  o.name = "basket";
  o.scale = 1.0;
  o.volume = 0.30 * 0.20 * 0.12;
  o.center_of_mass = Eigen::Vector3d(0, 0, 0.07);
  o.torque_scale = 0.25;
  o.vertices.resize(static_cast<Eigen::Index>(v.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i) o.vertices.row(static_cast<Eigen::Index>(i)) = v[i];
  o.faces.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (std::size_t i = 0; i < f.size(); ++i)
    o.faces.row(static_cast<Eigen::Index>(i)) = f[i].cast<std::int64_t>();
  return o;
}

// Orientation whose +z axis (approach) is dir, with a random twist about it.
inline Eigen::Quaterniond approachOrientation(const Eigen::Vector3d& dir, Rng& rng) {
  const Eigen::Quaterniond align =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), dir);
  const double twist = rng.uniform(-0.3, 0.3);
  return align * Eigen::Quaterniond(Eigen::AngleAxisd(twist, Eigen::Vector3d::UnitZ()));
}

/// The inspection tests' map: the basket object (basketObject), n_per_cluster grasps around each
/// of the three bars (fewer on later bars) plus n_outliers scattered grasps, clustered by
/// construction with cluster summaries, contacts available (none stored).
inline TaskMapData clusteredBasketMap(int n_per_cluster = 40, int n_outliers = 6,
                                      std::uint64_t seed = 11) {
  TaskMapData m;
  m.generator = "taskmap test";
  m.created_utc = "2026-01-01T00:00:00Z";
  m.object = basketObject();
  m.hand.name = "three_finger";
  m.hand.urdf_sha256 = "";
  m.hand.joint_names = {"f1", "f2", "f3"};
  m.sampling.sampler = "volume";
  m.sampling.seed = seed;
  Rng rng(seed, 0);
  // Bar centres and the direction the palm approaches from (+z axis points at the bar).
  const Eigen::Vector3d centres[3] = {{0.0, 0.0, 0.29}, {-0.14, 0.0, 0.21}, {0.14, 0.0, 0.21}};
  const Eigen::Vector3d approach[3] = {{0, 0, -1}, {1, 0, 0}, {-1, 0, 0}};
  const Eigen::Vector3d spread[3] = {{0.12, 0.0, 0.0}, {0.0, 0.0, 0.07}, {0.0, 0.0, 0.07}};
  std::vector<int> labels;
  std::vector<Eigen::Matrix<double, 7, 1>> rows;
  std::vector<double> eps;
  for (int k = 0; k < 3; ++k) {
    const int size = std::max(1, n_per_cluster * (5 - k) / 5);
    for (int i = 0; i < size; ++i) {
      const Eigen::Vector3d p = centres[k] + rng.uniform(-1, 1) * spread[k] - 0.05 * approach[k] +
                                0.004 * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
      Pose pose{p, approachOrientation(approach[k], rng)};
      rows.push_back(pose.toVector7());
      labels.push_back(k);
      eps.push_back(0.02 + 0.1 * rng.uniform() * (3 - k) / 3.0);
    }
  }
  for (int i = 0; i < n_outliers; ++i) {
    const Eigen::Vector3d p(rng.uniform(-0.2, 0.2), rng.uniform(0.12, 0.2), rng.uniform(0, 0.3));
    Pose pose{p, rng.rotation()};
    rows.push_back(pose.toVector7());
    labels.push_back(-1);
    eps.push_back(i % 2 == 0 ? 0.0 : 0.01);
  }
  const auto n = static_cast<Eigen::Index>(rows.size());
  auto& g = m.grasps;
  g.pose.resize(n, 7);
  for (Eigen::Index i = 0; i < n; ++i)
    g.pose.row(i) = rows[static_cast<std::size_t>(i)].transpose();
  g.joints = RowMatrixXd::Constant(n, 3, 0.4);
  g.epsilon = eps;
  g.force_closure.resize(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) g.force_closure[i] = eps[i] > 0 ? 1 : 0;
  g.volume.assign(rows.size(), 1e-3);
  g.contact_offsets.assign(rows.size() + 1, 0);
  g.contact_points.resize(0, 3);
  g.contact_normals.resize(0, 3);
  g.contacts_available = true;
  g.rotation_scale = 0.1;
  m.sampling.trials = 3 * rows.size();
  m.sampling.outcomes = {{"ok", rows.size()}, {"no_contact", 2 * rows.size()}};

  ClusteringResult c;
  c.labels = labels;
  c.method = Linkage::kSingle;
  c.rotation_scale = 0.1;
  c.threshold = 0.05;
  c.min_size = 3;
  // A valid chain dendrogram (the tests never read it): point k+1 joins the cluster so far.
  c.linkage = chainLinkage(n, 0.001);

  for (int k = 0; k < 3; ++k) {
    ClusterSummary s;
    std::vector<Eigen::Quaterniond> qs;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    s.bounds_min = Eigen::Vector3d::Constant(1e9);
    s.bounds_max = Eigen::Vector3d::Constant(-1e9);
    double eps_sum = 0;
    for (std::size_t i = 0; i < labels.size(); ++i) {
      if (labels[i] != k) continue;
      const Pose p = g.poseAt(i);
      ++s.size;
      sum += p.position;
      qs.push_back(p.orientation);
      eps_sum += eps[i];
      s.bounds_min = s.bounds_min.cwiseMin(p.position);
      s.bounds_max = s.bounds_max.cwiseMax(p.position);
      if (s.representative < 0 || eps[i] > s.best_epsilon) {
        s.representative = static_cast<int>(i);
        s.best_epsilon = eps[i];
      }
    }
    s.mean_pose.position = sum / s.size;
    s.mean_pose.orientation = meanOrientation(qs);
    s.mean_epsilon = eps_sum / s.size;
    c.clusters.push_back(s);
  }
  m.clustering = c;
  return m;
}

}  // namespace taskmap::testing
