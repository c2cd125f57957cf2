// taskmap export MAP.h5 --format ply|glb|acronym -o OUT: the map for other tools.
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "acronym_frame.hpp"
#include "command.hpp"
#include "map_hand.hpp"
#include "map_summary.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/output_guard.hpp"
#include "taskmap/mapstore/acronym.hpp"
#include "taskmap/mapstore/map_file.hpp"
#include "taskmap/meshes/mesh_export.hpp"
#include "taskmap/meshes/shape_mesh.hpp"

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

Rgba rgba(int cluster) {
  const auto c = clusterColor(cluster);
  return Rgba(c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f, 1.0f);
}

// Object mesh, palm positions coloured by cluster (outliers grey) and a hand glyph at each
// cluster representative (fingers along the palm's +z approach axis).
ExportScene sceneOf(const TaskMapData& map, double glyph_size) {
  ExportScene s;
  s.name = map.object.name.empty() ? "taskmap" : map.object.name;
  const auto& v = map.object.vertices;
  for (Eigen::Index i = 0; i < v.rows(); ++i)
    s.object.vertices.emplace_back(v(i, 0), v(i, 1), v(i, 2));
  const auto& f = map.object.faces;
  for (Eigen::Index i = 0; i < f.rows(); ++i) {
    s.object.faces.emplace_back(static_cast<int>(f(i, 0)), static_cast<int>(f(i, 1)),
                                static_cast<int>(f(i, 2)));
  }
  const std::size_t n = map.grasps.size();
  const bool labelled = map.clustering && map.clustering->labels.size() == n;
  for (std::size_t i = 0; i < n; ++i) {
    s.points.push_back(map.grasps.pose.row(static_cast<Eigen::Index>(i)).head<3>().transpose());
    s.point_colors.push_back(rgba(labelled ? map.clustering->labels[i] : -1));
  }
  if (map.clustering) {
    for (std::size_t k = 0; k < map.clustering->clusters.size(); ++k) {
      const int rep = map.clustering->clusters[k].representative;
      if (rep < 0 || static_cast<std::size_t>(rep) >= n) continue;
      SceneGlyph g;
      g.pose = map.grasps.poseAt(static_cast<std::size_t>(rep)).toIsometry();
      g.color = rgba(static_cast<int>(k));
      s.glyphs.push_back(g);
    }
  }
  if (glyph_size > 0) {
    s.glyph_size = glyph_size;
  } else {
    // About a hand: rho approximates the palm-to-fingertip length; at most a fifth of the
    // object so that glyphs do not hide it.
    double extent = 0.1;
    if (v.rows() > 0) extent = (v.colwise().maxCoeff() - v.colwise().minCoeff()).maxCoeff();
    s.glyph_size = std::min(map.grasps.rotation_scale, 0.2 * extent);
    if (!(s.glyph_size > 0)) s.glyph_size = 0.03;
  }
  return s;
}

// The hand's links posed by each cluster representative (stored pose and joint values), one
// part per link with collision shapes, named "cluster<k>_<link>", in the cluster colour.
std::vector<ScenePart> handParts(const TaskMapData& map, const HandModel& hand) {
  std::vector<ScenePart> parts;
  if (!map.clustering) return parts;
  for (std::size_t k = 0; k < map.clustering->clusters.size(); ++k) {
    const int rep = map.clustering->clusters[k].representative;
    if (rep < 0 || static_cast<std::size_t>(rep) >= map.grasps.size()) continue;
    const GraspPosture p = graspPosture(map, static_cast<std::size_t>(rep));
    std::vector<TriangleMesh> links = posedLinkMeshes(hand, p.palm_pose, p.joints);
    for (std::size_t li = 0; li < links.size(); ++li) {
      if (links[li].faces.empty()) continue;
      ScenePart part;
      part.name = "cluster" + std::to_string(k) + "_" + hand.links()[li].name;
      part.mesh = std::move(links[li]);
      part.color = rgba(static_cast<int>(k));
      parts.push_back(std::move(part));
    }
  }
  return parts;
}

void runExport(const ExportArgs& args) {
  if (args.format != "ply" && args.format != "glb" && args.format != "acronym") {
    throw Error("unknown format '" + args.format + "'; use ply, glb or acronym");
  }
  if (!std::filesystem::exists(args.map)) {
    throw Error("map file '" + args.map + "' does not exist; give the path of a task map (.h5)");
  }
  if (args.glyph_size < 0) throw Error("--glyph-size must be a positive length in metres");
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
    options.base_to_palm = baseToPalm(args.frame);
    writeAcronym(args.output, map, options);
  } else {
    ExportScene scene = sceneOf(map, args.glyph_size);
    const std::optional<HandModel> hand = mapHand(map, args.frame.hand, "taskmap export");
    if (hand) scene.parts = handParts(map, *hand);
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
