// A closed solid as convex pieces: the hand meshes' policy (collision_mesh.cpp, partShapes)
// applied to a whole object mesh.
#include "taskmap/meshes/convex_pieces.hpp"

#include "collision_mesh.hpp"
#include "mesh_soup.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {

void ConvexPiecesOptions::validate() const {
  if (max_pieces < 1 || max_pieces > 64)
    throw Error("convex pieces: max_pieces must be in [1, 64], got " + std::to_string(max_pieces));
  if (max_faces < 50 || max_faces > 5000)
    throw Error("convex pieces: max_faces must be in [50, 5000], got " + std::to_string(max_faces));
  if (!(convex_tolerance >= 0.0 && convex_tolerance < 1.0))
    throw Error("convex pieces: convex_tolerance must be in [0, 1)");
}

double ConvexPieces::volumeError() const {
  return mesh_volume > 0.0 ? (pieces_volume - mesh_volume) / mesh_volume : 0.0;
}

ConvexPieces convexPieces(const TriangleMesh& mesh, const ConvexPiecesOptions& options,
                          const std::string& what) {
  options.validate();
  detail::MeshSoup soup;
  soup.points = mesh.vertices;
  soup.faces.reserve(mesh.faces.size());
  for (const auto& f : mesh.faces) soup.faces.push_back({f.x(), f.y(), f.z()});
  detail::CollisionOptions o;
  o.decompose = true;
  o.max_pieces = options.max_pieces;
  o.max_faces = options.max_faces;
  o.wrap = options.wrap;
  o.convex_tolerance = options.convex_tolerance;
  detail::PartShapes part = detail::partShapes(std::move(soup), o, what);
  ConvexPieces out;
  for (auto& p : part.pieces) {
    out.pieces.push_back(std::move(p.vertices));
    out.piece_volumes.push_back(p.volume);
  }
  out.mesh_volume = part.info.mesh_volume;
  out.hull_volume = part.info.hull_volume;
  out.pieces_volume = part.info.pieces_volume;
  out.decomposed = part.info.decomposed;
  out.wrapped = part.info.wrapped;
  out.note = part.info.note;
  return out;
}

}  // namespace taskmap
