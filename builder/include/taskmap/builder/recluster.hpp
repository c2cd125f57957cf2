#pragma once
/// @file recluster.hpp
/// Re-clustering the grasps of a built map (paper 1.6.1) with other settings, as `taskmap
/// cluster` does: the stored dendrogram is reused when it was computed with the same method and
/// metric, so a new cut costs no new clustering.

#include <optional>
#include <string>

#include "taskmap/clustering/clustering.hpp"
#include "taskmap/mapstore/task_map_data.hpp"

namespace taskmap {

/// What to change; an unset field keeps the library default (ClusteringOptions).
struct ReclusterOptions {
  std::optional<double> threshold;       ///< cut distance in the pose metric (metres)
  std::optional<int> clusters;           ///< or: cut into this many groups
  std::optional<int> min_size;           ///< smallest cluster kept
  std::optional<std::string> method;     ///< "single", "average" or "complete" (used or refused)
  std::optional<double> outlier_budget;  ///< share of grasps the default cut may leave out
};

/// What reclusterMap did.
struct ReclusterResult {
  bool reused_dendrogram = false;  ///< the map's stored dendrogram was cut again
  std::size_t grasps = 0;          ///< grasps clustered
};

/// Replaces map->clustering by a clustering of its grasps under `options` (the map's rotation
/// scale rho). Throws Error naming the option when it is out of range or contradicts another
/// (threshold and clusters), or when an explicit method cannot cluster this many grasps.
ReclusterResult reclusterMap(TaskMapData* map, const ReclusterOptions& options);

/// The summary `taskmap cluster` prints: grasps, linkage, whether the dendrogram was reused,
/// rho (m/rad), the cut and minimum size, then one line per cluster (size, best and mean
/// epsilon, mean position in metres, object frame) and "wrote <path>"; lines end in '\n'.
std::string reclusterText(const TaskMapData& map, const ReclusterResult& result,
                          const std::string& written_to);

}  // namespace taskmap
