// Re-clustering a built map (builder/recluster.hpp).
#include "taskmap/builder/recluster.hpp"

#include <sstream>
#include <vector>

#include "taskmap/core/error.hpp"
#include "taskmap/core/text.hpp"

namespace taskmap {
namespace {

ClusteringOptions clusteringOptions(const ReclusterOptions& o, const TaskMapData& map) {
  if (o.threshold && o.clusters)
    throw Error("recluster: give a threshold or a number of clusters, not both");
  ClusteringOptions options;
  if (o.method) {
    options.method = linkageFromString(*o.method);
    options.fallback_to_single = false;  // an explicit method is used or refused
  } else {
    options.method = resolveMethod(options, static_cast<int>(map.grasps.size()));
  }
  if (o.outlier_budget) options.outlier_budget = *o.outlier_budget;
  options.threshold = o.threshold;
  options.num_clusters = o.clusters;
  if (o.min_size) options.min_size = *o.min_size;
  options.rotation_scale = map.grasps.rotation_scale;
  options.validate();
  return options;
}

}  // namespace

ReclusterResult reclusterMap(TaskMapData* map, const ReclusterOptions& o) {
  const ClusteringOptions options = clusteringOptions(o, *map);
  const std::size_t n = map->grasps.size();
  std::vector<Pose> poses;
  poses.reserve(n);
  for (std::size_t i = 0; i < n; ++i) poses.push_back(map->grasps.poseAt(i));
  ReclusterResult result;
  result.grasps = n;
  result.reused_dendrogram =
      map->clustering && map->clustering->method == options.method &&
      map->clustering->rotation_scale == options.rotation_scale &&
      map->clustering->linkage.rows() == static_cast<Eigen::Index>(n > 0 ? n - 1 : 0);
  ClusteringResult c =
      result.reused_dendrogram
          ? clusterFromLinkage(poses, map->grasps.epsilon, map->clustering->linkage, options)
          : clusterGrasps(poses, map->grasps.epsilon, options);
  map->clustering = std::move(c);
  return result;
}

std::string reclusterText(const TaskMapData& map, const ReclusterResult& result,
                          const std::string& written_to) {
  if (!map.clustering) return "wrote " + written_to + "\n";
  const ClusteringResult& c = *map.clustering;
  std::ostringstream os;
  std::size_t outliers = 0;
  for (int l : c.labels) outliers += l < 0;
  os << formatted(
      "taskmap cluster: %zu grasps, %s linkage (%s), rho %.4g m/rad, cut at %.6g, min size "
      "%d\n",
      result.grasps, toString(c.method),
      result.reused_dendrogram ? "stored dendrogram" : "recomputed", c.rotation_scale, c.threshold,
      c.min_size);
  os << formatted("  %zu clusters, %zu outliers\n", c.clusters.size(), outliers);
  if (!c.clusters.empty()) os << "  id   size  best_eps  mean_eps  mean position (m)\n";
  for (std::size_t k = 0; k < c.clusters.size(); ++k) {
    const ClusterSummary& s = c.clusters[k];
    os << formatted("  %-4zu %5d  %8.4f  %8.4f  (%.4f, %.4f, %.4f)\n", k, s.size, s.best_epsilon,
                    s.mean_epsilon, s.mean_pose.position.x(), s.mean_pose.position.y(),
                    s.mean_pose.position.z());
  }
  os << "  wrote " << written_to << "\n";
  return os.str();
}

}  // namespace taskmap
