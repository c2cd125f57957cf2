// The scene of `taskmap export --format ply|glb` (map_scene.hpp).
#include "taskmap/inspect/map_scene.hpp"

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "taskmap/core/error.hpp"
#include "taskmap/hands/shape_mesh.hpp"
#include "taskmap/inspect/map_hand.hpp"
#include "taskmap/inspect/map_summary.hpp"

namespace taskmap {
namespace {

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

}  // namespace

void MapSceneOptions::validate() const {
  if (glyph_size < 0) throw Error("--glyph-size must be a positive length in metres");
}

ExportScene mapScene(const TaskMapData& map, const MapSceneOptions& options,
                     const HandModel* hand) {
  options.validate();
  ExportScene scene = sceneOf(map, options.glyph_size);
  if (hand) scene.parts = handParts(map, *hand);
  return scene;
}

}  // namespace taskmap
