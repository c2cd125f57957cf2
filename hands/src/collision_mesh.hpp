#pragma once
// Private to hands: a URDF <mesh> collision element as convex shapes. Each connected part of
// the file (meshes' mesh_parts.hpp) becomes its qhull hull, or, when it is clearly non-convex
// and the sidecar allows it, the pieces of an exact convex decomposition (meshes'
// convex_pieces.hpp).
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "taskmap/hands/hand_model.hpp"
#include "taskmap/meshes/convex_hull.hpp"
#include "taskmap/meshes/convex_pieces.hpp"

namespace taskmap::detail {

/// Sidecar "collision" (meshes/hands/README.md): how non-convex mesh parts are handled, the
/// options of meshes' convexPieces (decompose, max_pieces, max_faces, wrap, convex_tolerance).
using CollisionOptions = ConvexPiecesOptions;

/// Reads the optional "collision" object of a parsed sidecar; `where` prefixes errors.
CollisionOptions collisionOptionsOf(const nlohmann::json& sidecar, const std::string& where);

/// The convex pieces of one connected part and how they were made (info.link, info.file and
/// info.first_shape are left for the caller).
struct PartShapes {
  std::vector<PointHull> pieces;  ///< hull vertices and volume of each piece
  CollisionMeshInfo info;         ///< how the part was converted
};

/// Loads mesh `file` (relative to the model file, or file://, or package://) with assimp,
/// scaled, in the file's frame, and converts each connected part with meshes' convexPieces.
/// Throws Error naming the model ("<format> '<urdf_path>'", format "URDF" or "MJCF"), link and
/// file on an unreadable mesh or one with no part of 4 or more vertices.
std::vector<PartShapes> collisionMeshShapes(const std::string& file, const Eigen::Vector3d& scale,
                                            const std::string& urdf_path, const std::string& link,
                                            const CollisionOptions& options,
                                            const std::string& format = "URDF");

}  // namespace taskmap::detail
