// Validation and repair of a triangle soup into a closed, manifold, outward solid (CGAL).
// CGAL stays in this file (and the generator) to keep compile times down.
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <numeric>
#include <string>
#include <unordered_map>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include "mesh_soup.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/text.hpp"

namespace taskmap::detail {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Surface = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

std::string plural(std::size_t n, const std::string& word) {
  if (n == 1) return "1 " + word;
  const std::string suffix = " vertex";
  if (word.size() >= suffix.size() &&
      word.compare(word.size() - suffix.size(), suffix.size(), suffix) == 0) {
    return std::to_string(n) + " " + word.substr(0, word.size() - 2) + "ices";
  }
  if (word == "vertex") return std::to_string(n) + " vertices";
  return std::to_string(n) + " " + word + "s";
}

struct EdgeStats {
  std::size_t border = 0;        ///< undirected edges used by one face
  std::size_t non_manifold = 0;  ///< undirected edges used by more than two faces
  std::size_t misoriented = 0;   ///< two-face edges traversed in the same direction by both
  std::vector<int> border_vertices;
};

EdgeStats edgeStats(const MeshSoup& soup) {
  // For each undirected edge: number of uses and sum of directions (+1 for a<b, -1 otherwise).
  std::unordered_map<std::uint64_t, std::pair<int, int>> edges;
  edges.reserve(soup.faces.size() * 2);
  for (const auto& f : soup.faces) {
    for (int c = 0; c < 3; ++c) {
      const int a = f[c], b = f[(c + 1) % 3];
      auto& e = edges[edgeKey(a, b)];
      e.first += 1;
      e.second += a < b ? 1 : -1;
    }
  }
  EdgeStats stats;
  std::vector<char> on_border(soup.points.size(), 0);
  for (const auto& [key, use] : edges) {
    if (use.first == 1) {
      ++stats.border;
      on_border[key >> 32] = 1;
      on_border[key & 0xffffffffULL] = 1;
    } else if (use.first > 2) {
      ++stats.non_manifold;
    } else if (use.second != 0) {
      ++stats.misoriented;
    }
  }
  for (std::size_t i = 0; i < on_border.size(); ++i) {
    if (on_border[i]) stats.border_vertices.push_back(static_cast<int>(i));
  }
  return stats;
}

double signedVolume(const MeshSoup& soup) {
  double v = 0;
  for (const auto& f : soup.faces) {
    v += soup.points[f[0]].dot(soup.points[f[1]].cross(soup.points[f[2]]));
  }
  return v / 6.0;
}

MeshSoup toSoup(const Surface& mesh) {
  MeshSoup soup;
  std::vector<int> index(mesh.number_of_vertices() + mesh.number_of_removed_vertices(), -1);
  for (auto v : mesh.vertices()) {
    index[v.idx()] = static_cast<int>(soup.points.size());
    const Point& p = mesh.point(v);
    soup.points.emplace_back(p.x(), p.y(), p.z());
  }
  for (auto f : mesh.faces()) {
    std::array<int, 3> tri{};
    int c = 0;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      if (c < 3) tri[c] = index[v.idx()];
      ++c;
    }
    assert(c == 3);
    soup.faces.push_back(tri);
  }
  return soup;
}

/// One validation run: the soup being repaired, what was done, how to report.
struct SolidBuild {
  MeshSoup soup;
  std::string what;
  bool repair = true;
  SolidResult result;
  double diagonal = 0.0;  ///< of the input bounding box, metres

  [[noreturn]] void refuse(const std::string& defect) const { throw Error(what + ": " + defect); }
  [[noreturn]] void refuseOpen(const std::string& defect) const {
    throw OpenSurfaceError(what + ": " + defect);
  }
  /// Records a repair, or refuses `defect` when repair is disabled.
  void repaired(const std::string& text, const std::string& defect) {
    if (!repair) refuse(defect + " (repair is disabled)");
    result.repairs.push_back(text);
  }
};

/// Refuses empty input, non-finite coordinates, bad indices and a point-like mesh.
void checkInput(SolidBuild& b) {
  const MeshSoup& soup = b.soup;
  if (soup.points.empty() || soup.faces.empty()) b.refuse("mesh has no triangles");
  for (std::size_t i = 0; i < soup.points.size(); ++i) {
    if (!soup.points[i].allFinite()) {
      b.refuse("vertex " + std::to_string(i) + " has a non-finite coordinate (NaN or infinity)");
    }
  }
  const int n_points = static_cast<int>(soup.points.size());
  for (std::size_t i = 0; i < soup.faces.size(); ++i) {
    for (int v : soup.faces[i]) {
      if (v < 0 || v >= n_points) {
        b.refuse("face " + std::to_string(i) + " references vertex " + std::to_string(v) +
                 " but the mesh has " + plural(soup.points.size(), "vertex"));
      }
    }
  }
  Eigen::Vector3d lo = soup.points[0], hi = soup.points[0];
  for (const auto& p : soup.points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  b.diagonal = (hi - lo).norm();
  if (!(b.diagonal > 0)) b.refuse("all vertices coincide; the mesh encloses no volume");
}

/// Merges identical points, drops degenerate and repeated faces and opposite-face pairs.
void cleanFaces(SolidBuild& b) {
  if (const std::size_t merged = mergeIdenticalPoints(&b.soup); merged > 0) {
    b.repaired("merged " + plural(merged, "duplicate vertex") + " with identical coordinates",
               "mesh has " + plural(merged, "duplicate vertex"));
  }
  const DroppedFaces d = dropBadFaces(&b.soup);
  if (d.degenerate > 0) {
    b.repaired("dropped " + plural(d.degenerate, "degenerate face") + " with a repeated vertex",
               "mesh has " + plural(d.degenerate, "degenerate face"));
  }
  if (d.duplicate > 0) {
    b.repaired("dropped " + plural(d.duplicate, "duplicate face"),
               "mesh has " + plural(d.duplicate, "duplicate face"));
  }
  if (d.opposite > 0) {
    b.repaired(
        "dropped " + plural(d.opposite, "pair") +
            " of identical faces with opposite orientation (zero-volume fins), both "
            "faces of each",
        "mesh has " + plural(d.opposite, "pair") + " of identical faces with opposite orientation");
  }
}

/// Welds border vertices (when repairing); refuses a surface that stays open or non-manifold.
EdgeStats closeBorders(SolidBuild& b) {
  EdgeStats stats = edgeStats(b.soup);
  if (stats.border > 0 && b.repair) {
    const double tol = 1e-6 * b.diagonal;
    const std::size_t welded = weldBorderVertices(&b.soup, stats.border_vertices, tol);
    if (welded > 0) {
      b.result.repairs.push_back("stitched borders: welded " + plural(welded, "border vertex") +
                                 " closer than " + shortNumber(tol) + " m");
      const DroppedFaces d = dropBadFaces(&b.soup);
      if (d.degenerate + d.duplicate + 2 * d.opposite > 0) {
        b.result.repairs.push_back("dropped " +
                                   plural(d.degenerate + d.duplicate + 2 * d.opposite, "face") +
                                   " collapsed by stitching");
      }
      stats = edgeStats(b.soup);
    }
  }
  if (stats.border > 0) {
    b.refuseOpen("mesh has " + plural(stats.border, "border edge") +
                 (b.repair ? " after stitching" : "") +
                 "; the object must be closed to sample its volume");
  }
  if (stats.non_manifold > 0) {
    b.refuseOpen("mesh has " + plural(stats.non_manifold, "non-manifold edge") +
                 " (shared by more than two faces); the object must be a manifold solid");
  }
  return stats;
}

/// Orients the soup consistently (splitting non-manifold vertices) into a closed surface.
Surface orientedSurface(SolidBuild& b, const EdgeStats& stats) {
  dropUnusedPoints(&b.soup);
  const MeshSoup& soup = b.soup;
  std::vector<std::vector<std::size_t>> polygons(soup.faces.size());
  for (std::size_t i = 0; i < soup.faces.size(); ++i) {
    polygons[i] = {static_cast<std::size_t>(soup.faces[i][0]),
                   static_cast<std::size_t>(soup.faces[i][1]),
                   static_cast<std::size_t>(soup.faces[i][2])};
  }
  std::vector<Point> points;
  points.reserve(soup.points.size());
  for (const auto& p : soup.points) points.emplace_back(p.x(), p.y(), p.z());
  if (!PMP::is_polygon_soup_a_polygon_mesh(polygons)) {
    if (!b.repair) {
      b.refuse(stats.misoriented > 0 ? "faces are not consistently oriented (repair is disabled)"
                                     : "mesh has non-manifold vertices (repair is disabled)");
    }
    const std::size_t before = points.size();
    const auto before_polygons = polygons;
    PMP::orient_polygon_soup(points, polygons);
    std::size_t flipped = 0;
    for (std::size_t i = 0; i < polygons.size() && i < before_polygons.size(); ++i) {
      // orient_polygon_soup keeps polygon order and only reverses or re-indexes polygons.
      const auto x = canonicalCycle({int(polygons[i][0] < before ? polygons[i][0] : 0),
                                     int(polygons[i][1] < before ? polygons[i][1] : 0),
                                     int(polygons[i][2] < before ? polygons[i][2] : 0)});
      const auto y = canonicalCycle(
          {int(before_polygons[i][0]), int(before_polygons[i][1]), int(before_polygons[i][2])});
      if (x != y) ++flipped;
    }
    if (points.size() > before) {
      b.result.repairs.push_back("split " + plural(points.size() - before, "non-manifold vertex"));
    }
    if (stats.misoriented > 0) {
      b.result.repairs.push_back("reoriented faces consistently (" + plural(flipped, "face") +
                                 " changed)");
    }
    if (!PMP::is_polygon_soup_a_polygon_mesh(polygons)) {
      b.refuseOpen(
          "faces cannot be oriented consistently (non-orientable or non-manifold surface)");
    }
  }
  Surface mesh;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, mesh);
  if (!CGAL::is_closed(mesh)) {
    b.refuseOpen("mesh is not closed after orienting its faces; the object must be closed");
  }
  return mesh;
}

/// Removes zero-area faces with distinct vertices (collinear corners), keeping it closed.
void removeZeroAreaFaces(SolidBuild& b, Surface& mesh) {
  std::size_t zero_area = 0;
  for (auto f : mesh.faces()) {
    if (PMP::is_degenerate_triangle_face(f, mesh)) ++zero_area;
  }
  if (zero_area == 0) return;
  if (!b.repair)
    b.refuse("mesh has " + plural(zero_area, "zero-area face") + " (repair is disabled)");
  const bool all_removed = PMP::remove_degenerate_faces(mesh);
  mesh.collect_garbage();
  if (!all_removed || mesh.is_empty() || !CGAL::is_closed(mesh) ||
      !CGAL::is_valid_polygon_mesh(mesh)) {
    b.refuse("mesh has " + plural(zero_area, "zero-area face") +
             " that could not be removed while keeping it closed");
  }
  b.result.repairs.push_back("removed " + plural(zero_area, "zero-area face"));
}

std::vector<std::array<int, 3>> faceCycles(const Surface& mesh) {
  std::vector<std::array<int, 3>> out;
  for (auto f : mesh.faces()) {
    std::array<int, 3> tri{};
    int c = 0;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) tri[c++] = int(v.idx());
    out.push_back(canonicalCycle(tri));
  }
  return out;
}

/// Orients the closed surface outward (warning about self-intersections).
void orientOutward(SolidBuild& b, Surface& mesh) {
  const bool self_intersecting = PMP::does_self_intersect(mesh);
  if (self_intersecting) {
    b.result.warnings.push_back(
        "the surface intersects itself: inside tests unite overlapping parts (positive winding "
        "number), but volume, centre of mass and inertia count overlaps twice");
  }
  const std::vector<std::array<int, 3>> before_orient = faceCycles(mesh);
  if (!self_intersecting) {
    PMP::orient_to_bound_a_volume(mesh);
  } else {
    MeshSoup tmp = toSoup(mesh);
    if (signedVolume(tmp) < 0) PMP::reverse_face_orientations(mesh);
  }
  const std::vector<std::array<int, 3>> after = faceCycles(mesh);
  std::size_t reversed = 0;
  for (std::size_t i = 0; i < after.size(); ++i) reversed += after[i] != before_orient[i];
  if (reversed > 0) {
    b.repaired("reversed " + plural(reversed, "face") + " to point outward",
               "mesh has " + plural(reversed, "inward-facing face"));
  }
}

SolidResult makeSolidImpl(MeshSoup soup, const std::string& what, bool repair) {
  SolidBuild b{std::move(soup), what, repair, {}, 0.0};
  checkInput(b);
  cleanFaces(b);
  // A mesh collapsed onto a plane (e.g. a box whose thickness is below float precision at its
  // coordinates) may lose every face here; CGAL must not see an empty surface.
  const auto refuseEmpty = [&b] {
    if (b.soup.faces.empty())
      b.refuse(
          "no faces are left after dropping degenerate, duplicate and opposite faces (the "
          "mesh is flat or collapsed); a solid needs positive volume");
  };
  refuseEmpty();
  const EdgeStats stats = closeBorders(b);
  refuseEmpty();
  Surface mesh = orientedSurface(b, stats);
  removeZeroAreaFaces(b, mesh);
  orientOutward(b, mesh);

  MeshSoup out = toSoup(mesh);
  const double volume = signedVolume(out);
  if (!(volume > 1e-12 * b.diagonal * b.diagonal * b.diagonal)) {
    b.refuse("mesh encloses zero volume (flat or collapsed); a solid needs positive volume");
  }
  b.result.mesh.vertices = std::move(out.points);
  b.result.mesh.faces.reserve(out.faces.size());
  for (const auto& f : out.faces) b.result.mesh.faces.emplace_back(f[0], f[1], f[2]);
  return std::move(b.result);
}

}  // namespace

double soupVolume(const MeshSoup& soup) {
  if (soup.points.empty()) return 0.0;
  Eigen::Vector3d lo = soup.points[0], hi = soup.points[0];
  for (const auto& p : soup.points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Eigen::Vector3d c = 0.5 * (lo + hi);
  double v = 0;
  for (const auto& f : soup.faces) {
    v += (soup.points[f[0]] - c).dot((soup.points[f[1]] - c).cross(soup.points[f[2]] - c));
  }
  return v / 6.0;
}

namespace {

SolidResult guardedMakeSolid(MeshSoup soup, const std::string& what, bool repair) {
  try {
    return makeSolidImpl(std::move(soup), what, repair);
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw Error(what + ": out of memory while validating the mesh");
  } catch (const std::exception& e) {
    throw Error(what + ": geometry validation failed: " + e.what());
  } catch (...) {
    throw Error(what + ": geometry validation failed");
  }
}

std::string metres(double v) {
  return shortNumber(v) + " m";
}

/// Replaces an open surface by its alpha wrap and validates that; reports the volume change.
SolidResult wrapSolid(const MeshSoup& input, const std::string& what, const SolidOptions& o) {
  Eigen::Vector3d lo = input.points[0], hi = input.points[0];
  for (const auto& p : input.points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double diagonal = (hi - lo).norm();
  const double alpha = o.wrap_alpha > 0 ? o.wrap_alpha : diagonal / 100.0;
  const double offset = o.wrap_offset > 0 ? o.wrap_offset : diagonal / 3000.0;
  MeshSoup cleaned = input;
  mergeIdenticalPoints(&cleaned);
  dropBadFaces(&cleaned);
  const double open_volume = std::abs(soupVolume(cleaned));
  SolidResult r = guardedMakeSolid(alphaWrap(cleaned, alpha, offset, what), what, true);
  MeshSoup wrapped{r.mesh.vertices, {}};
  for (const auto& t : r.mesh.faces) wrapped.faces.push_back({t[0], t[1], t[2]});
  const double volume = soupVolume(wrapped);
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "closed the open surface by alpha wrapping (alpha %s, offset %s): %zu faces, "
                "volume %.6g m^3 vs %.6g m^3 enclosed by the open input (%+.1f%%)",
                metres(alpha).c_str(), metres(offset).c_str(), r.mesh.faces.size(), volume,
                open_volume, open_volume > 0 ? 100.0 * (volume - open_volume) / open_volume : 0.0);
  r.repairs.insert(r.repairs.begin(), buf);
  return r;
}

}  // namespace

SolidResult makeSolid(MeshSoup soup, const std::string& what, const SolidOptions& options) {
  MeshSoup input;
  if (options.wrap) input = soup;
  try {
    return guardedMakeSolid(std::move(soup), what, options.repair);
  } catch (const OpenSurfaceError& e) {
    if (!options.wrap)
      throw Error(std::string(e.what()) +
                  "; `--repair wrap` (load option wrap) closes it by alpha wrapping");
  }
  return wrapSolid(input, what, options);
}

}  // namespace taskmap::detail
