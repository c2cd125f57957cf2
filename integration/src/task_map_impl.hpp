#pragma once
// Private: the state behind TaskMap.

#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/StdVector>

#include "nn_index.hpp"
#include "taskmap/integration/task_map.hpp"

namespace taskmap {

struct TaskMap::Impl {
  /// The samples of the whole map or of one cluster, with their own index.
  struct SampleSet {
    std::vector<std::size_t> members;  ///< global grasp indices; empty = identity (whole map)
    std::size_t count = 0;
    std::vector<double> embedding;  ///< count x 12, row-major (the index points into it)
    std::unique_ptr<detail::NnIndex> index;
    double total_weight = 0.0;  ///< sum of epsilon over the set
    std::size_t size() const { return count; }
    std::size_t global(std::size_t local) const { return members.empty() ? local : members[local]; }
  };

  TaskMapData data;
  TaskMapOptions options;  ///< defaults resolved by build()
  double rho = kDefaultRotationScale;
  std::vector<Eigen::Vector3d> pos;
  std::vector<Eigen::Quaterniond, Eigen::aligned_allocator<Eigen::Quaterniond>> qconj;
  std::vector<double> weight;  ///< epsilon
  SampleSet all;
  std::vector<SampleSet> clusters;
  double wp = 1.0, wr = 1.0;
  double sp = 0.0, sr = 0.0, inv_sp2 = 0.0, inv_sr2 = 0.0, inv_z = 0.0;
  double cutoff = 0.0, cutoff2 = 0.0;
  double value_bound_factor = 0.0, gradient_bound_factor = 0.0;

  /// Validates data and options, builds indexes, resolves defaults. Throws Error.
  void build();
  /// Embeds the set's samples and builds its index.
  void buildSet(SampleSet& s) const;
  const SampleSet& set(std::optional<int> cluster) const;
  ProximityResult proximityTo(const Eigen::Vector3d& p, const Eigen::Quaterniond& q,
                              const Eigen::Matrix3d& r, const Neighbor& n) const;
  QualityResult qualityExact(const Eigen::Vector3d& p, const Eigen::Quaterniond& q,
                             const Eigen::Matrix3d& r, const SampleSet& s) const;
  QualityResult qualityOver(const Eigen::Vector3d& p, const Eigen::Quaterniond& q,
                            const Eigen::Matrix3d& r, const SampleSet& s,
                            const std::vector<detail::IndexHit>& hits) const;

  /// Running sums of the quality mixture (gradient parts before normalisation).
  struct MixtureSum {
    double sum = 0.0;
    Eigen::Vector3d gp = Eigen::Vector3d::Zero();
    Eigen::Vector3d gw = Eigen::Vector3d::Zero();  ///< hand frame, rotated by R at the end
    double included_weight = 0.0;
    std::size_t terms = 0;
  };
  /// Adds the weighted Gaussian of sample i at (p, q) and its gradient parts to m.
  void addTerm(std::size_t i, const Eigen::Vector3d& p, const Eigen::Quaterniond& q,
               MixtureSum& m) const;
  /// The normalised value and object-frame gradient of an accumulated mixture.
  QualityResult finish(const MixtureSum& m, const Eigen::Matrix3d& r, const SampleSet& s) const;
};

}  // namespace taskmap
