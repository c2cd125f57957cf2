// Validation, default parameters and index construction of TaskMap.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "sample_weight.hpp"
#include "task_map_impl.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/integration/criteria.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap {
namespace {

/// Samples used to estimate the sampling density (deterministic stride).
constexpr std::size_t kDensitySamples = 2000;

std::string grasp(std::size_t i) {
  return "/grasps row " + std::to_string(i);
}

}  // namespace

void TaskMap::Impl::buildSet(SampleSet& s, const std::vector<std::size_t>& members) const {
  const Impl& m = *this;
  s.count = members.size();
  std::vector<double> rows(s.count * kRowStride);
  for (std::size_t k = 0; k < s.count; ++k) {
    Pose p;
    p.position = m.pos[members[k]];
    p.orientation = m.qconj[members[k]].conjugate();
    const PoseEmbedding e = embedPose(p, m.rho);
    std::copy(e.data(), e.data() + kEmbeddingDim, rows.data() + k * kRowStride);
    rows[k * kRowStride + kWeightColumn] = m.weight[members[k]];
  }
  // Rows in the ball tree's leaf order (else the index's): a query's candidates and hits are
  // contiguous blocks.
  std::vector<Eigen::Vector3d> positions(s.count);
  std::vector<Eigen::Vector4d> quaternions(s.count);
  for (std::size_t k = 0; k < s.count; ++k) {
    positions[k] = m.pos[members[k]];
    const Eigen::Quaterniond q = m.qconj[members[k]].conjugate();
    quaternions[k] = Eigen::Vector4d(q.w(), q.x(), q.y(), q.z());
  }
  s.ball = detail::PoseBallTree::build(positions, quaternions, m.rho);
  std::vector<std::size_t> order;
  if (s.ball) {
    order.assign(s.ball->order().begin(), s.ball->order().end());
  } else {
    order = detail::NnIndex::leafOrder(rows.data(), s.count, kEmbeddingDim, kRowStride);
  }
  s.grasp.resize(s.count);
  s.rows.resize(s.count * kRowStride);
  for (std::size_t k = 0; k < s.count; ++k) {
    s.grasp[k] = members[order[k]];
    std::copy(rows.data() + order[k] * kRowStride, rows.data() + (order[k] + 1) * kRowStride,
              s.rows.data() + k * kRowStride);
  }
  // Total in grasp order, independent of the layout.
  s.total_weight = 0.0;
  for (const std::size_t i : members) s.total_weight += m.weight[i];
  s.index = std::make_unique<detail::NnIndex>(
      s.rows.data(), s.count, kEmbeddingDim, kRowStride, s.grasp.data(),
      m.options.index == IndexKind::kRandomizedForest, m.options.trees, m.options.checks,
      /*reorder=*/s.ball != nullptr);
}

void TaskMap::Impl::build() {
  readGrasps();
  const std::size_t n = pos.size();
  std::vector<std::size_t> every(n);
  for (std::size_t i = 0; i < n; ++i) every[i] = i;
  buildSet(all, every);
  buildClusters();
  // W_map: w_r = rho^2 w_p by default (docs/METHOD.md §4).
  wp = options.linear_weight;
  wr = options.angular_weight.value_or(rho * rho * wp);
  options.angular_weight = wr;
  chooseKernelWidths();
  setTruncation();
}

void TaskMap::Impl::readGrasps() {
  const MapGrasps& g = data.grasps;
  const std::size_t n = static_cast<std::size_t>(g.pose.rows());
  if (n == 0) throw Error("task map has no grasps; build a map with at least one valid grasp");
  if (g.pose.cols() != 7)
    throw Error("/grasps/pose has " + std::to_string(g.pose.cols()) +
                " columns; expected 7 (x y z qw qx qy qz)");
  if (g.epsilon.size() != n)
    throw Error("/grasps/epsilon has " + std::to_string(g.epsilon.size()) + " entries; expected " +
                std::to_string(n) + " (one per grasp)");
  if (!(std::isfinite(g.rotation_scale) && g.rotation_scale > 0))
    throw Error("/grasps rotation_scale is not a finite positive length (metres per radian)");
  rho = g.rotation_scale;
  options.sample_weight = detail::resolveSampleWeight(data, options.sample_weight);
  const std::vector<double> margin = options.sample_weight == SampleWeight::kHoldMargin
                                         ? detail::holdMargins(data)
                                         : std::vector<double>(n, 1.0);
  pos.resize(n);
  qconj.resize(n);
  weight.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Matrix<double, 7, 1> v = g.pose.row(static_cast<Eigen::Index>(i)).transpose();
    if (!v.allFinite()) throw Error(grasp(i) + ": pose has a non-finite value");
    const Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);
    if (std::abs(q.norm() - 1.0) > 1e-6)
      throw Error(grasp(i) + ": orientation is not a unit quaternion (norm " +
                  std::to_string(q.norm()) + ")");
    pos[i] = v.head<3>();
    qconj[i] = q.normalized().conjugate();
    const double eps = g.epsilon[i];
    if (!(std::isfinite(eps) && eps >= 0))
      throw Error(grasp(i) + ": epsilon " + std::to_string(eps) + " is not a finite value >= 0");
    weight[i] = eps * margin[i];
  }
}

void TaskMap::Impl::buildClusters() {
  const std::size_t n = pos.size();
  clusters.clear();
  if (data.clustering) {
    const ClusteringResult& c = *data.clustering;
    const int k = static_cast<int>(c.clusters.size());
    if (c.labels.size() != n)
      throw Error("/grasps/cluster has " + std::to_string(c.labels.size()) + " labels; expected " +
                  std::to_string(n) + " (one per grasp)");
    clusters.resize(static_cast<std::size_t>(k));
    std::vector<std::vector<std::size_t>> members(static_cast<std::size_t>(k));
    for (std::size_t i = 0; i < n; ++i) {
      const int l = c.labels[i];
      if (l < -1 || l >= k)
        throw Error(grasp(i) + ": cluster label " + std::to_string(l) + " outside -1.." +
                    std::to_string(k - 1));
      if (l >= 0) members[static_cast<std::size_t>(l)].push_back(i);
    }
    for (int j = 0; j < k; ++j) {
      const int rep = c.clusters[static_cast<std::size_t>(j)].representative;
      if (rep < 0 || static_cast<std::size_t>(rep) >= n ||
          c.labels[static_cast<std::size_t>(rep)] != j)
        throw Error("/clusters row " + std::to_string(j) + ": representative " +
                    std::to_string(rep) + " is not a grasp of that cluster");
      buildSet(clusters[static_cast<std::size_t>(j)], members[static_cast<std::size_t>(j)]);
    }
  }
}

void TaskMap::Impl::chooseKernelWidths() {
  const std::size_t n = pos.size();
  // Kernel widths: sigma_p from the sampling density (median nearest-neighbour pose distance
  // over a deterministic subset of at most kDensitySamples samples), sigma_r = sigma_p / rho.
  if (!options.position_sigma) {
    if (n < 2)
      throw Error(
          "task map has a single grasp: the sampling density is undefined; set "
          "position_sigma (and rotation_sigma) explicitly");
    const std::size_t stride = std::max<std::size_t>(1, n / kDensitySamples);
    std::vector<double> nn;
    std::vector<detail::IndexHit> hits;
    for (std::size_t i = 0; i < n; i += stride) {
      Pose p;
      p.position = pos[i];
      p.orientation = qconj[i].conjugate();
      const PoseEmbedding e = embedPose(p, rho);  // bitwise the row of grasp i
      all.index->knn(e.data(), 2, hits);
      // hits hold the sample itself (distance 0) and its nearest other sample.
      double d2 = 0.0;
      for (const auto& h : hits)
        if (all.grasp[h.index] != i) d2 = h.distance2;
      nn.push_back(std::sqrt(d2));
    }
    std::nth_element(nn.begin(), nn.begin() + static_cast<std::ptrdiff_t>(nn.size() / 2), nn.end());
    const double median = nn[nn.size() / 2];
    if (!(median > 0))
      throw Error(
          "task map grasps are duplicated so densely that the median nearest-neighbour "
          "distance is 0; set position_sigma and rotation_sigma explicitly");
    options.position_sigma = options.bandwidth_factor * median;
  }
  sp = *options.position_sigma;
  sr = options.rotation_sigma.value_or(sp / rho);
  options.rotation_sigma = sr;
  inv_sp2 = 1.0 / (sp * sp);
  inv_se2 = 1.0 / (rho * sr * rho * sr);
  inv_z = 1.0 / gaussianNormaliser(sp, sr);
}

void TaskMap::Impl::setTruncation() {
  // Truncation. In the embedding x = (p, (rho/sqrt2) vec R) the kernel distance is
  //   d = |dx_p|^2 / sp^2 + |dx_R|^2 / (rho sr)^2   (|dx_R|^2 = rho^2/2 ||dR||_F^2),
  // and the index distance is D^2 = |dx_p|^2 + |dx_R|^2. With s = max(sp, rho sr) both
  // coefficients are >= 1/s^2, so d >= D^2 / s^2 exactly (no approximation of the angle).
  // Omitted samples have D > r_c = t_c s, hence d > t_c^2 and each omitted density is below
  // exp(-t_c^2 / 2) / Z = tol / Z. With the default sr = sp / rho, d = D^2 / sp^2.
  const double s = std::max(sp, rho * sr);
  const double tc = std::sqrt(2.0 * std::log(1.0 / options.quality_tolerance));
  cutoff = tc * s;
  cutoff2 = cutoff * cutoff * (1.0 + 1e-12);  // include boundary samples despite rounding
  value_bound_factor = options.quality_tolerance * inv_z;
  // Gradient of one term (criteria.hpp): |grad f_i| = f_i/2 |grad d_i| with
  // |grad d_i|^2 = 4 |dp|^2 / sp^4 + |v(R R_i^T)|^2 / sr^4 and |v(R R_i^T)| = 2 sin(theta)
  // <= 2 (2 sin(theta/2)), so |grad d_i|^2 <= 4 d_i / min(sp, sr)^2 and
  // |grad f_i| <= f_i sqrt(d_i) / min(sp, sr); t exp(-t^2/2) decreases for t >= 1 and peaks at
  // exp(-1/2) at t = 1.
  const double peak = tc >= 1.0 ? tc * std::exp(-0.5 * tc * tc) : std::exp(-0.5);
  gradient_bound_factor = peak * inv_z / std::min(sp, sr);
}

TaskMap TaskMap::load(const std::string& path, const TaskMapOptions& options) {
  options.validate();
  TaskMapData data = readMap(path);
  try {
    return fromData(std::move(data), options);
  } catch (const Error& e) {
    throw Error("task map " + path + ": " + e.what());
  }
}

}  // namespace taskmap
