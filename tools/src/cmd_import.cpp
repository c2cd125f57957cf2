// taskmap import --acronym FILE.h5 --object MESH -o MAP.h5: an ACRONYM grasp file as a task map.
// The foreign file carries no seal, so the import runs in a child process with CPU-time and
// memory limits (isolated.hpp): a file that crashes or hangs HDF5 is refused.
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "acronym_frame.hpp"
#include "command.hpp"
#include "isolated.hpp"
#include "taskmap/builder/map_builder.hpp"
#include "taskmap/clustering/clustering.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/output_guard.hpp"
#include "taskmap/mapstore/acronym.hpp"
#include "taskmap/mapstore/map_file.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap::cli {
namespace {

struct ImportArgs {
  std::string acronym;
  std::string object;
  std::string output;
  double scale = 0.0;  // 0: object/scale of the file
  bool successful_only = false;
  bool no_cluster = false;
  bool timestamp = false;
  IsolationLimits limits{600, 16.0};
  std::string linkage = toString(ClusteringOptions{}.method);  // the library default
  double rotation_scale = kDefaultRotationScale;
  std::optional<double> threshold;
  std::optional<int> clusters;
  double min_size_fraction = kDefaultMinSizeFraction;
  AcronymFrameArgs frame;
  bool force = false;
};

void runImport(const ImportArgs& args) {
  if (args.scale < 0) throw Error("--scale must be positive");
  AcronymImportOptions options;
  options.successful_only = args.successful_only;
  options.cluster = !args.no_cluster;
  options.clustering.method = linkageFromString(args.linkage);
  options.clustering.rotation_scale = args.rotation_scale;
  options.clustering.threshold = args.threshold;
  options.clustering.num_clusters = args.clusters;
  options.clustering.min_size_fraction = args.min_size_fraction;
  options.base_to_palm = baseToPalm(args.frame);
  options.validate();
  const AcronymGrasps grasps = readAcronym(args.acronym);
  if (!std::filesystem::exists(args.object)) {
    throw Error("object mesh '" + args.object + "' does not exist; give the mesh that " +
                args.acronym + " refers to (object/file: '" + grasps.object_file + "')");
  }
  MeshLoadOptions load;
  load.scale = args.scale > 0 ? args.scale : grasps.object_scale;
  const ObjectModel model = ObjectModel::load(args.object, load);
  TaskMapData map = acronymToMap(grasps, mapObjectOf(model), options);
  if (args.timestamp) map.created_utc = mapCreationTime(true);
  writeMap(args.output, map);
  std::size_t successes = 0;
  for (auto fc : map.grasps.force_closure) successes += fc;
  std::cout << "wrote " << args.output << ": " << map.grasps.size() << " grasps (" << successes
            << " successful) from " << args.acronym << ", object " << model.name() << " at scale "
            << load.scale << ", "
            << (map.clustering ? std::to_string(map.clustering->clusters.size())
                               : std::string("no"))
            << " clusters; contacts absent; "
            << describeBaseToPalm(args.frame, options.base_to_palm) << "\n";
}

const CommandRegistrar kRegistrar("import", [](CLI::App& app) {
  auto args = std::make_shared<ImportArgs>();
  CLI::App* cmd = app.add_subcommand(
      "import",
      "Turn an ACRONYM grasp file into a task map: poses from grasps/transforms, force closure "
      "from grasps/qualities/flex/object_in_gripper, epsilon from the taskmap epsilon if the "
      "file has one (else the success flag 0/1); contacts absent; clustered like `taskmap "
      "build`.");
  cmd->add_option("--acronym", args->acronym, "ACRONYM grasp file (.h5)")->required();
  cmd->add_option("--object", args->object, "the object's mesh file (any format assimp reads)")
      ->required();
  cmd->add_option("-o,--output", args->output, "task map to write (.h5)")->required();
  cmd->add_option("--scale", args->scale,
                  "scale of the mesh file (default: the file's object/scale)");
  cmd->add_flag("--successful-only", args->successful_only,
                "keep only grasps with object_in_gripper = 1");
  cmd->add_flag("--no-cluster", args->no_cluster, "do not cluster the imported grasps");
  cmd->add_flag("--timestamp", args->timestamp,
                "store the current time as created_utc (default: SOURCE_DATE_EPOCH if set, "
                "else none)");
  cmd->add_option("--linkage", args->linkage, "single, average or complete")->capture_default_str();
  cmd->add_option("--rotation-scale", args->rotation_scale,
                  "rho of the pose metric in metres per radian")
      ->capture_default_str();
  cmd->add_option("--threshold", args->threshold, "cut distance in metres (default: automatic)");
  cmd->add_option("--clusters", args->clusters, "cut to this many clusters");
  cmd->add_option("--min-size-fraction", args->min_size_fraction,
                  "clusters below this share of the grasps are outliers")
      ->capture_default_str();
  addAcronymFrameOptions(cmd, args->frame);
  cmd->add_option("--cpu-seconds", args->limits.cpu_seconds,
                  "CPU-time limit of the import (it runs in a child process)")
      ->check(CLI::Range(1, 86400))
      ->capture_default_str();
  cmd->add_option("--memory-gib", args->limits.memory_gib, "address-space limit of the import")
      ->check(CLI::Range(0.25, 1024.0))
      ->capture_default_str();
  cmd->add_flag("--force", args->force,
                "replace an existing output file that is not a task map (never an input)");
  cmd->callback([args]() {
    checkOutputPath(args->output, {args->acronym, args->object}, OutputKind::kTaskMap, args->force);
    runIsolated([&args] { runImport(*args); }, args->limits,
                "cannot import ACRONYM file '" + args->acronym + "'");
  });
});

}  // namespace
}  // namespace taskmap::cli
