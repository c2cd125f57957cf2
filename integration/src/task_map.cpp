#include "taskmap/integration/task_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "kernels.hpp"
#include "nn_index.hpp"
#include "task_map_impl.hpp"
#include "taskmap/integration/criteria.hpp"
#include "taskmap/meshes/error.hpp"

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

Neighbor TaskMap::nearest(const Pose& x, std::optional<int> cluster) const {
  const auto& set = impl_->set(cluster);
  if (set.size() == 0) throw Error("nearest: the cluster has no samples");
  const PoseEmbedding e = embedPose(x, impl_->rho);
  thread_local std::vector<IndexHit> hits;
  set.index->knn(e.data(), 1, hits);
  return Neighbor{set.global(hits[0].index), std::sqrt(hits[0].distance2)};
}

std::vector<Neighbor> TaskMap::knn(const Pose& x, int k, std::optional<int> cluster) const {
  if (k < 1) throw Error("knn: k = " + std::to_string(k) + " is invalid; give k >= 1");
  const auto& set = impl_->set(cluster);
  const PoseEmbedding e = embedPose(x, impl_->rho);
  std::vector<IndexHit> hits;
  set.index->knn(e.data(), static_cast<std::size_t>(k), hits);
  std::vector<Neighbor> out;
  out.reserve(hits.size());
  for (const auto& h : hits) out.push_back(Neighbor{set.global(h.index), std::sqrt(h.distance2)});
  return out;
}

std::vector<Neighbor> TaskMap::radius(const Pose& x, double r, std::optional<int> cluster) const {
  if (!(r >= 0) || !std::isfinite(r))
    throw Error("radius: r = " + num(r) + " is invalid; give a finite distance >= 0 (metres)");
  const auto& set = impl_->set(cluster);
  const PoseEmbedding e = embedPose(x, impl_->rho);
  std::vector<IndexHit> hits;
  set.index->radius(e.data(), r * r, hits);
  std::vector<Neighbor> out;
  out.reserve(hits.size());
  for (const auto& h : hits) out.push_back(Neighbor{set.global(h.index), std::sqrt(h.distance2)});
  return out;
}

ProximityResult TaskMap::proximity(const Pose& x, std::optional<int> cluster) const {
  const Neighbor n = nearest(x, cluster);
  const Eigen::Quaterniond q = x.orientation.normalized();
  return impl_->proximityTo(x.position, q, q.toRotationMatrix(), n);
}

QualityResult TaskMap::quality(const Pose& x, std::optional<int> cluster,
                               std::optional<QualityMode> mode) const {
  const auto& set = impl_->set(cluster);
  const Eigen::Quaterniond q = x.orientation.normalized();
  const Eigen::Matrix3d r = q.toRotationMatrix();
  if (mode.value_or(impl_->options.quality_mode) == QualityMode::kExact) {
    return impl_->qualityExact(x.position, q, r, set);
  }
  const PoseEmbedding e = embedPose(x, impl_->rho);
  thread_local std::vector<IndexHit> hits;
  set.index->radius(e.data(), impl_->cutoff2, hits);
  return impl_->qualityOver(x.position, q, r, set, hits);
}

Evaluation TaskMap::evaluate(const Pose& x, std::optional<int> cluster) const {
  const auto& set = impl_->set(cluster);
  if (set.size() == 0) throw Error("evaluate: the cluster has no samples");
  const Eigen::Quaterniond q = x.orientation.normalized();
  const Eigen::Matrix3d r = q.toRotationMatrix();
  const PoseEmbedding e = embedPose(x, impl_->rho);
  thread_local std::vector<IndexHit> hits;
  Evaluation out;
  if (impl_->options.quality_mode == QualityMode::kTruncated) {
    set.index->radius(e.data(), impl_->cutoff2, hits);
    out.quality = impl_->qualityOver(x.position, q, r, set, hits);
    // The radius search is exact: its closest hit is the nearest sample. Nothing within the
    // cut-off: one nearest-neighbour search.
    if (hits.empty()) set.index->knn(e.data(), 1, hits);
  } else {
    out.quality = impl_->qualityExact(x.position, q, r, set);
    set.index->knn(e.data(), 1, hits);
  }
  const Neighbor n{set.global(hits[0].index), std::sqrt(hits[0].distance2)};
  out.proximity = impl_->proximityTo(x.position, q, r, n);
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

ProximityResult TaskMap::Impl::proximityTo(const Eigen::Vector3d& p, const Eigen::Quaterniond& q,
                                           const Eigen::Matrix3d& r, const Neighbor& n) const {
  ProximityResult out;
  out.nearest = n;
  const Eigen::Vector3d dp = p - pos[n.index];
  const Eigen::Vector3d w = detail::relativeLog(qconj[n.index], q);
  out.difference << dp, w;
  out.value = wp * dp.squaredNorm() + wr * w.squaredNorm();
  out.gradient.head<3>() = 2.0 * wp * dp;
  out.gradient.tail<3>() = 2.0 * wr * (r * w);  // R J_r^{-1}(w)^T 2 w_r w = 2 w_r R w
  return out;
}

void TaskMap::Impl::addTerm(std::size_t i, const Eigen::Vector3d& p, const Eigen::Quaterniond& q,
                            MixtureSum& m) const {
  const double wi = weight[i];
  if (wi <= 0) return;
  const Eigen::Vector3d dp = p - pos[i];
  const Eigen::Vector3d w = detail::relativeLog(qconj[i], q);
  const double c = wi * std::exp(-0.5 * (dp.squaredNorm() * inv_sp2 + w.squaredNorm() * inv_sr2));
  m.sum += c;
  m.gp += c * dp;
  m.gw += c * w;
  m.included_weight += wi;
  ++m.terms;
}

QualityResult TaskMap::Impl::finish(const MixtureSum& m, const Eigen::Matrix3d& r,
                                    const SampleSet& s) const {
  QualityResult out;
  if (s.total_weight <= 0) return out;
  const double scale = inv_z / s.total_weight;
  out.value = -m.sum * scale;
  out.gradient.head<3>() = (scale * inv_sp2) * m.gp;
  out.gradient.tail<3>() = (scale * inv_sr2) * (r * m.gw);
  out.terms = m.terms;
  return out;
}

QualityResult TaskMap::Impl::qualityExact(const Eigen::Vector3d& p, const Eigen::Quaterniond& q,
                                          const Eigen::Matrix3d& r, const SampleSet& s) const {
  MixtureSum m;
  for (std::size_t k = 0; k < s.size(); ++k) addTerm(s.global(k), p, q, m);
  return finish(m, r, s);
}

QualityResult TaskMap::Impl::qualityOver(const Eigen::Vector3d& p, const Eigen::Quaterniond& q,
                                         const Eigen::Matrix3d& r, const SampleSet& s,
                                         const std::vector<IndexHit>& hits) const {
  MixtureSum m;
  for (const auto& h : hits) addTerm(s.global(h.index), p, q, m);
  QualityResult out = finish(m, r, s);
  if (s.total_weight <= 0) return out;
  // Omitted samples have embedding distance D > r_c, so Mahalanobis d >= D^2/s^2 > t_c^2.
  const double omitted = std::max(0.0, s.total_weight - m.included_weight) / s.total_weight;
  out.value_bound = value_bound_factor * omitted;
  out.gradient_bound = gradient_bound_factor * omitted;
  return out;
}

}  // namespace taskmap
