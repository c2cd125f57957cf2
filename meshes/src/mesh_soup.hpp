#pragma once
/// @file mesh_soup.hpp
/// Private to the meshes stage: a triangle soup as read from a file, and the steps that turn
/// it into a validated solid (import with assimp, repair and validation with CGAL).

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "taskmap/core/triangle_mesh.hpp"

namespace taskmap::detail {

/// Triangles indexing points; may be non-manifold, open, inconsistently oriented.
struct MeshSoup {
  std::vector<Eigen::Vector3d> points;    ///< metres (after scaling)
  std::vector<std::array<int, 3>> faces;  ///< indices into points
};

/// Reads every mesh of the scene in `path` with assimp, applies node transforms and `scale`,
/// and merges vertices with bit-identical coordinates (the OBJ and STL loaders duplicate them
/// per face corner). Throws Error naming the file on unreadable, empty or malformed input.
/// @param format receives the lower-case file extension (e.g. "obj", "stl").
MeshSoup importMeshFile(const std::string& path, double scale, std::string* format);

/// Merges points with bit-identical coordinates, remapping faces. Returns the number merged.
std::size_t mergeIdenticalPoints(MeshSoup* soup);

/// Result of turning a soup into a solid.
struct SolidResult {
  TriangleMesh mesh;                  ///< closed, manifold, outward oriented
  std::vector<std::string> repairs;   ///< repairs done, human readable
  std::vector<std::string> warnings;  ///< accepted defects (for example self-intersections)
};

/// Validates (and, if `repair`, repairs) a soup into a closed outward solid with CGAL.
/// `what` names the source in error messages (for example "mesh file 'x.obj'").
/// Throws Error naming `what` and the defect when no closed solid results.
SolidResult makeSolid(MeshSoup soup, const std::string& what, bool repair);

}  // namespace taskmap::detail
