#pragma once
// Private to meshes: a URDF <mesh> collision element as convex shapes. Each connected part of
// the file becomes its qhull hull, or, when it is clearly non-convex and the sidecar allows it,
// the pieces of an exact convex decomposition (convex_decomposition.hpp).
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "convex_hull.hpp"
#include "mesh_soup.hpp"
#include "taskmap/meshes/hand_model.hpp"

namespace taskmap::detail {

/// Sidecar "collision" (meshes/hands/README.md): how non-convex mesh parts are handled.
struct CollisionOptions {
  bool decompose = true;  ///< decompose non-convex parts (false: every part is its hull)
  int max_pieces = 16;    ///< at most this many convex pieces per part, in [1, 64]
  int max_faces = 600;    ///< parts with more faces are simplified to this many, in [50, 5000]
  /// Decompose the alpha wrap of a part that is not a clean solid (open, non-manifold,
  /// self-intersecting) instead of keeping its hull.
  bool wrap = true;
  /// A part whose volume is at least (1 - convex_tolerance) of its hull's counts as convex.
  double convex_tolerance = 0.03;
};

/// Reads the optional "collision" object of a parsed sidecar; `where` prefixes errors.
CollisionOptions collisionOptionsOf(const nlohmann::json& sidecar, const std::string& where);

/// The convex pieces of one connected part and how they were made (info.link, info.file and
/// info.first_shape are left for the caller).
struct PartShapes {
  std::vector<PointHull> pieces;
  CollisionMeshInfo info;
};

/// One connected part (points and faces, metres) as convex pieces: its qhull hull, or when it
/// is clearly non-convex and options allow, the merged pieces of an exact decomposition (of
/// its alpha wrap when the part is not a clean solid). A failed decomposition keeps the hull
/// and says why in info.note. Throws Error starting with `what` for fewer than 4 points.
PartShapes partShapes(MeshSoup part, const CollisionOptions& o, const std::string& what);

/// Loads mesh `file` (relative to the model file, or file://) with assimp, scaled, in the
/// file's frame, and converts each connected part. Throws Error naming the model ("<format>
/// '<urdf_path>'", format "URDF" or "MJCF"), link and file on an unreadable mesh or one with no
/// part of 4 or more vertices.
std::vector<PartShapes> collisionMeshShapes(const std::string& file, const Eigen::Vector3d& scale,
                                            const std::string& urdf_path, const std::string& link,
                                            const CollisionOptions& options,
                                            const std::string& format = "URDF");

}  // namespace taskmap::detail
