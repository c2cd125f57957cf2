#pragma once
// Private: the state behind TaskMap.

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/StdVector>

#include "ball_tree.hpp"
#include "huge_page_allocator.hpp"
#include "kernels.hpp"
#include "nn_index.hpp"
#include "taskmap/integration/task_map.hpp"

namespace taskmap {

struct TaskMap::Impl {
  /// Values per row of a sample set: the 12-D embedding (the index's point), then epsilon
  /// (the layout detail::addMixtureTerm reads).
  static constexpr std::size_t kRowStride = kEmbeddingDim + 1;
  static constexpr std::size_t kWeightColumn = kEmbeddingDim;

  /// The samples of the whole map or of one cluster, with their own index and ball tree. Rows
  /// are in the ball tree's leaf order (else the index's, NnIndex::leafOrder), so the samples
  /// a query touches lie together in memory; row k is grasp `grasp[k]`.
  struct SampleSet {
    std::size_t count = 0;
    std::vector<std::size_t> grasp;   ///< grasp index of each row
    detail::HugeVector<double> rows;  ///< count x kRowStride (an index without a ball tree
                                      ///< reads them in place, else its own copy)
    std::unique_ptr<detail::NnIndex> index;
    /// Candidates of the cut-off searches; null if it does not apply (ball_tree.hpp).
    std::unique_ptr<detail::PoseBallTree> ball;
    double total_weight = 0.0;  ///< sum of the sample weights over the set
    std::size_t size() const { return count; }
    const double* row(std::size_t k) const { return rows.data() + k * kRowStride; }
  };

  /// A query pose, normalised, with its rotation matrix and embedding.
  struct Query {
    Eigen::Vector3d p;
    Eigen::Quaterniond q;
    Eigen::Matrix3d r;
    PoseEmbedding e;
  };

  TaskMapData data;
  TaskMapOptions options;  ///< defaults resolved by build()
  double rho = kDefaultRotationScale;
  std::vector<Eigen::Vector3d> pos;
  std::vector<Eigen::Quaterniond, Eigen::aligned_allocator<Eigen::Quaterniond>> qconj;
  std::vector<double> weight;  ///< w_i: epsilon, or epsilon x hold margin (SampleWeight)
  SampleSet all;
  std::vector<SampleSet> clusters;
  double wp = 1.0, wr = 1.0;
  double sp = 0.0, sr = 0.0, inv_z = 0.0;
  /// Kernel factors in embedding units: d = |dx_p|^2 inv_sp2 + |dx_R|^2 inv_se2, with
  /// inv_se2 = 1 / (rho sr)^2 (criteria.hpp, task_map_build.cpp).
  double inv_sp2 = 0.0, inv_se2 = 0.0;
  double cutoff = 0.0, cutoff2 = 0.0;
  double value_bound_factor = 0.0, gradient_bound_factor = 0.0;

  /// Validates data and options, builds indexes, resolves defaults. Throws Error.
  void build();
  /// build's steps: check the grasps and fill pos/qconj/weight; one sample set per cluster;
  /// kernel widths (from the sampling density unless given); the cut-off and error bounds.
  void readGrasps();
  void buildClusters();
  void chooseKernelWidths();
  void setTruncation();
  /// Embeds the given grasps (in leaf order) into s and builds its index.
  void buildSet(SampleSet& s, const std::vector<std::size_t>& members) const;
  const SampleSet& set(std::optional<int> cluster) const;
  Query query(const Pose& x) const;
  ProximityResult proximityTo(const Query& x, const Neighbor& n) const;
  /// Every sample of s within squared pose distance radius2 of x, in search order, with the
  /// index's distances (the same set as NnIndex::radius): from the ball tree's candidates
  /// when it applies, else from the index.
  void ballSearch(const SampleSet& s, const Query& x, double radius2,
                  std::vector<detail::IndexHit>& out) const;
  /// The ball tree's candidates of s within pose distance sqrt(radius2) of x, prefetching
  /// their rows; false if the tree does not apply (none, or it cannot answer this radius).
  static bool ballCandidates(const SampleSet& s, const Query& x, double radius2,
                             std::vector<std::uint32_t>& out);
  /// a before b: nearer, ties to the smaller grasp index (the index's rule).
  static bool nearer(const SampleSet& s, const detail::IndexHit& a, const detail::IndexHit& b) {
    return a.distance2 < b.distance2 ||
           (a.distance2 == b.distance2 && s.grasp[a.index] < s.grasp[b.index]);
  }
  /// The nearest sample (a row of s) when no sample is within a searched ball: exact tree: the
  /// ball tree's exact branch and bound (the index's distances and ties), else the index's
  /// nearest() (randomized forest: its answer).
  detail::IndexHit nearestOutsideBall(const SampleSet& s, const Query& x) const;
  /// ballSearch() and the nearest sample (a row of s): the best of the ball if it holds a
  /// sample, else the index's nearest() (exact tree: exact; randomized forest: its answer), as
  /// NnIndex::radiusAndNearest.
  detail::IndexHit ballAndNearest(const SampleSet& s, const Query& x, double radius2,
                                  std::vector<detail::IndexHit>& out) const;
  QualityCriterion qualityExact(const Query& x, const SampleSet& s) const;
  /// The truncated mixture at x over the samples of s within the cut-off, added to m, and the
  /// nearest sample (a row of s; as ballAndNearest) from the same search.
  detail::IndexHit cutoffMixture(const SampleSet& s, const Query& x, detail::MixtureSum& m) const;
  /// The truncated-mode result of a mixture over the samples within the cut-off: finish()
  /// and the truncation bounds from the weight the mixture left out.
  QualityCriterion truncated(const detail::MixtureSum& m, const Query& x, const SampleSet& s) const;

  /// The normalised value and object-frame gradient of an accumulated mixture.
  QualityCriterion finish(const detail::MixtureSum& m, const Query& x, const SampleSet& s) const;
};

}  // namespace taskmap
