#include "taskmap/integration/task_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>

#include "kernels.hpp"
#include "nn_index.hpp"
#include "task_map_impl.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/integration/criteria.hpp"

namespace taskmap {

using detail::IndexHit;

namespace {

std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

void TaskMapOptions::validate() const {
  auto positive = [](const char* name, double v) {
    if (!(std::isfinite(v) && v > 0))
      throw Error(std::string("task map option ") + name + " = " + num(v) +
                  " is invalid; give a finite value > 0");
  };
  if (trees < 1) throw Error("task map option trees = " + num(trees) + " is invalid; give >= 1");
  if (checks < 1) throw Error("task map option checks = " + num(checks) + " is invalid; give >= 1");
  positive("linear_weight", linear_weight);
  if (angular_weight) positive("angular_weight", *angular_weight);
  if (position_sigma) positive("position_sigma", *position_sigma);
  if (rotation_sigma) positive("rotation_sigma", *rotation_sigma);
  positive("bandwidth_factor", bandwidth_factor);
  if (!(quality_tolerance > 0 && quality_tolerance < 1))
    throw Error("task map option quality_tolerance = " + num(quality_tolerance) +
                " is invalid; give a relative bound in (0, 1), for example 1e-3");
  if (threads < 0)
    throw Error("task map option threads = " + num(threads) + " is invalid; give >= 0");
}

std::vector<Pose> posesFromRows(const PoseRows& rows) {
  std::vector<Pose> out;
  out.reserve(static_cast<std::size_t>(rows.rows()));
  for (Eigen::Index i = 0; i < rows.rows(); ++i) {
    try {
      out.push_back(Pose::fromVector7(rows.row(i).transpose()));
    } catch (const Error& e) {
      throw Error("pose row " + std::to_string(i) + ": " + e.what());
    }
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Construction

TaskMap::TaskMap(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
TaskMap::TaskMap(TaskMap&&) noexcept = default;
TaskMap& TaskMap::operator=(TaskMap&&) noexcept = default;
TaskMap::~TaskMap() = default;

TaskMap TaskMap::fromData(TaskMapData data, const TaskMapOptions& options) {
  options.validate();
  auto impl = std::make_unique<Impl>();
  impl->data = std::move(data);
  impl->options = options;
  impl->build();
  return TaskMap(std::move(impl));
}

const TaskMapData& TaskMap::data() const {
  return impl_->data;
}
std::size_t TaskMap::size() const {
  return impl_->pos.size();
}
int TaskMap::numClusters() const {
  return static_cast<int>(impl_->clusters.size());
}
const TaskMapOptions& TaskMap::options() const {
  return impl_->options;
}
double TaskMap::rotationScale() const {
  return impl_->rho;
}
double TaskMap::cutoffRadius() const {
  return impl_->cutoff;
}

Pose TaskMap::pose(std::size_t i) const {
  if (i >= size())
    throw Error("grasp index " + std::to_string(i) + " out of range; the map has " +
                std::to_string(size()) + " grasps");
  Pose p;
  p.position = impl_->pos[i];
  p.orientation = impl_->qconj[i].conjugate();
  if (p.orientation.w() < 0) p.orientation.coeffs() *= -1.0;
  return p;
}

// ---------------------------------------------------------------------------------------------
// Queries

namespace {

// Hits (rows of a sample set) as grasp indices and distances.
std::vector<Neighbor> neighbours(const std::vector<std::size_t>& grasp,
                                 const std::vector<IndexHit>& hits) {
  std::vector<Neighbor> out;
  out.reserve(hits.size());
  for (const auto& h : hits) out.push_back(Neighbor{grasp[h.index], std::sqrt(h.distance2)});
  return out;
}

}  // namespace

Neighbor TaskMap::nearest(const Pose& x, std::optional<int> cluster) const {
  const auto& set = impl_->set(cluster);
  if (set.size() == 0) throw Error("nearest: the cluster has no samples");
  const PoseEmbedding e = embedPose(x, impl_->rho);
  const IndexHit h = set.index->nearest(e.data());
  return Neighbor{set.grasp[h.index], std::sqrt(h.distance2)};
}

std::vector<Neighbor> TaskMap::knn(const Pose& x, int k, std::optional<int> cluster) const {
  if (k < 1) throw Error("knn: k = " + std::to_string(k) + " is invalid; give k >= 1");
  const auto& set = impl_->set(cluster);
  const PoseEmbedding e = embedPose(x, impl_->rho);
  std::vector<IndexHit> hits;
  set.index->knn(e.data(), static_cast<std::size_t>(k), hits);
  return neighbours(set.grasp, hits);
}

std::vector<Neighbor> TaskMap::radius(const Pose& x, double r, std::optional<int> cluster) const {
  if (!(r >= 0) || !std::isfinite(r))
    throw Error("radius: r = " + num(r) + " is invalid; give a finite distance >= 0 (metres)");
  const auto& set = impl_->set(cluster);
  std::vector<IndexHit> hits;
  // The index's set and distances (NnIndex::radius), from the ball tree's candidates.
  impl_->ballSearch(set, impl_->query(x), r * r, hits);
  // Nearest first, ties by grasp index.
  std::sort(hits.begin(), hits.end(), [&](const IndexHit& a, const IndexHit& b) {
    return a.distance2 < b.distance2 ||
           (a.distance2 == b.distance2 && set.grasp[a.index] < set.grasp[b.index]);
  });
  return neighbours(set.grasp, hits);
}

ProximityResult TaskMap::proximity(const Pose& x, std::optional<int> cluster) const {
  const Neighbor n = nearest(x, cluster);
  return impl_->proximityTo(impl_->query(x), n);
}

QualityCriterion TaskMap::quality(const Pose& x, std::optional<int> cluster,
                                  std::optional<QualityMode> mode) const {
  const auto& set = impl_->set(cluster);
  const Impl::Query q = impl_->query(x);
  if (mode.value_or(impl_->options.quality_mode) == QualityMode::kExact) {
    return impl_->qualityExact(q, set);
  }
  detail::MixtureSum m;
  impl_->cutoffMixture(set, q, m);
  return impl_->truncated(m, q, set);
}

Evaluation TaskMap::evaluate(const Pose& x, std::optional<int> cluster) const {
  const auto& set = impl_->set(cluster);
  if (set.size() == 0) throw Error("evaluate: the cluster has no samples");
  const Impl::Query q = impl_->query(x);
  Evaluation out;
  IndexHit nearest;
  if (impl_->options.quality_mode == QualityMode::kTruncated) {
    // One search: the mixture over the samples within the cut-off (the same terms, in the same
    // order, as quality()'s) and the nearest sample, within the cut-off or, if none is, from
    // the index.
    detail::MixtureSum m;
    nearest = impl_->cutoffMixture(set, q, m);
    out.quality = impl_->truncated(m, q, set);
  } else {
    out.quality = impl_->qualityExact(q, set);
    nearest = set.index->nearest(q.e.data());
  }
  const Neighbor n{set.grasp[nearest.index], std::sqrt(nearest.distance2)};
  out.proximity = impl_->proximityTo(q, n);
  return out;
}

// ---------------------------------------------------------------------------------------------
// Impl

const TaskMap::Impl::SampleSet& TaskMap::Impl::set(std::optional<int> cluster) const {
  if (!cluster) return all;
  if (clusters.empty())
    throw Error("cluster " + std::to_string(*cluster) +
                " requested but the map has no clustering; cluster the map first");
  if (*cluster < 0 || *cluster >= static_cast<int>(clusters.size()))
    throw Error("cluster " + std::to_string(*cluster) +
                " does not exist; the map has clusters 0.." + std::to_string(clusters.size() - 1));
  return clusters[static_cast<std::size_t>(*cluster)];
}

TaskMap::Impl::Query TaskMap::Impl::query(const Pose& x) const {
  Query out;
  out.p = x.position;
  out.q = x.orientation.normalized();
  out.r = out.q.toRotationMatrix();
  out.e = embedPose(x, rho);
  return out;
}

ProximityResult TaskMap::Impl::proximityTo(const Query& x, const Neighbor& n) const {
  ProximityResult out;
  out.nearest = n;
  const Eigen::Vector3d dp = x.p - pos[n.index];
  const Eigen::Vector3d w = detail::relativeLog(qconj[n.index], x.q);
  out.difference << dp, w;
  out.value = wp * dp.squaredNorm() + wr * w.squaredNorm();
  out.gradient.head<3>() = 2.0 * wp * dp;
  out.gradient.tail<3>() = 2.0 * wr * (x.r * w);  // R J_r^{-1}(w)^T 2 w_r w = 2 w_r R w
  return out;
}

// The mixture g_q = -scale sum c_i, scale = 1 / (Z W), c_i = w_i exp(-d_i / 2) with
// d_i = |p - p_i|^2 / sp^2 + (3 - tr(R_i^T R)) / sr^2 (||R - R_i||_F^2 = 6 - 2 tr(R_i^T R)).
// Under p <- p + dp, R <- exp(w^) R:  dc_i = -c_i/2 dd_i,
//   dd_i/dp = 2 (p - p_i) / sp^2,
//   dd_i/dw = -(1/sr^2) d tr(R_i^T exp(w^) R)/dw = -(1/sr^2) d tr(w^ R R_i^T)/dw
//           = v(R R_i^T) / sr^2,   v(A) = (A21 - A12, A02 - A20, A10 - A01),
// using tr(w^ A) = -w . v(A). Summed (v is linear), with the running sums of finish():
//   dg_q/dp = (scale / sp^2) sum c_i (p - p_i)       = -(scale / sp^2) moment_p,
//   dg_q/dw = (scale / (2 sr^2)) v(R sum c_i R_i^T)  = (scale / (2 sr^2)) v(R S^T),
// S = sum c_i (R_i - R) = (sqrt2 / rho) moment_R (v(R R^T) = v(I) = 0 drops the c_i R part;
// sums of differences avoid cancellation).
QualityCriterion TaskMap::Impl::finish(const detail::MixtureSum& m, const Query& x,
                                       const SampleSet& s) const {
  QualityCriterion out;
  if (s.total_weight <= 0) return out;
  const double scale = inv_z / s.total_weight;
  out.value = -m.sum * scale;
  out.gradient.head<3>() = (-scale * inv_sp2) * Eigen::Map<const Eigen::Vector3d>(m.moment);
  out.gradient.tail<3>() = (0.5 * scale / (sr * sr)) *
                           detail::skewOfProduct(x.r, detail::rotationBlock(m.moment + 3, rho));
  out.terms = m.terms;
  return out;
}

QualityCriterion TaskMap::Impl::qualityExact(const Query& x, const SampleSet& s) const {
  detail::MixtureSum m;
  for (std::size_t k = 0; k < s.size(); ++k)
    detail::addMixtureTerm(s.row(k), x.e.data(), inv_sp2, inv_se2, m);
  return finish(m, x, s);
}

QualityCriterion TaskMap::Impl::truncated(const detail::MixtureSum& m, const Query& x,
                                          const SampleSet& s) const {
  QualityCriterion out = finish(m, x, s);
  if (s.total_weight <= 0) return out;
  // Omitted samples have embedding distance D > r_c, so d >= D^2 / s^2 > t_c^2
  // (task_map_build.cpp).
  const double omitted = std::max(0.0, s.total_weight - m.included_weight) / s.total_weight;
  out.value_bound = value_bound_factor * omitted;
  out.gradient_bound = gradient_bound_factor * omitted;
  return out;
}

}  // namespace taskmap
