#pragma once
// Private to meshes: exact convex decomposition of a closed triangle mesh (CGAL Nef polyhedra,
// CGAL::convex_decomposition_3), after an optional edge-collapse simplification, and the
// greedy merge that caps the piece count. Policy (when to decompose) in convex_pieces.cpp.
#include <string>
#include <vector>

#include "mesh_soup.hpp"
#include "taskmap/meshes/convex_hull.hpp"

namespace taskmap::detail {

/// Bounds of one decomposition.
struct DecompositionLimits {
  int max_faces = 600;  ///< simplify (edge collapse) meshes with more faces to this many
  int max_raw = 2000;   ///< give up when CGAL returns more pieces than this (before merging)
  int max_pieces = 16;  ///< merge pieces until at most this many remain
};

/// Outcome of decomposeClosedMesh.
struct ConvexPieces {
  std::vector<PointHull> pieces;  ///< convex pieces (hull vertices, volume), metres / m^3
  double mesh_volume = 0.0;       ///< volume enclosed by the (simplified) mesh, m^3
  int faces_used = 0;             ///< faces of the mesh given to CGAL (after simplification)
  int raw_pieces = 0;             ///< pieces CGAL returned before merging
};

/// Decomposes the solid bounded by `soup` (closed, 2-manifold, no self-intersection) into
/// convex pieces. Throws Error starting with `what` and naming the reason when the mesh is not
/// such a solid (after simplification) or CGAL returns more than limits.max_raw pieces.
ConvexPieces decomposeClosedMesh(const MeshSoup& soup, const DecompositionLimits& limits,
                                 const std::string& what);

/// Greedily merges the pair of pieces whose joint hull adds the least volume until at most
/// `max_pieces` remain (pairs whose bounding boxes touch first). Deterministic.
std::vector<PointHull> mergePieces(std::vector<PointHull> pieces, int max_pieces,
                                   const std::string& what);

}  // namespace taskmap::detail
