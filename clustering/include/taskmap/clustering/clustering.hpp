#pragma once
/// @file clustering.hpp
/// Hierarchical clustering of grasp poses into qualitatively different solutions
/// (paper 1.6.1), in the pose embedding of docs/METHOD.md §4.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "taskmap/core/pose.hpp"

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

/// Gap rule alone (no coverage floor): at the largest relative gap between consecutive merge
/// distances among the top merges of the dendrogram (documented in the implementation). Same as
/// defaultThreshold(linkage, max(2, ceil(0.02 n))).
double defaultThreshold(const LinkageMatrix& linkage);

/// Smallest relative gap that defaultThreshold accepts as a split; below it the data is one
/// cluster.
constexpr double kMinGapRatio = 2.0;

/// Gap-rule threshold for clusters of at least min_size points (metres, in the embedding).
/// A merge is significant when both merged clusters have >= min_size points. Its gap ratio
/// is its distance over the core distance of its two children, where the core distance of a
/// cluster skips outlier attachments (merges with a child below min_size) down to the first
/// merge of two significant clusters or of two small ones. The significant merge with the
/// largest ratio (ties: the higher merge) is cut: the threshold is the geometric mean of its
/// distance and its children's larger core distance (half its distance when that is 0). No
/// significant merge with ratio >= kMinGapRatio: one cluster; if the top merge is at least
/// kMinGapRatio times the core distance of the whole dendrogram, the cut is at their
/// geometric mean (stragglers above it become outliers), else at the top merge distance.
/// 0 for fewer than 2 points.
double defaultThreshold(const LinkageMatrix& linkage, int min_size);

/// Lowest merge distance (metres) at which at least (1 - outlier_budget) of the n points lie
/// in clusters of at least min_size points, i.e. the smallest cut that leaves at most
/// outlier_budget * n points as outliers. Coverage only grows with the cut distance, so every
/// higher cut keeps the bound. 0 when no merge is needed (or for fewer than 2 points).
/// @param outlier_budget share in [0, 1]; 1 gives 0.
double coverageThreshold(const LinkageMatrix& linkage, int min_size, double outlier_budget);

/// Default cut of clusterGrasps. With a significant gap (defaultThreshold finds a merge of two
/// clusters of min_size with ratio >= kMinGapRatio): max(gap cut, coverageThreshold), except
/// that when both sides of the gap's merge are families larger than the outlier budget
/// (outlier_budget * n points), a coverage floor at or above the merge distance would undo the
/// split: then the cut is the highest merge below that distance (the families stay apart, as
/// few outliers as that allows). Without one (a continuum of
/// grasps): the coverage floor when it leaves at least two clusters of min_size, else the gap
/// rule's one-cluster cut. The chosen distance is then moved to the middle of its merge gap
/// (midGapCut), so the stored threshold never sits on a merge height. No prior on the number
/// of clusters: the gap rule finds the natural
/// split; the coverage floor stops it from cutting so low that many grasps fall into fragments
/// below min_size. One cluster over a continuum of orientations would be summarised by a mean
/// pose that no grasp has: measured on real maps (the YCB mug with the humanoid hand, ACRONYM's
/// mug), the handle grasps then fall into clusters of their own, mixed with body grasps only
/// where orientations overlap. Measured on the paper's basket map (1000 grasps, Barrett hand,
/// seed 1, average linkage, min size 30; the mixed sampler's): 12 clusters and 88 outliers, each
/// cluster on one bar of the handle or the rim; with palm_enclose, the default since 2026-11-27,
/// 18 clusters and 87 outliers (docs/METHOD.md, "Default cut"). The bars split into several
/// clusters each because rho weighs orientation: grasps on one bar with different approach
/// directions are further apart than the bars' spacing.
double defaultCut(const LinkageMatrix& linkage, int min_size, double outlier_budget);

/// Largest number of points average and complete linkage accept (memory O(n^2)).
constexpr int kMaxPairwiseLinkagePoints = 20000;

/// Default outlier budget of ClusteringOptions: share of grasps the default cut may leave as
/// outliers.
constexpr double kDefaultOutlierBudget = 0.1;

/// Default share of the grasps below which a cluster is an outlier group (ClusteringOptions).
constexpr double kDefaultMinSizeFraction = 0.03;

/// Smallest cluster the default options keep, in grasps: a cluster of two is not a family of
/// grasps a person would name (issue 30 measured 18-25 clusters per 100 grasps without it).
constexpr int kDefaultMinClusterSize = 3;

/// Moves a cut distance into the middle of the gap between the merge heights around it: the
/// result is halfway between the highest merge distance <= threshold and the lowest one above
/// it (threshold itself when no merge lies above; the top merge distance plus half of it when
/// every merge is below and the threshold equals the top). Cutting at the result gives the same
/// partition as cutting at threshold, but a dendrogram recomputed by another implementation,
/// whose merge heights differ by rounding (1e-16 relative), cuts the same way. Throws Error for
/// a negative or non-finite threshold.
double midGapCut(const LinkageMatrix& linkage, double threshold);

/// Options for clustering grasps.
/// Default: average linkage (single beyond kMaxPairwiseLinkagePoints grasps, see
/// fallback_to_single), cut at defaultCut with min size max(3 grasps, 3 % of the grasps) and
/// outlier budget 10 %, moved to the middle of its merge gap (midGapCut). Average rather than
/// single linkage because single linkage chains the three bars of the paper's basket handle through
/// the grasps at the handle's corners (measured on the basket map: one cluster holding all 1000
/// grasps at the gap-rule cut).
struct ClusteringOptions {
  Linkage method = Linkage::kAverage;
  /// Average/complete with more than kMaxPairwiseLinkagePoints grasps: true uses single
  /// linkage instead (ClusteringResult::method tells which was used), false throws Error.
  bool fallback_to_single = true;
  /// Share of grasps the default cut may leave as outliers, in [0, 1] (see defaultCut).
  double outlier_budget = kDefaultOutlierBudget;
  double rotation_scale = kDefaultRotationScale;  ///< rho, metres per radian, > 0
  std::optional<double> threshold;  ///< cut distance (metres); neither set: defaultCut
  std::optional<int> num_clusters;  ///< cut to this many clusters (exclusive with threshold)
  /// Clusters smaller than this share of grasps are outliers (with min_size 0).
  double min_size_fraction = kDefaultMinSizeFraction;
  /// Absolute minimum size; 0 uses max(kDefaultMinClusterSize, min_size_fraction share).
  int min_size = 0;
  /// Throws Error naming the option when a value is out of range or both cuts are set.
  void validate() const;
};

/// Absolute minimum cluster size the options give for n grasps: options.min_size if > 0,
/// else max(kDefaultMinClusterSize, ceil(min_size_fraction * n)), at most n (a map of fewer than
/// kDefaultMinClusterSize grasps is one cluster, not all outliers), at least 1.
int resolveMinSize(const ClusteringOptions& options, int n);

/// Linkage clusterGrasps uses for n grasps: options.method, or single when options.method is
/// average/complete, n > kMaxPairwiseLinkagePoints and options.fallback_to_single.
Linkage resolveMethod(const ClusteringOptions& options, int n);

/// Summary of one cluster.
struct ClusterSummary {
  int size = 0;             ///< number of grasps
  int representative = -1;  ///< grasp index with the best epsilon
  Pose mean_pose;           ///< mean position, chordal mean orientation
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
  double threshold = 0.0;  ///< the cut distance used
  int min_size = 0;        ///< the absolute minimum size used
};

/// Clusters grasps by pose. Deterministic. @param epsilon per-grasp quality (same length).
ClusteringResult clusterGrasps(const std::vector<Pose>& poses, const std::vector<double>& epsilon,
                               const ClusteringOptions& options = {});

/// Relabels and summarises an existing dendrogram (for re-cutting a stored map).
ClusteringResult clusterFromLinkage(const std::vector<Pose>& poses,
                                    const std::vector<double>& epsilon,
                                    const LinkageMatrix& linkage, const ClusteringOptions& options);

}  // namespace taskmap
