// Exact convex decomposition of a closed triangle mesh: the soup becomes a CGAL Surface_mesh
// (oriented outward), is simplified by edge collapse when it has more faces than the limit,
// is converted to an exact Nef polyhedron and split by CGAL::convex_decomposition_3 into convex
// volumes; each volume becomes the qhull hull of its vertices. Kept apart from the other CGAL
// users of meshes: Nef polyhedra are heavy to compile.
#include "convex_decomposition.hpp"

// GCC 12 reports CGAL's own Reflex_vertex_searcher (convex_decomposition_3.h) as possibly
// uninitialised once inlined here; the warning is in CGAL's code, not ours.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include <array>
#include <cstddef>
#include <vector>

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Nef_polyhedron_3.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polyhedron_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Bounded_normal_change_filter.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>
#include <CGAL/convex_decomposition_3.h>

namespace taskmap::detail {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Inexact = CGAL::Exact_predicates_inexact_constructions_kernel;
using Exact = CGAL::Exact_predicates_exact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Inexact::Point_3>;
using ExactMesh = CGAL::Surface_mesh<Exact::Point_3>;
using Nef = CGAL::Nef_polyhedron_3<Exact>;
using ExactPolyhedron = CGAL::Polyhedron_3<Exact>;

/// The soup as an outward-oriented closed surface mesh; throws Error when it is not closed.
Mesh closedMesh(const MeshSoup& soup, const std::string& what) {
  std::vector<Inexact::Point_3> points;
  std::vector<std::array<std::size_t, 3>> faces;
  soupArrays(soup, &points, &faces);
  if (!PMP::orient_polygon_soup(points, faces))
    throw Error(what + " is not 2-manifold (edges shared by more than two faces)");
  Mesh mesh;
  PMP::polygon_soup_to_polygon_mesh(points, faces, mesh);
  if (mesh.is_empty() || !CGAL::is_closed(mesh))
    throw Error(what + " is not closed (it has border edges)");
  if (!PMP::is_outward_oriented(mesh)) PMP::reverse_face_orientations(mesh);
  return mesh;
}

/// The same surface with exact coordinates.
ExactMesh exactCopy(const Mesh& mesh) {
  ExactMesh out;
  std::vector<ExactMesh::Vertex_index> index(mesh.number_of_vertices() +
                                             mesh.number_of_removed_vertices());
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    index[v.idx()] = out.add_vertex(Exact::Point_3(p.x(), p.y(), p.z()));
  }
  for (auto f : mesh.faces()) {
    std::vector<ExactMesh::Vertex_index> cycle;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
      cycle.push_back(index[v.idx()]);
    out.add_face(cycle);
  }
  return out;
}

/// The convex volumes of a decomposed Nef polyhedron as hulls (flat slivers skipped; CGAL
/// declares the shell conversion non-const).
std::vector<PointHull> volumesOf(Nef& nef, const std::string& what) {
  std::vector<PointHull> pieces;
  auto vol = nef.volumes_begin();
  for (++vol; vol != nef.volumes_end(); ++vol) {  // the first volume is the outside
    if (!vol->mark()) continue;
    ExactPolyhedron poly;
    nef.convert_inner_shell_to_polyhedron(vol->shells_begin(), poly);
    std::vector<Eigen::Vector3d> pts;
    for (auto v = poly.vertices_begin(); v != poly.vertices_end(); ++v)
      pts.emplace_back(CGAL::to_double(v->point().x()), CGAL::to_double(v->point().y()),
                       CGAL::to_double(v->point().z()));
    try {
      pieces.push_back(convexHull(pts, what + " (a convex piece)"));
    } catch (const Error&) {
      // A piece with no volume (rounding to double flattened it) encloses nothing.
    }
  }
  return pieces;
}

}  // namespace

ConvexPieces decomposeClosedMesh(const MeshSoup& soup, const DecompositionLimits& limits,
                                 const std::string& what) {
  Mesh mesh = closedMesh(soup, what);
  if (static_cast<int>(mesh.number_of_faces()) > limits.max_faces) {
    namespace SMS = CGAL::Surface_mesh_simplification;
    // A closed triangle mesh has 3/2 edges per face.
    SMS::Count_stop_predicate<Mesh> stop(static_cast<std::size_t>(limits.max_faces) * 3 / 2);
    SMS::edge_collapse(mesh, stop);
    mesh.collect_garbage();
    if (PMP::does_self_intersect(mesh)) {
      // Thin parts (a scissors' blade, a mug's wall) fold through each other when collapsed
      // freely; again from the original, refusing collapses that flip a face's normal.
      mesh = closedMesh(soup, what);
      SMS::edge_collapse(mesh, stop,
                         CGAL::parameters::filter(SMS::Bounded_normal_change_filter<>()));
      mesh.collect_garbage();
    }
  }
  if (PMP::does_self_intersect(mesh))
    throw Error(
        what + " intersects itself" +
        (static_cast<int>(soup.faces.size()) > limits.max_faces ? " after simplification" : ""));
  ConvexPieces out;
  out.faces_used = static_cast<int>(mesh.number_of_faces());
  out.mesh_volume = PMP::volume(mesh);
  Nef nef(exactCopy(mesh));
  if (!nef.is_simple()) throw Error(what + " does not bound a simple solid");
  CGAL::convex_decomposition_3(nef);
  std::vector<PointHull> pieces = volumesOf(nef, what);
  out.raw_pieces = static_cast<int>(pieces.size());
  if (pieces.empty()) throw Error(what + ": the convex decomposition returned no piece");
  if (out.raw_pieces > limits.max_raw)
    throw Error(what + ": the convex decomposition returned " + std::to_string(out.raw_pieces) +
                " pieces (limit " + std::to_string(limits.max_raw) + ")");
  out.pieces = mergePieces(std::move(pieces), limits.max_pieces, what);
  return out;
}

}  // namespace taskmap::detail
