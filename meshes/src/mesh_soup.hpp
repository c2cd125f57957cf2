#pragma once
/// @file mesh_soup.hpp
/// Private to the meshes stage: a triangle soup as read from a file, and the steps that turn
/// it into a validated solid (import with assimp, repair and validation with CGAL).

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "taskmap/core/error.hpp"
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

/// The soup as polygon-soup arrays for CGAL (Point: any kernel's Point_3, built from x, y, z).
template <class Point>
void soupArrays(const MeshSoup& soup, std::vector<Point>* points,
                std::vector<std::array<std::size_t, 3>>* faces) {
  points->reserve(soup.points.size());
  for (const auto& p : soup.points) points->emplace_back(p.x(), p.y(), p.z());
  faces->reserve(soup.faces.size());
  for (const auto& f : soup.faces)
    faces->push_back({static_cast<std::size_t>(f[0]), static_cast<std::size_t>(f[1]),
                      static_cast<std::size_t>(f[2])});
}

/// Key of the undirected edge (a, b): the smaller index in the high 32 bits.
inline std::uint64_t edgeKey(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}

/// Orientation of a face as its vertex cycle rotated so that the smallest index comes first.
inline std::array<int, 3> canonicalCycle(std::array<int, 3> f) {
  while (f[0] > f[1] || f[0] > f[2]) std::rotate(f.begin(), f.begin() + 1, f.end());
  return f;
}

/// What dropBadFaces removed.
struct DroppedFaces {
  std::size_t degenerate = 0;  ///< faces with a repeated vertex
  std::size_t duplicate = 0;   ///< repeats of a face in the same orientation
  std::size_t opposite = 0;    ///< pairs of identical faces with opposite orientation
};

/// Drops faces with a repeated vertex and repeated faces; of identical faces with opposite
/// orientation keeps the one the surrounding surface asks for, or neither (a fin). In
/// mesh_faces.cpp.
DroppedFaces dropBadFaces(MeshSoup* soup);

/// Welds the border vertices closer than tol (metres); returns how many were welded.
std::size_t weldBorderVertices(MeshSoup* soup, const std::vector<int>& border, double tol);

/// Removes points no face references.
void dropUnusedPoints(MeshSoup* soup);

/// Result of turning a soup into a solid.
struct SolidResult {
  TriangleMesh mesh;                  ///< closed, manifold, outward oriented
  std::vector<std::string> repairs;   ///< repairs done, human readable
  std::vector<std::string> warnings;  ///< accepted defects (for example self-intersections)
};

/// How makeSolid may change the input.
struct SolidOptions {
  bool repair = true;        ///< merge, drop, stitch, orient (see MeshLoadOptions::repair)
  bool wrap = false;         ///< close an open or non-manifold surface by alpha wrapping
  double wrap_alpha = 0.0;   ///< metres; 0: diagonal of the bounding box / 100
  double wrap_offset = 0.0;  ///< metres; 0: diagonal of the bounding box / 3000
};

/// Thrown inside makeSolid when the surface is open or non-manifold (what wrapping fixes).
class OpenSurfaceError : public Error {
 public:
  using Error::Error;
};

/// Validates (and, if `options.repair`, repairs) a soup into a closed outward solid with
/// CGAL; with `options.wrap`, a surface that stays open is replaced by its alpha wrap.
/// `what` names the source in error messages (for example "mesh file 'x.obj'").
/// Throws Error naming `what` and the defect when no closed solid results.
SolidResult makeSolid(MeshSoup soup, const std::string& what, const SolidOptions& options);

/// Alpha wrap (CGAL::alpha_wrap_3) of the soup's triangles: a closed, manifold, outward surface
/// at distance `offset` (metres) outside them that enters no cavity narrower than about
/// `alpha` (metres). Throws Error naming `what` when wrapping fails.
MeshSoup alphaWrap(const MeshSoup& soup, double alpha, double offset, const std::string& what);

/// Signed volume of a soup's triangles about the centre of its bounding box, m^3 (the
/// enclosed volume for a closed outward surface, an estimate for a surface with small holes).
double soupVolume(const MeshSoup& soup);

}  // namespace taskmap::detail
