#pragma once
/// @file clustering.hpp
/// Hierarchical clustering of grasp poses into qualitatively different solutions
/// (paper 1.6.1), in the pose embedding of shared/TASKMAPS.md §4.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "taskmap/meshes/pose.hpp"

namespace taskmap {

/// Linkage criterion.
enum class Linkage {
  kSingle,    ///< minimum spanning tree (any size)
  kAverage,   ///< UPGMA, nearest-neighbour chain (up to 2e4 points)
  kComplete,  ///< farthest point, nearest-neighbour chain (up to 2e4 points)
};

/// "single", "average", "complete".
const char* toString(Linkage method);
/// Parses a linkage name; throws Error on an unknown name.
Linkage linkageFromString(const std::string& name);

/// Dendrogram in scipy's format: row k merges clusters i and j (ids < n are points, n + k'
/// is the cluster of row k') at distance d into a cluster of the given size.
/// Columns: i, j, distance, size. (n - 1) rows, distances non-decreasing.
using LinkageMatrix = Eigen::Matrix<double, Eigen::Dynamic, 4>;

/// Row-major point set, one point per row (for example embedded poses, N x 12).
using PointMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// Dendrogram of points under Euclidean distance. Identical to
/// scipy.cluster.hierarchy.linkage(points, method) up to ties. Throws Error for fewer than
/// 2 points, non-finite values, or average/complete beyond 20000 points.
LinkageMatrix computeLinkage(const PointMatrix& points, Linkage method);

/// Flat cluster labels (0..K-1, in order of first appearance) from cutting the dendrogram at
/// distance threshold: points joined by merges with distance <= threshold share a label.
std::vector<int> cutAtDistance(const LinkageMatrix& linkage, double threshold);

/// Flat labels for exactly k clusters (1 <= k <= n), labelled as in cutAtDistance.
std::vector<int> cutToCount(const LinkageMatrix& linkage, int k);

/// Default threshold: at the largest relative gap between consecutive merge distances
/// among the top merges of the dendrogram (documented in the implementation).
double defaultThreshold(const LinkageMatrix& linkage);

/// Options for clustering grasps.
struct ClusteringOptions {
  Linkage method = Linkage::kSingle;
  double rotation_scale = kDefaultRotationScale;  ///< rho, metres per radian, > 0
  std::optional<double> threshold;   ///< cut distance (metres); neither set: defaultThreshold
  std::optional<int> num_clusters;   ///< cut to this many clusters (exclusive with threshold)
  double min_size_fraction = 0.02;   ///< clusters smaller than this share of grasps are outliers
  int min_size = 0;                  ///< absolute minimum size; 0 uses min_size_fraction
  /// Throws Error naming the option when a value is out of range or both cuts are set.
  void validate() const;
};

/// Summary of one cluster.
struct ClusterSummary {
  int size = 0;                 ///< number of grasps
  int representative = -1;      ///< grasp index with the best epsilon
  Pose mean_pose;               ///< mean position, chordal mean orientation
  double mean_epsilon = 0.0;
  double best_epsilon = 0.0;
  Eigen::Vector3d bounds_min = Eigen::Vector3d::Zero();  ///< position bounds, metres
  Eigen::Vector3d bounds_max = Eigen::Vector3d::Zero();
};

/// Result of clustering a set of grasps.
struct ClusteringResult {
  std::vector<int> labels;               ///< per grasp: cluster id 0..K-1, or -1 for outliers
  std::vector<ClusterSummary> clusters;  ///< K clusters, largest first (ties: lowest grasp index)
  LinkageMatrix linkage;                 ///< full dendrogram over the embedded poses
  Linkage method = Linkage::kSingle;
  double rotation_scale = kDefaultRotationScale;
  double threshold = 0.0;                ///< the cut distance used
  int min_size = 0;                      ///< the absolute minimum size used
};

/// Clusters grasps by pose. Deterministic. @param epsilon per-grasp quality (same length).
ClusteringResult clusterGrasps(const std::vector<Pose>& poses, const std::vector<double>& epsilon,
                               const ClusteringOptions& options = {});

/// Relabels and summarises an existing dendrogram (for re-cutting a stored map).
ClusteringResult clusterFromLinkage(const std::vector<Pose>& poses,
                                    const std::vector<double>& epsilon,
                                    const LinkageMatrix& linkage,
                                    const ClusteringOptions& options);

}  // namespace taskmap
