// A map file exported for other tools (builder/map_export.hpp).
#include "taskmap/builder/map_export.hpp"

#include <filesystem>

#include "taskmap/builder/acronym_import.hpp"
#include "taskmap/core/data_dir.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/output_guard.hpp"
#include "taskmap/inspect/map_scene.hpp"
#include "taskmap/mapstore/acronym.hpp"
#include "taskmap/mapstore/map_file.hpp"
#include "taskmap/meshes/mesh_export.hpp"

namespace taskmap {
namespace {

/// The map's hand as the commands find it: an explicit one (path or bundled name) or the map's
/// own among the bundled hands (none when there is no data directory).
MapHandResult exportHand(const TaskMapData& map, const std::string& hand) {
  MapHandOptions options;
  if (!hand.empty()) options.hand = resolveHandUrdf(hand);
  try {
    options.hands_dir = (std::filesystem::path(dataDir()) / "hands").string();
  } catch (const Error&) {
    // No data directory: only the path the build recorded is tried.
  }
  return findMapHand(map, options);
}

}  // namespace

MapExportResult exportMapFile(const MapExportOptions& o) {
  if (o.format != "ply" && o.format != "glb" && o.format != "acronym")
    throw Error("unknown format '" + o.format + "'; use ply, glb or acronym");
  if (!std::filesystem::exists(o.map))
    throw Error("map file '" + o.map + "' does not exist; give the path of a task map (.h5)");
  MapSceneOptions scene_options;
  scene_options.glyph_size = o.glyph_size;
  scene_options.validate();
  checkOutputPath(o.output, {o.map},
                  o.format == "ply"   ? OutputKind::kPly
                  : o.format == "glb" ? OutputKind::kGlb
                                      : OutputKind::kHdf5,
                  o.force, o.output_option);
  const TaskMapData map = readMap(o.map);
  MapExportResult r;
  r.grasps = map.grasps.size();
  r.clusters = map.clustering ? map.clustering->clusters.size() : 0;
  r.object_vertices = static_cast<std::size_t>(map.object.vertices.rows());
  if (o.format == "acronym") {
    AcronymExportOptions options;
    options.density = o.density;
    options.object_file = o.object_file;
    options.base_to_palm = acronymBaseToPalm(o.palm_offset, o.hand);
    writeAcronym(o.output, map, options);
    return r;
  }
  const MapHandResult hand = exportHand(map, o.hand);
  r.hand_status = hand.status;
  r.hand_message = hand.message;
  const ExportScene scene = mapScene(map, scene_options, hand.hand ? &*hand.hand : nullptr);
  exportScene(o.output, scene, sceneFormatFromString(o.format));
  return r;
}

}  // namespace taskmap
