// Clustering grasps: embedding, dendrogram, default cut, outliers, per-cluster summaries.

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "linkage_internal.hpp"
#include "taskmap/clustering/clustering.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {

void ClusteringOptions::validate() const {
  if (!(rotation_scale > 0.0) || !std::isfinite(rotation_scale)) {
    throw Error("clustering option rotation_scale must be a positive length per radian, got " +
                std::to_string(rotation_scale));
  }
  if (threshold && num_clusters) {
    throw Error("clustering options threshold and num_clusters exclude each other: set one");
  }
  if (threshold && (!std::isfinite(*threshold) || *threshold < 0.0)) {
    throw Error("clustering option threshold must be a finite distance >= 0 (metres), got " +
                std::to_string(*threshold));
  }
  if (num_clusters && *num_clusters < 1) {
    throw Error("clustering option num_clusters must be >= 1, got " +
                std::to_string(*num_clusters));
  }
  if (!(min_size_fraction >= 0.0 && min_size_fraction <= 1.0)) {
    throw Error("clustering option min_size_fraction must be in [0, 1], got " +
                std::to_string(min_size_fraction));
  }
  if (!(outlier_budget >= 0.0 && outlier_budget <= 1.0)) {
    throw Error("clustering option outlier_budget must be a share in [0, 1], got " +
                std::to_string(outlier_budget));
  }
  if (min_size < 0) {
    throw Error("clustering option min_size must be >= 0 (0: use min_size_fraction), got " +
                std::to_string(min_size));
  }
}

int resolveMinSize(const ClusteringOptions& options, int n) {
  if (options.min_size > 0) return options.min_size;
  // The small epsilon keeps 0.03 * 1000 at 30, not 31 from rounding.
  const double m = std::ceil(options.min_size_fraction * n - 1e-9);
  const int wanted = std::max(kDefaultMinClusterSize, static_cast<int>(m));
  return std::max(1, std::min(wanted, n));
}

double midGapCut(const LinkageMatrix& linkage, double threshold) {
  detail::validateLinkage(linkage, "midGapCut");
  if (!std::isfinite(threshold) || threshold < 0.0) {
    throw Error("midGapCut: the cut distance must be finite and >= 0 (metres), got " +
                std::to_string(threshold));
  }
  const Eigen::Index rows = linkage.rows();
  if (rows == 0) return threshold;
  // Merge distances are non-decreasing: the first row above the threshold bounds the gap.
  Eigen::Index above = 0;
  while (above < rows && linkage(above, 2) <= threshold) ++above;
  const double top = linkage(rows - 1, 2);
  if (above == rows) return top > 0.0 ? 1.5 * top : threshold;  // one cluster: clear of the top
  const double lo = above > 0 ? linkage(above - 1, 2) : 0.0;
  return 0.5 * (lo + linkage(above, 2));
}

double defaultThreshold(const LinkageMatrix& linkage) {
  const double n = static_cast<double>(linkage.rows() + 1);
  return defaultThreshold(linkage, std::max(2, static_cast<int>(std::ceil(0.02 * n - 1e-9))));
}

namespace {

/// The gap rule's cut, and the distance of the significant merge it cuts (0: none found).
struct GapCut {
  double threshold = 0.0;
  double split = 0.0;
  double smaller = 0.0;  ///< points in the smaller side of that merge
};

GapCut gapCut(const LinkageMatrix& linkage, int min_size) {
  const Eigen::Index rows = linkage.rows();
  if (rows == 0) return {};
  const Eigen::Index n = rows + 1;
  const double m = std::max(1, min_size);
  auto size_of = [&](Eigen::Index id) { return id < n ? 1.0 : linkage(id - n, 3); };
  // core[k]: core distance of the cluster formed by row k (see the header).
  std::vector<double> core(static_cast<std::size_t>(rows), 0.0);
  auto core_of = [&](Eigen::Index id) { return id < n ? 0.0 : core[id - n]; };
  double best_ratio = 0.0;
  double best_threshold = linkage(rows - 1, 2);
  double best_split = 0.0, best_smaller = 0.0;
  for (Eigen::Index k = 0; k < rows; ++k) {
    const auto a = static_cast<Eigen::Index>(linkage(k, 0));
    const auto b = static_cast<Eigen::Index>(linkage(k, 1));
    const bool big_a = size_of(a) >= m;
    const bool big_b = size_of(b) >= m;
    const double d = linkage(k, 2);
    if (big_a == big_b) {
      core[k] = d;
    } else {
      core[k] = core_of(big_a ? a : b);
    }
    if (!(big_a && big_b) || d <= 0.0) continue;
    const double inner = std::max(core_of(a), core_of(b));
    const double ratio = inner > 0.0 ? d / inner : std::numeric_limits<double>::infinity();
    if (ratio >= kMinGapRatio && ratio >= best_ratio) {
      best_ratio = ratio;
      best_threshold = inner > 0.0 ? std::sqrt(inner * d) : 0.5 * d;
      best_split = d;
      best_smaller = std::min(size_of(a), size_of(b));
    }
  }
  if (best_ratio > 0.0) return {best_threshold, best_split, best_smaller};
  // One cluster: cut off stragglers that attach far above the core of the whole tree.
  const double top = linkage(rows - 1, 2);
  const double root_core = core[rows - 1];
  if (root_core > 0.0 && top >= kMinGapRatio * root_core)
    return {std::sqrt(root_core * top), 0.0, 0.0};
  return {top, 0.0, 0.0};
}

/// Number of clusters of at least min_size points when cutting at `threshold`.
int clustersAtLeast(const LinkageMatrix& linkage, double threshold, int min_size) {
  const std::vector<int> labels = cutAtDistance(linkage, threshold);
  std::vector<int> sizes;
  for (int l : labels) {
    if (l >= static_cast<int>(sizes.size())) sizes.resize(static_cast<std::size_t>(l) + 1, 0);
    ++sizes[static_cast<std::size_t>(l)];
  }
  return static_cast<int>(
      std::count_if(sizes.begin(), sizes.end(), [&](int c) { return c >= std::max(1, min_size); }));
}

}  // namespace

double defaultThreshold(const LinkageMatrix& linkage, int min_size) {
  detail::validateLinkage(linkage, "defaultThreshold");
  return gapCut(linkage, min_size).threshold;
}

double coverageThreshold(const LinkageMatrix& linkage, int min_size, double outlier_budget) {
  detail::validateLinkage(linkage, "coverageThreshold");
  if (!(outlier_budget >= 0.0 && outlier_budget <= 1.0)) {
    throw Error("coverageThreshold: outlier_budget must be a share in [0, 1], got " +
                std::to_string(outlier_budget));
  }
  const Eigen::Index rows = linkage.rows();
  if (rows == 0) return 0.0;
  const Eigen::Index n = rows + 1;
  const double m = std::max(1, min_size);
  // Points needed in clusters of >= m; the small epsilon keeps 0.9 * 1000 at 900.
  const double needed = std::ceil((1.0 - outlier_budget) * static_cast<double>(n) - 1e-9);
  double covered = m <= 1.0 ? static_cast<double>(n) : 0.0;
  if (covered >= needed) return 0.0;
  auto size_of = [&](Eigen::Index id) { return id < n ? 1.0 : linkage(id - n, 3); };
  for (Eigen::Index k = 0; k < rows; ++k) {
    const double a = size_of(static_cast<Eigen::Index>(linkage(k, 0)));
    const double b = size_of(static_cast<Eigen::Index>(linkage(k, 1)));
    if (a + b >= m) covered += (a < m ? a : 0.0) + (b < m ? b : 0.0);
    if (covered >= needed) return linkage(k, 2);
  }
  assert(false && "the root cluster covers every point");
  return linkage(rows - 1, 2);
}

double defaultCut(const LinkageMatrix& linkage, int min_size, double outlier_budget) {
  detail::validateLinkage(linkage, "defaultCut");
  const GapCut gap = gapCut(linkage, min_size);
  const double coverage = coverageThreshold(linkage, min_size, outlier_budget);
  if (gap.split > 0.0) {
    const double n = static_cast<double>(linkage.rows() + 1);
    if (coverage < gap.split || gap.smaller <= outlier_budget * n)
      return midGapCut(linkage, std::max(gap.threshold, coverage));
    // A clear split of two families each larger than the outlier budget: the coverage floor
    // may absorb fragments, never undo the split itself: cut at the highest merge below it.
    double below = gap.threshold;
    for (Eigen::Index k = 0; k < linkage.rows(); ++k)
      if (linkage(k, 2) < gap.split) below = std::max(below, linkage(k, 2));
    return midGapCut(linkage, below);
  }
  // No clear gap: a continuum of grasps. One cluster would summarise it by a mean pose that
  // no grasp has (around a cylinder, of a mug's handle and body); cut at the coverage floor
  // instead when that leaves at least two clusters of min_size.
  if (linkage.rows() > 0 && clustersAtLeast(linkage, coverage, min_size) >= 2)
    return midGapCut(linkage, coverage);
  return midGapCut(linkage, std::max(gap.threshold, coverage));
}

namespace {

void checkInputs(const std::vector<Pose>& poses, const std::vector<double>& epsilon,
                 const char* what) {
  if (poses.size() != epsilon.size()) {
    throw Error(std::string(what) + ": " + std::to_string(poses.size()) + " poses but " +
                std::to_string(epsilon.size()) + " epsilon values; give one per grasp");
  }
  if (poses.size() > static_cast<std::size_t>(std::numeric_limits<int>::max() / 2)) {
    throw Error(std::string(what) + ": too many grasps");
  }
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (!std::isfinite(epsilon[i])) {
      throw Error(std::string(what) + ": epsilon of grasp " + std::to_string(i) + " is not finite");
    }
    if (!poses[i].position.allFinite() || !poses[i].orientation.coeffs().allFinite() ||
        poses[i].orientation.norm() < 1e-9) {
      throw Error(std::string(what) + ": pose of grasp " + std::to_string(i) +
                  " is not finite or has a zero quaternion");
    }
  }
}

ClusterSummary summarise(const std::vector<Pose>& poses, const std::vector<double>& epsilon,
                         const std::vector<int>& members) {
  assert(!members.empty());
  ClusterSummary s;
  s.size = static_cast<int>(members.size());
  s.bounds_min = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  s.bounds_max = -s.bounds_min;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double eps_sum = 0.0;
  std::vector<Eigen::Quaterniond> qs;
  qs.reserve(members.size());
  for (int i : members) {
    const Pose& p = poses[i];
    sum += p.position;
    s.bounds_min = s.bounds_min.cwiseMin(p.position);
    s.bounds_max = s.bounds_max.cwiseMax(p.position);
    qs.push_back(p.orientation.normalized());
    eps_sum += epsilon[i];
    if (s.representative < 0 || epsilon[i] > epsilon[s.representative]) s.representative = i;
  }
  s.mean_pose.position = sum / static_cast<double>(members.size());
  s.mean_pose.orientation = meanOrientation(qs);
  s.mean_epsilon = eps_sum / static_cast<double>(members.size());
  s.best_epsilon = epsilon[s.representative];
  return s;
}

}  // namespace

ClusteringResult clusterFromLinkage(const std::vector<Pose>& poses,
                                    const std::vector<double>& epsilon,
                                    const LinkageMatrix& linkage,
                                    const ClusteringOptions& options) {
  options.validate();
  checkInputs(poses, epsilon, "clusterFromLinkage");
  const int n = static_cast<int>(poses.size());
  const Eigen::Index expected_rows = n > 0 ? n - 1 : 0;
  if (linkage.rows() != expected_rows) {
    throw Error("clusterFromLinkage: the dendrogram has " + std::to_string(linkage.rows()) +
                " rows but " + std::to_string(n) + " grasps need " + std::to_string(expected_rows) +
                "; recompute it with computeLinkage");
  }
  detail::validateLinkage(linkage, "clusterFromLinkage");
  ClusteringResult result;
  result.linkage = linkage;
  result.method = options.method;
  result.rotation_scale = options.rotation_scale;
  result.min_size = resolveMinSize(options, n);
  if (n == 0) {
    if (options.num_clusters) {
      throw Error("number of clusters (--clusters) " + std::to_string(*options.num_clusters) +
                  " exceeds the number of grasps (0)");
    }
    result.threshold = options.threshold.value_or(0.0);
    return result;
  }

  std::vector<int> raw;
  if (options.num_clusters) {
    const int k = *options.num_clusters;
    if (k > n) {
      throw Error("number of clusters (--clusters) " + std::to_string(k) +
                  " exceeds the number of grasps (" + std::to_string(n) + ")");
    }
    raw = cutToCount(linkage, k);
    // The distance of the last merge applied (0 when none is).
    result.threshold = n - k > 0 ? linkage(n - k - 1, 2) : 0.0;
  } else {
    result.threshold = options.threshold
                           ? *options.threshold
                           : defaultCut(linkage, result.min_size, options.outlier_budget);
    raw = cutAtDistance(linkage, result.threshold);
  }

  // Members per raw label; raw labels appear in order of first member, so a stable sort by
  // size keeps "ties: lowest grasp index".
  const int raw_count = raw.empty() ? 0 : *std::max_element(raw.begin(), raw.end()) + 1;
  std::vector<std::vector<int>> members(static_cast<std::size_t>(raw_count));
  for (int i = 0; i < n; ++i) members[raw[i]].push_back(i);
  std::vector<int> order;
  for (int c = 0; c < raw_count; ++c) {
    if (static_cast<int>(members[c].size()) >= result.min_size) order.push_back(c);
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return members[a].size() > members[b].size(); });
  result.labels.assign(static_cast<std::size_t>(n), -1);
  result.clusters.reserve(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    for (int i : members[order[k]]) result.labels[i] = static_cast<int>(k);
    result.clusters.push_back(summarise(poses, epsilon, members[order[k]]));
  }
  return result;
}

Linkage resolveMethod(const ClusteringOptions& options, int n) {
  if (options.method != Linkage::kSingle && options.fallback_to_single &&
      n > kMaxPairwiseLinkagePoints) {
    return Linkage::kSingle;
  }
  return options.method;
}

ClusteringResult clusterGrasps(const std::vector<Pose>& poses, const std::vector<double>& epsilon,
                               const ClusteringOptions& options) {
  options.validate();
  checkInputs(poses, epsilon, "clusterGrasps");
  const auto n = static_cast<Eigen::Index>(poses.size());
  LinkageMatrix linkage(n > 0 ? n - 1 : 0, 4);
  const Linkage method = resolveMethod(options, static_cast<int>(n));
  if (n >= 2) {
    PointMatrix points(n, kEmbeddingDim);
    for (Eigen::Index i = 0; i < n; ++i) {
      Pose p = poses[static_cast<std::size_t>(i)];
      p.orientation.normalize();
      points.row(i) = embedPose(p, options.rotation_scale).transpose();
    }
    linkage = computeLinkage(points, method);
  }
  ClusteringOptions used = options;
  used.method = method;
  return clusterFromLinkage(poses, epsilon, linkage, used);
}

}  // namespace taskmap
