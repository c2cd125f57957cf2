// taskmap cluster: re-cluster the grasps of a task map (paper 1.6.1) and write it back.
#include <iostream>
#include <memory>
#include <string>

#include "command.hpp"
#include "taskmap/builder/recluster.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap::cli {
namespace {

struct ClusterArgs {
  std::string map;
  ReclusterOptions options;
  bool quiet = false;
};

void runCluster(const ClusterArgs& args) {
  TaskMapData map = readMap(args.map);
  const ReclusterResult result = reclusterMap(&map, args.options);
  writeMap(args.map, map);
  if (!args.quiet) std::cout << reclusterText(map, result, args.map);
}

const CommandRegistrar kRegistrar(
    "cluster", "Re-cluster a map's grasps: labels, cluster table and dendrogram",
    [](CLI::App& app) {
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
      auto* threshold = cmd->add_option("--threshold", args->options.threshold,
                                        "cut distance in the pose metric (metres)")
                            ->check(CLI::NonNegativeNumber);
      auto* clusters =
          cmd->add_option("--clusters", args->options.clusters,
                          "cut the dendrogram into this many groups (groups below the minimum "
                          "size then become outliers)")
              ->check(CLI::PositiveNumber);
      threshold->excludes(clusters);
      clusters->excludes(threshold);
      cmd->add_option("--min-size", args->options.min_size,
                      "smallest cluster kept; smaller ones are outliers (label -1). "
                      "Default: 3 % of the grasps, at least 3")
          ->check(CLI::PositiveNumber);
      cmd->add_option("--method", args->options.method,
                      "linkage: single (any size), average or complete (up to 20000 grasps). "
                      "Default: average, single beyond 20000 grasps")
          ->check(CLI::IsMember({"single", "average", "complete"}));
      cmd->add_option("--outlier-budget", args->options.outlier_budget,
                      "share of the grasps the default cut may leave as outliers, in [0, 1] "
                      "(ignored with --threshold or --clusters). Default: 0.1")
          ->check(CLI::Range(0.0, 1.0));
      cmd->add_flag("-q,--quiet", args->quiet, "print nothing");
      cmd->callback([args]() { runCluster(*args); });
    });

}  // namespace
}  // namespace taskmap::cli
