// taskmap mesh-info FILE [--scale S] [--json] [--no-repair | --repair wrap]: load an object
// mesh as a solid and print what was found and repaired, and its mass properties.
#include <iostream>
#include <memory>
#include <string>

#include "command.hpp"
#include "mesh_options.hpp"
#include "taskmap/core/data_dir.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/inspect/mesh_info.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap::cli {
namespace {

struct MeshInfoArgs {
  std::string file;
  double scale = 1.0;
  bool json = false;
  MeshRepairArgs repair;
};

void run(const MeshInfoArgs& args) {
  MeshLoadOptions options;
  options.scale = args.scale;
  applyMeshRepairArgs(args.repair, options);
  ObjectModel model;
  try {
    model = ObjectModel::load(resolveObjectFile(args.file), options);
  } catch (const Error& e) {
    if (args.json) std::cout << meshInfoErrorJson(args.file, e.what()) << "\n";
    throw;
  }
  const MeshInfo info = meshInfo(model);
  std::cout << (args.json ? info.json + "\n" : info.text);
}

const CommandRegistrar kRegistrar(
    "mesh-info", "Load an object as a closed solid: repairs, size, mass properties",
    [](CLI::App& app) {
      auto args = std::make_shared<MeshInfoArgs>();
      CLI::App* cmd = app.add_subcommand(
          "mesh-info",
          "Load an object mesh as a closed solid; print repairs, size and mass properties, and "
          "flag a size implausible for a graspable object (with the --scale that fixes a file in "
          "millimetres, centimetres or inches)");
      cmd->add_option(
             "file", args->file,
             "mesh file (any format assimp reads), or a bundled object name (basket, box, ...)")
          ->required();
      cmd->add_option("--scale", args->scale, "multiplies coordinates (file units to metres)")
          ->check(CLI::PositiveNumber);
      cmd->add_flag("--json", args->json, "print JSON instead of text");
      addMeshRepairOptions(cmd, args->repair);
      cmd->callback([args]() { run(*args); });
    });

}  // namespace
}  // namespace taskmap::cli
