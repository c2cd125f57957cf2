#pragma once
/// @file mesh_export.hpp
/// Writes a scene of an object mesh, coloured points and small hand glyphs to PLY or binary
/// glTF (GLB) files for MeshLab or Blender. The exporter (assimp) stays private.

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "taskmap/core/triangle_mesh.hpp"

namespace taskmap {

/// File format of exportScene.
enum class SceneFormat {
  kPly,  ///< ASCII PLY: one vertex list (RGBA uchar colours), triangles and one-vertex faces
         ///< (ASCII because assimp 5.2 writes binary PLY colours as floats under a uchar header)
  kGlb,  ///< binary glTF 2.0: one mesh node per part, points as a POINTS primitive
};

/// Parses "ply" or "glb"; throws Error naming the format otherwise.
SceneFormat sceneFormatFromString(const std::string& name);

/// RGBA colour, components in [0, 1].
using Rgba = Eigen::Vector4f;

/// A small hand glyph: a palm plate with three fingers pointing along the palm's +z axis
/// (the approach axis), placed at a pose.
struct SceneGlyph {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< palm frame -> object frame
  Rgba color = Rgba(0.8f, 0.2f, 0.2f, 1.0f);
};

/// A named triangle mesh already in the object frame, e.g. one hand link posed by a grasp.
struct ScenePart {
  std::string name;   ///< node and mesh name (e.g. "cluster0_palm_link")
  TriangleMesh mesh;  ///< metres, object frame, outward faces
  Rgba color = Rgba(0.2f, 0.45f, 0.85f, 1.0f);
};

/// What exportScene writes. Coordinates in metres, object frame.
struct ExportScene {
  std::string name = "taskmap";  ///< scene / root node name
  TriangleMesh object;           ///< the object surface
  Rgba object_color = Rgba(0.75f, 0.75f, 0.75f, 1.0f);
  std::vector<Eigen::Vector3d> points;  ///< e.g. palm positions of the grasps
  std::vector<Rgba> point_colors;       ///< one per point
  std::vector<SceneGlyph> glyphs;       ///< e.g. cluster representatives
  double glyph_size = 0.03;             ///< metres, length of a glyph's fingers; > 0
  std::vector<ScenePart> parts;         ///< e.g. the hand's links at each representative
  /// Throws Error naming the field when sizes disagree, an index is out of range, or a value
  /// is not finite.
  void validate() const;
};

/// The triangle mesh of one hand glyph of the given size (metres) in the palm frame:
/// palm plate in the xy plane, fingers along +z. kGlyphVertices vertices.
TriangleMesh handGlyphMesh(double size);

/// Vertex count of handGlyphMesh (four boxes of 8 vertices).
constexpr int kGlyphVertices = 32;

/// Writes the scene atomically (temporary file beside path, then rename).
/// PLY: the object vertices come first (in order), then the points, then the glyphs; faces
/// are the object triangles, then one one-vertex face per point, then the glyph triangles;
/// every vertex carries an RGBA colour; the parts follow the glyphs. GLB: meshes named
/// "object", "grasps" (points) and "glyphs", then one mesh per part named as the part, each
/// with per-vertex colours and a material of its colour, each in a node of its own name.
/// Throws Error naming the file when it cannot be written.
void exportScene(const std::string& path, const ExportScene& scene, SceneFormat format);

}  // namespace taskmap
