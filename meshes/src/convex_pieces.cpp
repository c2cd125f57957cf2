// A closed solid as convex pieces (convex_pieces.hpp): the solid's qhull hull or, when clearly
// non-convex (volume below (1 - convex_tolerance) of the hull's), the merged pieces of an exact
// convex decomposition (of its alpha wrap when the mesh is not a clean solid); a failed
// decomposition falls back to the hull and says why. The policy of every connected part of a
// hand's link meshes and of whole object meshes.
#include "taskmap/meshes/convex_pieces.hpp"

#include <cmath>
#include <map>

#include <Eigen/Geometry>

#include "convex_decomposition.hpp"
#include "mesh_soup.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/meshes/convex_hull.hpp"

namespace taskmap {
namespace {

using detail::MeshSoup;

/// True when every edge is used once in each direction (closed, consistently oriented).
bool closedOriented(const MeshSoup& soup) {
  std::map<std::pair<int, int>, int> uses;
  for (const auto& f : soup.faces)
    for (int c = 0; c < 3; ++c) ++uses[{f[static_cast<std::size_t>(c)], f[(c + 1) % 3]}];
  for (const auto& [e, n] : uses) {
    const auto it = uses.find({e.second, e.first});
    if (n != 1 || it == uses.end() || it->second != 1) return false;
  }
  return !soup.faces.empty();
}

/// Decomposes `part`; when it is not a clean solid (open, non-manifold, self-intersecting) and
/// options allow, decomposes its alpha wrap instead (alpha = diagonal / 30, offset = diagonal /
/// 1000: a closed surface just outside the part). Throws Error when neither works.
detail::ConvexPieces decomposeOrWrap(const MeshSoup& part, const ConvexPiecesOptions& o,
                                     const std::string& what, ConvexPieces* out) {
  detail::DecompositionLimits limits;
  limits.max_pieces = o.max_pieces;
  limits.max_faces = o.max_faces;
  try {
    return detail::decomposeClosedMesh(part, limits, what);
  } catch (const Error& e) {
    if (!o.wrap) throw;
    Eigen::AlignedBox3d box;
    for (const auto& p : part.points) box.extend(p);
    const double d = box.diagonal().norm();
    const MeshSoup wrapped = detail::alphaWrap(part, d / 30.0, d / 1000.0, what);
    try {
      detail::ConvexPieces pieces = detail::decomposeClosedMesh(wrapped, limits, "its alpha wrap");
      out->wrapped = true;
      out->note = std::string(e.what()) + "; decomposed its alpha wrap";
      return pieces;
    } catch (const Error& e2) {
      throw Error(std::string(e.what()) + "; " + e2.what());
    }
  }
}

}  // namespace

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
  MeshSoup part;
  part.points = mesh.vertices;
  part.faces.reserve(mesh.faces.size());
  for (const auto& f : mesh.faces) part.faces.push_back({f.x(), f.y(), f.z()});
  PointHull hull = convexHull(part.points, what);
  detail::dropBadFaces(&part);
  ConvexPieces out;
  out.faces = static_cast<int>(part.faces.size());
  out.hull_volume = hull.volume;
  const bool closed = closedOriented(part);
  out.mesh_volume = closed ? std::abs(detail::soupVolume(part)) : 0.0;
  const bool convex = out.mesh_volume >= (1.0 - options.convex_tolerance) * hull.volume;
  if (!options.decompose || (closed && convex)) {
    out.note = !options.decompose ? "decomposition off" : "nearly convex";
  } else {
    try {
      detail::ConvexPieces d = decomposeOrWrap(part, options, what, &out);
      out.raw_pieces = d.raw_pieces;
      for (auto& p : d.pieces) {
        out.pieces.push_back(std::move(p.vertices));
        out.piece_volumes.push_back(p.volume);
      }
      out.decomposed = true;
    } catch (const Error& e) {
      out.note = std::string(e.what()) + "; its convex hull is used";
      out.failed = true;
    }
  }
  if (out.pieces.empty()) {
    out.pieces.push_back(std::move(hull.vertices));
    out.piece_volumes.push_back(hull.volume);
  }
  for (const double v : out.piece_volumes) out.pieces_volume += v;
  return out;
}

}  // namespace taskmap
