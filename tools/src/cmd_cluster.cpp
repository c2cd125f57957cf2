// taskmap cluster: re-cluster the grasps of a task map (paper 1.6.1) and write it back.
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "command.hpp"
#include "taskmap/clustering/clustering.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap::cli {
namespace {

struct ClusterArgs {
  std::string map;
  std::optional<double> threshold;
  std::optional<int> clusters;
  std::optional<int> min_size;
  std::optional<std::string> method;  ///< default: the library default (ClusteringOptions)
  std::optional<double> outlier_budget;
  bool quiet = false;
};

std::string formatSummary(const std::string& path, const ClusteringResult& c, bool reused,
                          std::size_t grasps) {
  std::ostringstream os;
  std::size_t outliers = 0;
  for (int l : c.labels) outliers += l < 0;
  char line[256];
  std::snprintf(line, sizeof line,
                "taskmap cluster: %zu grasps, %s linkage (%s), rho %.4g m/rad, cut at %.6g, "
                "min size %d\n",
                grasps, toString(c.method), reused ? "stored dendrogram" : "recomputed",
                c.rotation_scale, c.threshold, c.min_size);
  os << line;
  std::snprintf(line, sizeof line, "  %zu clusters, %zu outliers\n", c.clusters.size(), outliers);
  os << line;
  if (!c.clusters.empty()) {
    os << "  id   size  best_eps  mean_eps  mean position (m)\n";
  }
  for (std::size_t k = 0; k < c.clusters.size(); ++k) {
    const ClusterSummary& s = c.clusters[k];
    std::snprintf(line, sizeof line, "  %-4zu %5d  %8.4f  %8.4f  (%.4f, %.4f, %.4f)\n", k, s.size,
                  s.best_epsilon, s.mean_epsilon, s.mean_pose.position.x(),
                  s.mean_pose.position.y(), s.mean_pose.position.z());
    os << line;
  }
  os << "  wrote " << path << "\n";
  return os.str();
}

void runCluster(const ClusterArgs& args) {
  TaskMapData map = readMap(args.map);
  ClusteringOptions options;
  const std::size_t n = map.grasps.size();
  if (args.method) {
    options.method = linkageFromString(*args.method);
    options.fallback_to_single = false;  // an explicit method is used or refused
  } else {
    options.method = resolveMethod(options, static_cast<int>(n));
  }
  if (args.outlier_budget) options.outlier_budget = *args.outlier_budget;
  options.threshold = args.threshold;
  options.num_clusters = args.clusters;
  if (args.min_size) options.min_size = *args.min_size;
  options.rotation_scale = map.grasps.rotation_scale;
  options.validate();

  std::vector<Pose> poses;
  poses.reserve(n);
  for (std::size_t i = 0; i < n; ++i) poses.push_back(map.grasps.poseAt(i));
  // The stored dendrogram is reused when it was computed with the same method and metric.
  const bool reuse = map.clustering && map.clustering->method == options.method &&
                     map.clustering->rotation_scale == options.rotation_scale &&
                     map.clustering->linkage.rows() == static_cast<Eigen::Index>(n > 0 ? n - 1 : 0);
  ClusteringResult result =
      reuse ? clusterFromLinkage(poses, map.grasps.epsilon, map.clustering->linkage, options)
            : clusterGrasps(poses, map.grasps.epsilon, options);
  map.clustering = std::move(result);
  writeMap(args.map, map);
  if (!args.quiet) std::cout << formatSummary(args.map, *map.clustering, reuse, n);
}

const CommandRegistrar kRegistrar("cluster", [](CLI::App& app) {
  auto args = std::make_shared<ClusterArgs>();
  CLI::App* cmd = app.add_subcommand(
      "cluster",
      "Re-cluster the grasps of a task map and write the labels, cluster table and dendrogram "
      "back into it. Hierarchical clustering in the pose metric of the map (its rho); the "
      "stored dendrogram is reused when the method is unchanged. Without --threshold or "
      "--clusters the cut is at the largest relative gap of the dendrogram between clusters of "
      "at least the minimum size, but never below the lowest cut that leaves at most the "
      "outlier budget of the grasps in clusters below the minimum size.");
  cmd->add_option("map", args->map, "task map (.h5), rewritten in place (atomically)")
      ->required()
      ->check(CLI::ExistingFile);
  auto* threshold =
      cmd->add_option("--threshold", args->threshold, "cut distance in the pose metric (metres)")
          ->check(CLI::NonNegativeNumber);
  auto* clusters =
      cmd->add_option("--clusters", args->clusters,
                      "cut the dendrogram into this many groups (groups below the minimum "
                      "size then become outliers)")
          ->check(CLI::PositiveNumber);
  threshold->excludes(clusters);
  clusters->excludes(threshold);
  cmd->add_option("--min-size", args->min_size,
                  "smallest cluster kept; smaller ones are outliers (label -1). "
                  "Default: 3 % of the grasps, at least 3")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--method", args->method,
                  "linkage: single (any size), average or complete (up to 20000 grasps). "
                  "Default: average, single beyond 20000 grasps")
      ->check(CLI::IsMember({"single", "average", "complete"}));
  cmd->add_option("--outlier-budget", args->outlier_budget,
                  "share of the grasps the default cut may leave as outliers, in [0, 1] "
                  "(ignored with --threshold or --clusters). Default: 0.1")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_flag("-q,--quiet", args->quiet, "print nothing");
  cmd->callback([args]() { runCluster(*args); });
});

}  // namespace
}  // namespace taskmap::cli
