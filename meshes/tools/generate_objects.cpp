// Generates the reference objects of meshes/objects/ (OBJ, metres, closed solids).
// Usage: taskmap_generate_objects OUTPUT_DIR
// Primitives are built as closed, outward-oriented triangle meshes; the mug and the basket are
// real unions/differences computed with CGAL corefinement on an exact kernel, so every object
// is ONE closed manifold solid. Dimensions are documented in meshes/objects/README.md.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <iterator>
#include <numeric>
#include <string>
#include <tuple>
#include <vector>

#include <Eigen/Geometry>

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include "taskmap/core/error.hpp"
#include "taskmap/meshes/mesh_io.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace {

using taskmap::TriangleMesh;
using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using Surface = CGAL::Surface_mesh<Kernel::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

constexpr int kSegments = 64;  ///< segments around every circle

double signedVolume(const TriangleMesh& m) {
  double v = 0;
  for (const auto& f : m.faces) {
    v += m.vertices[f[0]].dot(m.vertices[f[1]].cross(m.vertices[f[2]]));
  }
  return v / 6;
}

void orientOutward(TriangleMesh* m) {
  if (signedVolume(*m) < 0) {
    for (auto& f : m->faces) std::swap(f[1], f[2]);
  }
}

/// Surface of revolution about z of a closed profile (r, z) that starts and ends on the axis
/// (r = 0) and runs counter-clockwise in the (r, z) half-plane.
TriangleMesh revolve(const std::vector<Eigen::Vector2d>& profile, int segments,
                     double phase = 0.0) {
  TriangleMesh m;
  const int n = static_cast<int>(profile.size());
  std::vector<std::vector<int>> ring(n);
  for (int i = 0; i < n; ++i) {
    if (profile[i].x() == 0.0) {
      ring[i].assign(segments, static_cast<int>(m.vertices.size()));
      m.vertices.emplace_back(0, 0, profile[i].y());
      continue;
    }
    for (int j = 0; j < segments; ++j) {
      const double t = phase + 2 * M_PI * j / segments;
      ring[i].push_back(static_cast<int>(m.vertices.size()));
      m.vertices.emplace_back(profile[i].x() * std::cos(t), profile[i].x() * std::sin(t),
                              profile[i].y());
    }
  }
  for (int i = 0; i + 1 < n; ++i) {
    for (int j = 0; j < segments; ++j) {
      const int k = (j + 1) % segments;
      const int a = ring[i][j], b = ring[i][k], c = ring[i + 1][k], d = ring[i + 1][j];
      if (a != b) m.faces.emplace_back(a, b, c);
      if (c != d) m.faces.emplace_back(a, c, d);
    }
  }
  orientOutward(&m);
  return m;
}

TriangleMesh cylinder(double r, double z0, double z1, double phase = 0.0) {
  return revolve({{0, z0}, {r, z0}, {r, z1}, {0, z1}}, kSegments, phase);
}

TriangleMesh sphere(double r, int stacks) {
  std::vector<Eigen::Vector2d> profile;
  for (int i = 0; i <= stacks; ++i) {
    const double phi = M_PI * i / stacks;
    profile.emplace_back(i == 0 || i == stacks ? 0.0 : r * std::sin(phi), -r * std::cos(phi));
  }
  return revolve(profile, kSegments);
}

TriangleMesh box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) {
    m.vertices.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(),
                            i & 4 ? hi.z() : lo.z());
  }
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.faces.emplace_back(q[0], q[1], q[2]);
    m.faces.emplace_back(q[0], q[2], q[3]);
  }
  orientOutward(&m);
  return m;
}

/// Torus in the xz-plane (axis along y) around `center`.
TriangleMesh torusXZ(const Eigen::Vector3d& center, double major, double minor, int tube) {
  TriangleMesh m;
  for (int i = 0; i < kSegments; ++i) {
    const double u = 2 * M_PI * i / kSegments;
    for (int j = 0; j < tube; ++j) {
      const double v = 2 * M_PI * j / tube;
      const double w = major + minor * std::cos(v);
      m.vertices.push_back(center +
                           Eigen::Vector3d(w * std::cos(u), minor * std::sin(v), w * std::sin(u)));
    }
  }
  for (int i = 0; i < kSegments; ++i) {
    for (int j = 0; j < tube; ++j) {
      const int i1 = (i + 1) % kSegments, j1 = (j + 1) % tube;
      const int a = i * tube + j, b = i1 * tube + j, c = i1 * tube + j1, d = i * tube + j1;
      m.faces.emplace_back(a, b, c);
      m.faces.emplace_back(a, c, d);
    }
  }
  orientOutward(&m);
  return m;
}

Surface toSurface(const TriangleMesh& m) {
  Surface s;
  std::vector<Surface::Vertex_index> v;
  for (const auto& p : m.vertices) v.push_back(s.add_vertex(Kernel::Point_3(p.x(), p.y(), p.z())));
  for (const auto& f : m.faces) s.add_face(v[f[0]], v[f[1]], v[f[2]]);
  return s;
}

/// Rounds to float32 coordinates (what assimp reads back) and removes slivers that rounding
/// could fold: caps (an angle above 175 degrees) and edges shorter than 10 micrometres.
TriangleMesh cleanUp(const TriangleMesh& in) {
  using Inexact = CGAL::Exact_predicates_inexact_constructions_kernel;
  CGAL::Surface_mesh<Inexact::Point_3> s;
  std::vector<CGAL::Surface_mesh<Inexact::Point_3>::Vertex_index> v;
  for (const auto& p : in.vertices) {
    v.push_back(s.add_vertex(Inexact::Point_3(float(p.x()), float(p.y()), float(p.z()))));
  }
  for (const auto& f : in.faces) s.add_face(v[f[0]], v[f[1]], v[f[2]]);
  PMP::experimental::remove_almost_degenerate_faces(s, std::cos(175.0 * M_PI / 180.0), 1e6, 1e-5);
  s.collect_garbage();
  TriangleMesh m;
  for (auto vi : s.vertices()) {
    const auto& p = s.point(vi);
    m.vertices.emplace_back(float(p.x()), float(p.y()), float(p.z()));
  }
  for (auto f : s.faces()) {
    Eigen::Vector3i tri;
    int c = 0;
    for (auto vi : CGAL::vertices_around_face(s.halfedge(f), s)) tri[c++] = int(vi.idx());
    m.faces.push_back(tri);
  }
  return m;
}

TriangleMesh toMesh(const Surface& s) {
  TriangleMesh m;
  std::vector<int> index(s.number_of_vertices() + s.number_of_removed_vertices(), -1);
  for (auto v : s.vertices()) {
    index[v.idx()] = static_cast<int>(m.vertices.size());
    const auto& p = s.point(v);
    m.vertices.emplace_back(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
  }
  for (auto f : s.faces()) {
    Eigen::Vector3i tri;
    int c = 0;
    for (auto v : CGAL::vertices_around_face(s.halfedge(f), s)) tri[c++] = index[v.idx()];
    m.faces.push_back(tri);
  }
  return m;
}

enum class Op { kUnion, kDifference };

TriangleMesh boolean(const TriangleMesh& a, const TriangleMesh& b, Op op) {
  Surface sa = toSurface(a), sb = toSurface(b), out;
  const bool ok = op == Op::kUnion ? PMP::corefine_and_compute_union(sa, sb, out)
                                   : PMP::corefine_and_compute_difference(sa, sb, out);
  if (!ok) throw taskmap::Error("corefinement failed");
  return toMesh(out);
}

void check(const TriangleMesh& m, const std::string& name) {
  Surface s;
  std::vector<Surface::Vertex_index> v;
  for (const auto& p : m.vertices) v.push_back(s.add_vertex(Kernel::Point_3(p.x(), p.y(), p.z())));
  for (const auto& f : m.faces) s.add_face(v[f[0]], v[f[1]], v[f[2]]);
  auto fcc = s.add_property_map<Surface::Face_index, std::size_t>("f:cc").first;
  const std::size_t components = PMP::connected_components(s, fcc);
  if (components != 1) {
    throw taskmap::Error(name + ": " + std::to_string(components) + " connected components");
  }
  if (!CGAL::is_closed(s)) throw taskmap::Error(name + ": not closed");
  std::vector<std::pair<Surface::Face_index, Surface::Face_index>> pairs;
  PMP::self_intersections(s, std::back_inserter(pairs));
  for (std::size_t i = 0; i < pairs.size() && i < 6; ++i) {
    for (const auto f : {pairs[i].first, pairs[i].second}) {
      std::fprintf(stderr, "face %u:", unsigned(f.idx()));
      for (auto vi : CGAL::vertices_around_face(s.halfedge(f), s)) {
        std::fprintf(stderr, " %u(%.9g %.9g %.9g)", unsigned(vi.idx()),
                     CGAL::to_double(s.point(vi).x()), CGAL::to_double(s.point(vi).y()),
                     CGAL::to_double(s.point(vi).z()));
      }
      std::fprintf(stderr, "\n");
    }
  }
  if (!pairs.empty()) {
    throw taskmap::Error(name + ": " + std::to_string(pairs.size()) +
                         " pairs of self-intersecting faces after rounding to double");
  }
}

/// Vertices sorted by coordinates, faces rotated to start at their smallest index and sorted:
/// the file does not depend on the order in which corefinement created elements.
TriangleMesh canonical(const TriangleMesh& in) {
  std::vector<int> order(in.vertices.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const auto& p = in.vertices[a];
    const auto& q = in.vertices[b];
    return std::make_tuple(p.x(), p.y(), p.z(), a) < std::make_tuple(q.x(), q.y(), q.z(), b);
  });
  std::vector<int> index(in.vertices.size());
  TriangleMesh out;
  for (std::size_t i = 0; i < order.size(); ++i) {
    index[order[i]] = static_cast<int>(i);
    out.vertices.push_back(in.vertices[order[i]]);
  }
  for (const auto& f : in.faces) {
    Eigen::Vector3i g(index[f[0]], index[f[1]], index[f[2]]);
    while (g[0] > g[1] || g[0] > g[2]) g = Eigen::Vector3i(g[1], g[2], g[0]);
    out.faces.push_back(g);
  }
  std::sort(out.faces.begin(), out.faces.end(), [](const auto& a, const auto& b) {
    return std::make_tuple(a[0], a[1], a[2]) < std::make_tuple(b[0], b[1], b[2]);
  });
  return out;
}

void emit(const TriangleMesh& unordered, const std::string& dir, const std::string& name,
          const std::string& description) {
  const TriangleMesh raw = canonical(unordered);
  // The file is read back as float32 (assimp): check the rounded mesh, and remove slivers
  // only if rounding folded something. The final word is the ObjectModel::load check below.
  TriangleMesh rounded = raw;
  for (auto& v : rounded.vertices) v = v.cast<float>().cast<double>();
  TriangleMesh mesh = raw;
  try {
    check(rounded, name);
  } catch (const taskmap::Error& e) {
    std::fprintf(stderr, "%s; removing slivers\n", e.what());
    mesh = cleanUp(raw);
    check(mesh, name);
  }
  const std::string path = dir + "/" + name + ".obj";
  taskmap::writeObj(mesh, path,
                    "taskmap reference object '" + name + "' (metres, z up)\n" + description +
                        "\ngenerated by meshes/tools/generate_objects.cpp; do not edit",
                    9);
  const taskmap::ObjectModel model = taskmap::ObjectModel::load(path);
  if (!model.report().repairs.empty() || !model.report().warnings.empty()) {
    throw taskmap::Error(name + ": loading needed repairs: " + model.report().repairs.front());
  }
  const auto& mp = model.massProperties();
  std::printf("%-9s %6zu vertices %6zu faces  volume %.9g m^3  com (%.6f %.6f %.6f)\n",
              name.c_str(), mesh.vertices.size(), mesh.faces.size(), mp.volume,
              mp.center_of_mass.x(), mp.center_of_mass.y(), mp.center_of_mass.z());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUTPUT_DIR\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  try {
    emit(cylinder(0.035, 0.0, 0.20), dir, "cylinder",
         "cylinder r=0.035 h=0.20, 64 segments; base centre at the origin");
    emit(box({-0.03, -0.04, 0.0}, {0.03, 0.04, 0.12}), dir, "box",
         "box 0.06 x 0.08 x 0.12 (x, y, z); base centre at the origin");
    emit(sphere(0.04, 48), dir, "sphere", "sphere r=0.04, 64 x 48 segments; centre at the origin");

    // Mug: (solid cylinder + torus handle) - cavity open at the top.
    const TriangleMesh body = cylinder(0.04, 0.0, 0.10);
    // Handle and cavity placed so that no vertex of one lies on an edge or face of another
    // (the cavity is turned by half a segment): corefinement then needs no sliver triangles.
    const TriangleMesh handle = torusXZ({0.0587, 0.0, 0.0503}, 0.025, 0.0071, 24);
    const TriangleMesh cavity = cylinder(0.035, 0.008, 0.12, M_PI / kSegments);
    emit(boolean(boolean(body, handle, Op::kUnion), cavity, Op::kDifference), dir, "mug",
         "mug: cylinder r=0.04 h=0.10, cavity r=0.035 from z=0.008 open at the top,\n"
         "torus handle in the xz-plane (centre x=0.0587 z=0.0503, R=0.025, tube r=0.0071)");

    // Bowl: revolved profile with a flat foot, 6 mm bottom, rim at z=0.07.
    std::vector<Eigen::Vector2d> profile = {{0.0, 0.0}};
    const int steps = 24;
    for (int i = 0; i <= steps; ++i) {
      const double t = 0.5 * M_PI * i / steps;
      profile.emplace_back(0.03 + 0.05 * std::sin(t), 0.07 * (1 - std::cos(t)));
    }
    for (int i = steps; i >= 0; --i) {
      const double t = 0.5 * M_PI * i / steps;
      profile.emplace_back(i == 0 ? 0.0 : 0.075 * std::sin(t), 0.006 + 0.064 * (1 - std::cos(t)));
    }
    emit(revolve(profile, kSegments), dir, "bowl",
         "bowl: outer rim r=0.08, inner rim r=0.075 at z=0.07, foot r=0.03, 6 mm bottom");

    // Basket: open box with a U-shaped handle along x (left bar, right bar, top bar).
    const TriangleMesh outer = box({-0.15, -0.10, 0.0}, {0.15, 0.10, 0.12});
    const TriangleMesh inner = box({-0.142, -0.092, 0.008}, {0.142, 0.092, 0.20});
    TriangleMesh basket = boolean(outer, inner, Op::kDifference);
    basket = boolean(basket, box({-0.156, -0.01, 0.08}, {-0.136, 0.01, 0.28}), Op::kUnion);
    basket = boolean(basket, box({0.136, -0.01, 0.08}, {0.156, 0.01, 0.28}), Op::kUnion);
    basket = boolean(basket, box({-0.15, -0.0095, 0.26}, {0.15, 0.0095, 0.279}), Op::kUnion);
    emit(basket, dir, "basket",
         "basket: body 0.30 x 0.20 x 0.12 (x, y, z), 8 mm walls and bottom, open top;\n"
         "U handle along x: bars 0.02 x 0.02 at x=+-0.146 from z=0.08 to 0.28, top bar\n"
         "0.30 x 0.019 x 0.019 at z=0.26..0.279; base centre at the origin");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "taskmap_generate_objects: %s\n", e.what());
    return 1;
  }
  return 0;
}
