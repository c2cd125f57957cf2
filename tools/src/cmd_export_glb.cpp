// taskmap export-glb TRAJECTORY.h5 -o out.glb: a reaching trajectory (`taskmap reach --map
// ... -o`) as glTF 2.0 binary for Blender: robot, hand and table primitives, the object mesh,
// and the movement as an animation (taskmap/inspect/glb_export.hpp).
#include <iostream>
#include <memory>
#include <string>

#include "command.hpp"
#include "taskmap/core/output_guard.hpp"
#include "taskmap/inspect/glb_export.hpp"
#include "taskmap/mapstore/trajectory_file.hpp"

namespace taskmap::cli {
namespace {

struct ExportGlbArgs {
  std::string trajectory, output;
  bool quiet = false;
  bool force = false;
};

void runExportGlb(const ExportGlbArgs& args) {
  checkOutputPath(args.output, {args.trajectory}, OutputKind::kGlb, args.force);
  const TrajectoryRecord r = readTrajectory(args.trajectory);
  writeGlb(r, args.output);
  if (!args.quiet)
    std::cout << "taskmap export-glb: " << args.output << " (" << r.body_names.size() << " bodies, "
              << r.rows() << " keys, " << (r.rows() - 1) * r.dt << " s)\n";
}

const CommandRegistrar kRegistrar(
    "export-glb", "Write a reach trajectory file as an animated glTF scene (.glb)",
    [](CLI::App& app) {
      auto args = std::make_shared<ExportGlbArgs>();
      CLI::App* cmd = app.add_subcommand(
          "export-glb",
          "Write a trajectory file (taskmap reach --map ... -o FILE) as glTF 2.0 binary (.glb, "
          "Blender: File > Import > glTF 2.0): one node per body with its collision primitives, "
          "the "
          "object mesh at its pose, animation 'reach' over the steps (z-up world turned to glTF's "
          "y-up by the root node 'world').");
      cmd->add_option("trajectory", args->trajectory, "trajectory file (.h5)")->required();
      cmd->add_option("-o,--output", args->output, "GLB file to write (atomically)")->required();
      cmd->add_flag("-q,--quiet", args->quiet, "print nothing on success");
      cmd->add_flag("--force", args->force, "replace an existing output that is not a GLB file");
      cmd->callback([args] { runExportGlb(*args); });
    });

}  // namespace
}  // namespace taskmap::cli
