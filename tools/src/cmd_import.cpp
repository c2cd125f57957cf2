// taskmap import --acronym FILE.h5 --object MESH -o MAP.h5: an ACRONYM grasp file as a task map.
// What it computes is builder's importAcronymFile (builder/acronym_import.hpp: in a child process
// with CPU-time and memory limits, so a file that crashes or hangs HDF5 is refused).
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "acronym_frame.hpp"
#include "command.hpp"
#include "taskmap/builder/acronym_import.hpp"
#include "taskmap/clustering/clustering.hpp"
#include "taskmap/core/data_dir.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/output_guard.hpp"

namespace taskmap::cli {
namespace {

struct ImportArgs {
  AcronymFileImportOptions options;
  std::string linkage = toString(ClusteringOptions{}.method);  // the library default
  double rotation_scale = kDefaultRotationScale;
  std::optional<double> threshold;
  std::optional<int> clusters;
  double min_size_fraction = kDefaultMinSizeFraction;
  bool successful_only = false;
  bool no_cluster = false;
  AcronymFrameArgs frame;
  bool force = false;
};

void runImport(ImportArgs& args) {
  AcronymFileImportOptions& o = args.options;
  o.object = objectFileOrBundled(o.object);
  checkOutputPath(o.output, {o.acronym, o.object}, OutputKind::kTaskMap, args.force);
  if (o.scale < 0) throw Error("--scale must be positive");
  o.import.successful_only = args.successful_only;
  o.import.cluster = !args.no_cluster;
  o.import.clustering.method = linkageFromString(args.linkage);
  o.import.clustering.rotation_scale = args.rotation_scale;
  o.import.clustering.threshold = args.threshold;
  o.import.clustering.num_clusters = args.clusters;
  o.import.clustering.min_size_fraction = args.min_size_fraction;
  o.import.base_to_palm = acronymBaseToPalm(args.frame.palm_offset, args.frame.hand);
  o.hand = args.frame.hand;
  const AcronymFileImport r = importAcronymFile(o);
  std::cout << "wrote " << o.output << ": " << r.grasps << " grasps (" << r.successes
            << " successful) from " << o.acronym << ", object " << r.object_name << " at scale "
            << r.scale << ", " << (r.clusters ? std::to_string(*r.clusters) : std::string("no"))
            << " clusters; contacts absent; "
            << describeBaseToPalm(args.frame, o.import.base_to_palm) << "\n";
  if (r.jaws_closed)
    std::cout << "joint values: the jaws of " << o.hand
              << " closed from open at each pose until both touch the object; dropped "
              << r.jaws_missed << " grasps whose jaws miss the object; kept " << r.jaws_overlap
              << " whose open jaws intersect it (the hold test's penetration check decides; "
                 "ACRONYM indices in the map's sampling parameters jaws_missed, jaws_overlap); "
                 "`taskmap validate` finds the hand\n";
  else
    std::cout << "joint values: none (poses only; give --hand URDF to close the jaws and "
                 "validate the map)\n";
}

const CommandRegistrar kRegistrar(
    "import", "Turn an ACRONYM grasp file into a task map", [](CLI::App& app) {
      auto args = std::make_shared<ImportArgs>();
      CLI::App* cmd = app.add_subcommand(
          "import",
          "Turn an ACRONYM grasp file into a task map: poses from grasps/transforms, force closure "
          "from grasps/qualities/flex/object_in_gripper, epsilon from the taskmap epsilon if the "
          "file has one (else the success flag 0/1); contacts absent; clustered like `taskmap "
          "build`.");
      cmd->add_option("--acronym", args->options.acronym, "ACRONYM grasp file (.h5)")->required();
      cmd->add_option("--object", args->options.object,
                      "the object's mesh file (any format assimp reads), or a bundled object name")
          ->required();
      cmd->add_option("-o,--output", args->options.output, "task map to write (.h5)")->required();
      cmd->add_option("--scale", args->options.scale,
                      "scale of the mesh file (default: the file's object/scale)");
      cmd->add_flag("--successful-only", args->successful_only,
                    "keep only grasps with object_in_gripper = 1");
      cmd->add_flag("--no-cluster", args->no_cluster, "do not cluster the imported grasps");
      cmd->add_flag("--timestamp", args->options.timestamp,
                    "store the current time as created_utc (default: SOURCE_DATE_EPOCH if set, "
                    "else none)");
      cmd->add_option("--linkage", args->linkage, "single, average or complete")
          ->capture_default_str();
      cmd->add_option("--rotation-scale", args->rotation_scale,
                      "rho of the pose metric in metres per radian")
          ->capture_default_str();
      cmd->add_option("--threshold", args->threshold,
                      "cut distance in metres (default: automatic)");
      cmd->add_option("--clusters", args->clusters, "cut to this many clusters");
      cmd->add_option("--min-size-fraction", args->min_size_fraction,
                      "clusters below this share of the grasps are outliers")
          ->capture_default_str();
      addAcronymFrameOptions(cmd, args->frame);
      cmd->add_option("--cpu-seconds", args->options.cpu_seconds,
                      "CPU-time limit of the import (it runs in a child process)")
          ->check(CLI::Range(1, 86400))
          ->capture_default_str();
      cmd->add_option("--memory-gib", args->options.memory_gib, "address-space limit of the import")
          ->check(CLI::Range(0.25, 1024.0))
          ->capture_default_str();
      cmd->add_flag("--force", args->force,
                    "replace an existing output file that is not a task map (never an input)");
      cmd->callback([args]() { runImport(*args); });
    });

}  // namespace
}  // namespace taskmap::cli
