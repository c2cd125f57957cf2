// taskmap export MAP.h5 --format ply|glb|acronym -o OUT: the map for other tools.
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "acronym_frame.hpp"
#include "command.hpp"
#include "map_hand_cli.hpp"
#include "taskmap/builder/acronym_import.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/output_guard.hpp"
#include "taskmap/inspect/map_scene.hpp"
#include "taskmap/mapstore/acronym.hpp"
#include "taskmap/mapstore/map_file.hpp"
#include "taskmap/meshes/mesh_export.hpp"

namespace taskmap::cli {
namespace {

struct ExportArgs {
  std::string map;
  std::string format;
  std::string output;
  double glyph_size = 0.0;  // 0: automatic
  double density = 1000.0;
  std::string object_file;
  AcronymFrameArgs frame;
  bool force = false;
};

void runExport(const ExportArgs& args) {
  if (args.format != "ply" && args.format != "glb" && args.format != "acronym") {
    throw Error("unknown format '" + args.format + "'; use ply, glb or acronym");
  }
  if (!std::filesystem::exists(args.map)) {
    throw Error("map file '" + args.map + "' does not exist; give the path of a task map (.h5)");
  }
  MapSceneOptions scene_options;
  scene_options.glyph_size = args.glyph_size;
  scene_options.validate();
  checkOutputPath(args.output, {args.map},
                  args.format == "ply"   ? OutputKind::kPly
                  : args.format == "glb" ? OutputKind::kGlb
                                         : OutputKind::kHdf5,
                  args.force);
  const TaskMapData map = readMap(args.map);
  if (args.format == "acronym") {
    AcronymExportOptions options;
    options.density = args.density;
    options.object_file = args.object_file;
    options.base_to_palm = acronymBaseToPalm(args.frame.palm_offset, args.frame.hand);
    writeAcronym(args.output, map, options);
  } else {
    const std::optional<HandModel> hand = mapHand(map, args.frame.hand, "taskmap export");
    const ExportScene scene = mapScene(map, scene_options, hand ? &*hand : nullptr);
    exportScene(args.output, scene, sceneFormatFromString(args.format));
  }
  std::cout << "wrote " << args.output << " (" << args.format << "): " << map.grasps.size()
            << " grasps, " << (map.clustering ? map.clustering->clusters.size() : 0)
            << " clusters, object " << map.object.vertices.rows() << " vertices\n";
}

const CommandRegistrar kRegistrar("export", [](CLI::App& app) {
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
  cmd->add_option("map", args->map, "task map file (.h5)")->required();
  cmd->add_option("--format", args->format, "ply, glb or acronym")->required();
  cmd->add_option("-o,--output", args->output, "file to write")->required();
  cmd->add_option("--glyph-size", args->glyph_size,
                  "ply/glb: finger length of the hand glyphs in metres (default: min(rho, a "
                  "fifth of the object size))");
  cmd->add_option("--density", args->density, "acronym: object density in kg/m^3")
      ->capture_default_str();
  cmd->add_option("--object-file", args->object_file,
                  "acronym: mesh file name for object/file (default <object name>.obj)");
  addAcronymFrameOptions(cmd, args->frame);
  cmd->add_flag("--force", args->force,
                "replace an existing output file that is not of the format written");
  cmd->callback([args]() { runExport(*args); });
});

}  // namespace
}  // namespace taskmap::cli
