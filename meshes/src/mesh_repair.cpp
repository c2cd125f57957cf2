// Validation and repair of a triangle soup into a closed, manifold, outward solid (CGAL).
// CGAL stays in this file (and the generator) to keep compile times down.
#include <algorithm>
#include <cmath>
#include <map>
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

std::uint64_t edgeKey(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
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

/// Drops faces with a repeated vertex and repeated faces. Returns (degenerate, duplicate).
std::pair<std::size_t, std::size_t> dropBadFaces(MeshSoup* soup) {
  std::size_t degenerate = 0, duplicate = 0;
  std::map<std::array<int, 3>, int> seen;
  std::vector<std::array<int, 3>> kept;
  kept.reserve(soup->faces.size());
  for (const auto& f : soup->faces) {
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) {
      ++degenerate;
      continue;
    }
    std::array<int, 3> key = f;
    std::sort(key.begin(), key.end());
    if (!seen.emplace(key, 1).second) {
      ++duplicate;
      continue;
    }
    kept.push_back(f);
  }
  soup->faces = std::move(kept);
  return {degenerate, duplicate};
}

/// Welds border vertices closer than tol (union-find over a hash grid). Returns the count.
std::size_t weldBorderVertices(MeshSoup* soup, const std::vector<int>& border, double tol) {
  std::vector<int> parent(soup->points.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  struct CellHash {
    std::size_t operator()(const Eigen::Vector3i& c) const {
      return static_cast<std::size_t>(c.x()) * 73856093u ^
             static_cast<std::size_t>(c.y()) * 19349663u ^
             static_cast<std::size_t>(c.z()) * 83492791u;
    }
  };
  struct CellEq {
    bool operator()(const Eigen::Vector3i& a, const Eigen::Vector3i& b) const { return a == b; }
  };
  std::unordered_map<Eigen::Vector3i, std::vector<int>, CellHash, CellEq> grid;
  auto cellOf = [&](const Eigen::Vector3d& p) {
    return Eigen::Vector3i(static_cast<int>(std::floor(p.x() / tol)),
                           static_cast<int>(std::floor(p.y() / tol)),
                           static_cast<int>(std::floor(p.z() / tol)));
  };
  std::size_t welded = 0;
  for (int v : border) {
    const Eigen::Vector3d& p = soup->points[v];
    const Eigen::Vector3i c = cellOf(p);
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          auto it = grid.find(c + Eigen::Vector3i(dx, dy, dz));
          if (it == grid.end()) continue;
          for (int w : it->second) {
            if ((soup->points[w] - p).norm() <= tol) {
              const int rv = find(v), rw = find(w);
              if (rv != rw) {
                parent[rv] = rw;
                ++welded;
              }
            }
          }
        }
      }
    }
    grid[c].push_back(v);
  }
  if (welded == 0) return 0;
  for (auto& f : soup->faces) {
    for (int& v : f) v = find(v);
  }
  return welded;
}

/// Removes points no face references (left by welding, or unused in the file).
void dropUnusedPoints(MeshSoup* soup) {
  std::vector<int> remap(soup->points.size(), -1);
  std::vector<Eigen::Vector3d> points;
  for (auto& f : soup->faces) {
    for (int& v : f) {
      if (remap[v] < 0) {
        remap[v] = static_cast<int>(points.size());
        points.push_back(soup->points[v]);
      }
      v = remap[v];
    }
  }
  soup->points = std::move(points);
}

double signedVolume(const MeshSoup& soup) {
  double v = 0;
  for (const auto& f : soup.faces) {
    v += soup.points[f[0]].dot(soup.points[f[1]].cross(soup.points[f[2]]));
  }
  return v / 6.0;
}

/// Orientation of a face as its vertex cycle rotated so that the smallest index comes first.
std::array<int, 3> canonicalCycle(std::array<int, 3> f) {
  while (f[0] > f[1] || f[0] > f[2]) std::rotate(f.begin(), f.begin() + 1, f.end());
  return f;
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

SolidResult makeSolidImpl(MeshSoup soup, const std::string& what, bool repair) {
  SolidResult result;
  auto refuse = [&](const std::string& defect) { throw Error(what + ": " + defect); };
  auto repaired = [&](const std::string& text, const std::string& defect) {
    if (!repair) refuse(defect + " (repair is disabled)");
    result.repairs.push_back(text);
  };

  if (soup.points.empty() || soup.faces.empty()) refuse("mesh has no triangles");
  for (std::size_t i = 0; i < soup.points.size(); ++i) {
    if (!soup.points[i].allFinite()) {
      refuse("vertex " + std::to_string(i) + " has a non-finite coordinate (NaN or infinity)");
    }
  }
  const int n_points = static_cast<int>(soup.points.size());
  for (std::size_t i = 0; i < soup.faces.size(); ++i) {
    for (int v : soup.faces[i]) {
      if (v < 0 || v >= n_points) {
        refuse("face " + std::to_string(i) + " references vertex " + std::to_string(v) +
               " but the mesh has " + plural(soup.points.size(), "vertex"));
      }
    }
  }
  Eigen::Vector3d lo = soup.points[0], hi = soup.points[0];
  for (const auto& p : soup.points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double diagonal = (hi - lo).norm();
  if (!(diagonal > 0)) refuse("all vertices coincide; the mesh encloses no volume");

  if (const std::size_t merged = mergeIdenticalPoints(&soup); merged > 0) {
    repaired("merged " + plural(merged, "duplicate vertex") + " with identical coordinates",
             "mesh has " + plural(merged, "duplicate vertex"));
  }
  const auto [degenerate, duplicate] = dropBadFaces(&soup);
  if (degenerate > 0) {
    repaired("dropped " + plural(degenerate, "degenerate face") + " with a repeated vertex",
             "mesh has " + plural(degenerate, "degenerate face"));
  }
  if (duplicate > 0) {
    repaired("dropped " + plural(duplicate, "duplicate face"),
             "mesh has " + plural(duplicate, "duplicate face"));
  }

  EdgeStats stats = edgeStats(soup);
  if (stats.border > 0 && repair) {
    const double tol = 1e-6 * diagonal;
    const std::size_t welded = weldBorderVertices(&soup, stats.border_vertices, tol);
    if (welded > 0) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.3g", tol);
      result.repairs.push_back("stitched borders: welded " + plural(welded, "border vertex") +
                               " closer than " + buf + " m");
      const auto [degenerate2, duplicate2] = dropBadFaces(&soup);
      if (degenerate2 + duplicate2 > 0) {
        result.repairs.push_back("dropped " + plural(degenerate2 + duplicate2, "face") +
                                 " collapsed by stitching");
      }
      stats = edgeStats(soup);
    }
  }
  if (stats.border > 0) {
    refuse("mesh has " + plural(stats.border, "border edge") + (repair ? " after stitching" : "") +
           "; the object must be closed to sample its volume");
  }
  if (stats.non_manifold > 0) {
    refuse("mesh has " + plural(stats.non_manifold, "non-manifold edge") +
           " (shared by more than two faces); the object must be a manifold solid");
  }

  // Consistent orientation and manifold vertices.
  dropUnusedPoints(&soup);
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
    if (!repair) {
      refuse(stats.misoriented > 0 ? "faces are not consistently oriented (repair is disabled)"
                                   : "mesh has non-manifold vertices (repair is disabled)");
    }
    const std::size_t before = points.size();
    const auto before_polygons = polygons;
    PMP::orient_polygon_soup(points, polygons);
    std::size_t flipped = 0;
    for (std::size_t i = 0; i < polygons.size() && i < before_polygons.size(); ++i) {
      // orient_polygon_soup keeps polygon order and only reverses or re-indexes polygons.
      const auto a = canonicalCycle({int(polygons[i][0] < before ? polygons[i][0] : 0),
                                     int(polygons[i][1] < before ? polygons[i][1] : 0),
                                     int(polygons[i][2] < before ? polygons[i][2] : 0)});
      const auto b = canonicalCycle(
          {int(before_polygons[i][0]), int(before_polygons[i][1]), int(before_polygons[i][2])});
      if (a != b) ++flipped;
    }
    if (points.size() > before) {
      result.repairs.push_back("split " + plural(points.size() - before, "non-manifold vertex"));
    }
    if (stats.misoriented > 0) {
      result.repairs.push_back("reoriented faces consistently (" + plural(flipped, "face") +
                               " changed)");
    }
    if (!PMP::is_polygon_soup_a_polygon_mesh(polygons)) {
      refuse("faces cannot be oriented consistently (non-orientable or non-manifold surface)");
    }
  }
  Surface mesh;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, mesh);
  if (!CGAL::is_closed(mesh)) {
    refuse("mesh is not closed after orienting its faces; the object must be closed");
  }

  // Zero-area faces with distinct vertices (collinear corners).
  std::size_t zero_area = 0;
  for (auto f : mesh.faces()) {
    if (PMP::is_degenerate_triangle_face(f, mesh)) ++zero_area;
  }
  if (zero_area > 0) {
    if (!repair)
      refuse("mesh has " + plural(zero_area, "zero-area face") + " (repair is disabled)");
    const bool all_removed = PMP::remove_degenerate_faces(mesh);
    mesh.collect_garbage();
    if (!all_removed || mesh.is_empty() || !CGAL::is_closed(mesh) ||
        !CGAL::is_valid_polygon_mesh(mesh)) {
      refuse("mesh has " + plural(zero_area, "zero-area face") +
             " that could not be removed while keeping it closed");
    }
    result.repairs.push_back("removed " + plural(zero_area, "zero-area face"));
  }

  const bool self_intersecting = PMP::does_self_intersect(mesh);
  if (self_intersecting) {
    result.warnings.push_back(
        "the surface intersects itself: inside tests unite overlapping parts (positive winding "
        "number), but volume, centre of mass and inertia count overlaps twice");
  }
  std::vector<std::array<int, 3>> before_orient;
  for (auto f : mesh.faces()) {
    std::array<int, 3> tri{};
    int c = 0;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) tri[c++] = int(v.idx());
    before_orient.push_back(canonicalCycle(tri));
  }
  if (!self_intersecting) {
    PMP::orient_to_bound_a_volume(mesh);
  } else {
    MeshSoup tmp = toSoup(mesh);
    if (signedVolume(tmp) < 0) PMP::reverse_face_orientations(mesh);
  }
  std::size_t reversed = 0;
  {
    std::size_t i = 0;
    for (auto f : mesh.faces()) {
      std::array<int, 3> tri{};
      int c = 0;
      for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) tri[c++] = int(v.idx());
      if (canonicalCycle(tri) != before_orient[i++]) ++reversed;
    }
  }
  if (reversed > 0) {
    repaired("reversed " + plural(reversed, "face") + " to point outward",
             "mesh has " + plural(reversed, "inward-facing face"));
  }

  MeshSoup out = toSoup(mesh);
  const double volume = signedVolume(out);
  if (!(volume > 1e-12 * diagonal * diagonal * diagonal)) {
    refuse("mesh encloses zero volume (flat or collapsed); a solid needs positive volume");
  }
  result.mesh.vertices = std::move(out.points);
  result.mesh.faces.reserve(out.faces.size());
  for (const auto& f : out.faces) result.mesh.faces.emplace_back(f[0], f[1], f[2]);
  return result;
}

}  // namespace

SolidResult makeSolid(MeshSoup soup, const std::string& what, bool repair) {
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

}  // namespace taskmap::detail
