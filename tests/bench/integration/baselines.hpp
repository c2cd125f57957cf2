#pragma once
// The baselines integration_bench times TaskMap::evaluate and nearest against: nanoflann
// kd-trees (7-D float points as TaskMap's ball tree, and the 12-D embedding) and a brute-force
// scan, each with the same mixture kernel and the same criteria as TaskMap (written out again).

#include <cstddef>
#include <memory>
#include <vector>

#include "taskmap/integration/task_map.hpp"

namespace taskmap {
namespace bench {

/// Evaluations of the benchmark's queries (by index into the vector given to the constructor)
/// without TaskMap's index. Builds its trees in the constructor; the map must outlive it.
class Baselines {
 public:
  /// Trees over the samples of map; per-query data for queries.
  Baselines(const TaskMap& map, const std::vector<Pose>& queries);
  ~Baselines();
  /// nanoflann over the 7-D float points y = (p, 2 rho q) with TaskMap's radius, -q search and
  /// exact 12-D filter (rows in its leaf order), then the 12-D nearest if none is within r_c.
  Evaluation nanoflann7(std::size_t query) const;
  /// nanoflann over the 12-D embedding: radius r_c, else its nearest.
  Evaluation nanoflann12(std::size_t query) const;
  /// One scan of every sample: the nearest and the whole mixture.
  Evaluation brute(std::size_t query) const;
  /// nanoflann's exact 12-D nearest sample.
  std::size_t nearestNanoflann(std::size_t query) const;
  /// Brute-force nearest sample; its squared embedding distance in *d2.
  std::size_t nearestBrute(std::size_t query, double* d2) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace bench
}  // namespace taskmap
