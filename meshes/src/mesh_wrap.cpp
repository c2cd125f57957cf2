// Closing open surfaces by 3D alpha wrapping (CGAL::alpha_wrap_3, CGAL >= 5.5). Kept apart from
// mesh_repair.cpp: the wrapper's templates are heavy to compile.
#include <array>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/alpha_wrap_3.h>

#include "mesh_soup.hpp"

namespace taskmap::detail {

MeshSoup alphaWrap(const MeshSoup& soup, double alpha, double offset, const std::string& what) {
  using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Point = Kernel::Point_3;
  if (!(alpha > 0) || !(offset > 0))
    throw Error(what + ": alpha wrapping needs a positive alpha and offset");
  std::vector<Point> points;
  std::vector<std::array<std::size_t, 3>> faces;
  soupArrays(soup, &points, &faces);
  CGAL::Surface_mesh<Point> wrap;
  try {
    CGAL::alpha_wrap_3(points, faces, alpha, offset, wrap);
  } catch (const std::exception& e) {
    throw Error(what + ": alpha wrapping failed: " + e.what());
  }
  MeshSoup out;
  std::vector<int> index(wrap.number_of_vertices() + wrap.number_of_removed_vertices(), -1);
  for (auto v : wrap.vertices()) {
    index[v.idx()] = static_cast<int>(out.points.size());
    const Point& p = wrap.point(v);
    out.points.emplace_back(p.x(), p.y(), p.z());
  }
  for (auto f : wrap.faces()) {
    std::array<int, 3> tri{};
    int c = 0;
    for (auto v : CGAL::vertices_around_face(wrap.halfedge(f), wrap)) {
      if (c < 3) tri[static_cast<std::size_t>(c)] = index[v.idx()];
      ++c;
    }
    if (c != 3) throw Error(what + ": alpha wrapping returned a non-triangular face");
    out.faces.push_back(tri);
  }
  if (out.faces.empty()) throw Error(what + ": alpha wrapping returned an empty surface");
  return out;
}

}  // namespace taskmap::detail
