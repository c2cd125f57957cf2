// taskmap export MAP.h5 --format ply|glb|acronym -o OUT: the map for other tools.
#include <iostream>
#include <memory>
#include <string>

#include "acronym_frame.hpp"
#include "command.hpp"
#include "taskmap/builder/map_export.hpp"

namespace taskmap::cli {
namespace {

struct ExportArgs {
  MapExportOptions options;
  AcronymFrameArgs frame;
};

void runExport(ExportArgs args) {
  args.options.palm_offset = args.frame.palm_offset;
  args.options.hand = args.frame.hand;
  const MapExportOptions& o = args.options;
  const MapExportResult r = exportMapFile(o);
  if (r.hand_status != MapHandResult::Status::kLoaded)
    std::cerr << "taskmap export: warning: " << r.hand_message << "; drawing no hand"
              << (r.hand_status == MapHandResult::Status::kNotFound ? " (give --hand)" : "")
              << "\n";
  std::cout << "wrote " << o.output << " (" << o.format << "): " << r.grasps << " grasps, "
            << r.clusters << " clusters, object " << r.object_vertices << " vertices\n";
}

const CommandRegistrar kRegistrar(
    "export", "Export a map as PLY or GLB (object, palms, hands) or as an ACRONYM file",
    [](CLI::App& app) {
      auto args = std::make_shared<ExportArgs>();
      CLI::App* cmd = app.add_subcommand(
          "export",
          "Export a task map: ply or glb (object mesh, palm positions as points coloured by "
          "cluster, a hand glyph per cluster representative with fingers along the approach axis "
          "(palm +z), and the hand's collision shapes posed by each representative, one mesh per "
          "link (the map's hand or --hand); opens in MeshLab or Blender), or acronym (ACRONYM's "
          "per-object HDF5 layout: "
          "grasps/transforms, grasps/qualities/flex/object_in_gripper = force closure, object/*, "
          "gripper/*).");
      cmd->add_option("map", args->options.map, "task map file (.h5)")->required();
      cmd->add_option("--format", args->options.format, "ply, glb or acronym")->required();
      cmd->add_option("-o,--output", args->options.output, "file to write")->required();
      cmd->add_option("--glyph-size", args->options.glyph_size,
                      "ply/glb: finger length of the hand glyphs in metres (default: min(rho, a "
                      "fifth of the object size))");
      cmd->add_option("--density", args->options.density, "acronym: object density in kg/m^3")
          ->capture_default_str();
      cmd->add_option("--object-file", args->options.object_file,
                      "acronym: mesh file name for object/file (default <object name>.obj)");
      addAcronymFrameOptions(cmd, args->frame);
      cmd->add_flag("--force", args->options.force,
                    "replace an existing output file that is not of the format written");
      cmd->callback([args]() { runExport(*args); });
    });

}  // namespace
}  // namespace taskmap::cli
