#pragma once
/// @file map_scene.hpp
/// The scene `taskmap export --format ply|glb` writes of a map: the object mesh, palm positions
/// coloured by cluster, a hand glyph per cluster representative and the hand's links posed by
/// each representative (meshes' ExportScene; write it with exportScene).

#include "taskmap/hands/hand_model.hpp"
#include "taskmap/mapstore/task_map_data.hpp"
#include "taskmap/meshes/mesh_export.hpp"

namespace taskmap {

/// How mapScene draws a map.
struct MapSceneOptions {
  /// Finger length of the hand glyphs, metres; 0: min(rho, a fifth of the object size), 0.03
  /// when that is not positive.
  double glyph_size = 0.0;
  /// Throws Error("--glyph-size must be a positive length in metres") when glyph_size < 0.
  void validate() const;
};

/// The map as a scene in the object frame (metres): object mesh, palm positions as points
/// coloured by cluster (clusterColor; outliers grey), a glyph at each cluster representative
/// (fingers along the palm's +z approach axis) and, with a hand (the map's: same actuated
/// joints), one part per link with collision shapes posed by each representative's stored
/// pose and joint values, named "cluster<k>_<link>", in the cluster colour.
ExportScene mapScene(const TaskMapData& map, const MapSceneOptions& options = {},
                     const HandModel* hand = nullptr);

}  // namespace taskmap
