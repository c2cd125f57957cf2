#pragma once
/// @file convex_pieces.hpp
/// A closed solid as convex pieces, for simulators that collide meshes as their convex hulls
/// (MuJoCo, Bullet's convex shapes): the solid's hull when it is nearly convex, else the merged
/// pieces of an exact convex decomposition (CGAL, kept private), of its alpha wrap when the
/// mesh is not a clean solid. The policy of hand link meshes (HandModel::collisionMeshes, each
/// connected part of a mesh file: mesh_parts.hpp).

#include <string>
#include <vector>

#include <Eigen/Core>

#include "taskmap/core/triangle_mesh.hpp"

namespace taskmap {

/// How a solid is cut into convex pieces.
struct ConvexPiecesOptions {
  int max_pieces = 16;             ///< at most this many pieces, in [1, 64]
  int max_faces = 600;             ///< meshes with more faces are simplified first, in [50, 5000]
  double convex_tolerance = 0.03;  ///< volume >= (1 - tolerance) x hull volume: keep the hull
  bool wrap = true;                ///< decompose the alpha wrap of a mesh that is not clean
  bool decompose = true;           ///< false: the hull only ("decomposition off")
  /// Throws Error naming the option when a value is out of range.
  void validate() const;
};

/// The pieces and what they cost in volume.
struct ConvexPieces {
  std::vector<std::vector<Eigen::Vector3d>> pieces;  ///< hull vertices of each piece, metres
  std::vector<double> piece_volumes;                 ///< m^3, one per piece
  double mesh_volume = 0.0;                          ///< volume enclosed by the mesh, m^3
  double hull_volume = 0.0;                          ///< volume of the mesh's convex hull, m^3
  double pieces_volume = 0.0;  ///< summed volume of the pieces, m^3 (overlaps counted twice)
  bool decomposed = false;     ///< true when the pieces come from the decomposition
  bool wrapped = false;        ///< true when the decomposition was of the alpha wrap
  /// Why the hull was kept ("decomposition off", "nearly convex", or the decomposition's
  /// failure: then `failed`), why the alpha wrap was decomposed, or "".
  std::string note;
  bool failed = false;  ///< true when decomposition was wanted but failed (the hull is kept)
  int faces = 0;        ///< faces of the mesh after dropping degenerate and duplicate ones
  int raw_pieces = 0;   ///< pieces of the exact decomposition before merging (0: none)
  /// Relative volume error of the pieces against the mesh, (pieces - mesh) / mesh.
  double volumeError() const;
};

/// Cuts the solid `mesh` (metres) into convex pieces. `what` names the mesh in messages.
/// Never throws for a decomposition that fails (the hull is kept and `note` says why); throws
/// Error naming `what` when the mesh has fewer than 4 points or is flat.
ConvexPieces convexPieces(const TriangleMesh& mesh, const ConvexPiecesOptions& options,
                          const std::string& what);

}  // namespace taskmap
