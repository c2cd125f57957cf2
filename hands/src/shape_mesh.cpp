// Collision shapes as triangle meshes (shape_mesh.hpp).
#include "taskmap/hands/shape_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include "taskmap/meshes/qhull_run.hpp"

namespace taskmap {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kSides = 24;                       // cylinder
constexpr int kLatitudes = 8, kLongitudes = 16;  // sphere

void boxMesh(const Eigen::Vector3d& size, TriangleMesh& m) {
  for (int i = 0; i < 8; ++i)
    m.vertices.emplace_back((i & 1 ? 0.5 : -0.5) * size.x(), (i & 2 ? 0.5 : -0.5) * size.y(),
                            (i & 4 ? 0.5 : -0.5) * size.z());
  // Faces of the cube with vertex index bits (x, y, z), counter-clockwise from outside.
  static constexpr int kQuads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                       {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : kQuads) {
    m.faces.emplace_back(q[0], q[1], q[2]);
    m.faces.emplace_back(q[0], q[2], q[3]);
  }
}

void cylinderMesh(double r, double length, TriangleMesh& m) {
  for (int k = 0; k < kSides; ++k) {
    const double a = 2 * kPi * k / kSides;
    m.vertices.emplace_back(r * std::cos(a), r * std::sin(a), -0.5 * length);
    m.vertices.emplace_back(r * std::cos(a), r * std::sin(a), 0.5 * length);
  }
  const int bottom = static_cast<int>(m.vertices.size());
  m.vertices.emplace_back(0, 0, -0.5 * length);
  m.vertices.emplace_back(0, 0, 0.5 * length);
  for (int k = 0; k < kSides; ++k) {
    const int a0 = 2 * k, a1 = 2 * k + 1, b0 = 2 * ((k + 1) % kSides), b1 = b0 + 1;
    m.faces.emplace_back(a0, b0, b1);
    m.faces.emplace_back(a0, b1, a1);
    m.faces.emplace_back(bottom, b0, a0);
    m.faces.emplace_back(bottom + 1, a1, b1);
  }
}

void sphereMesh(double r, TriangleMesh& m) {
  m.vertices.emplace_back(0, 0, r);
  for (int i = 1; i < kLatitudes; ++i) {
    const double theta = kPi * i / kLatitudes;
    for (int j = 0; j < kLongitudes; ++j) {
      const double phi = 2 * kPi * j / kLongitudes;
      m.vertices.emplace_back(r * std::sin(theta) * std::cos(phi),
                              r * std::sin(theta) * std::sin(phi), r * std::cos(theta));
    }
  }
  const int south = static_cast<int>(m.vertices.size());
  m.vertices.emplace_back(0, 0, -r);
  const auto ring = [](int i, int j) { return 1 + (i - 1) * kLongitudes + (j % kLongitudes); };
  for (int j = 0; j < kLongitudes; ++j) {
    m.faces.emplace_back(0, ring(1, j), ring(1, j + 1));
    for (int i = 1; i + 1 < kLatitudes; ++i) {
      m.faces.emplace_back(ring(i, j), ring(i + 1, j), ring(i + 1, j + 1));
      m.faces.emplace_back(ring(i, j), ring(i + 1, j + 1), ring(i, j + 1));
    }
    m.faces.emplace_back(ring(kLatitudes - 1, j), south, ring(kLatitudes - 1, j + 1));
  }
}

// Convex hull of points: qhull's facet planes, each with the hull vertices on it ordered
// counter-clockwise about the outward normal and fanned (merged coplanar facets appear once).
void hullMesh(const std::vector<Eigen::Vector3d>& points, TriangleMesh& m) {
  if (points.size() < 4) return;
  std::vector<double> coords;
  double scale = 0.0;
  for (const auto& p : points) {
    coords.insert(coords.end(), {p.x(), p.y(), p.z()});
    scale = std::max(scale, p.cwiseAbs().maxCoeff());
  }
  const QhullOutput hull = runQhull(3, coords, "Qt", true, true);
  if (hull.exit_code != 0 || hull.vertices.empty()) return;
  const double tol = 1e-9 + 1e-7 * scale;
  std::set<std::vector<int>> seen;
  std::vector<int> index(points.size(), -1);  // input point -> mesh vertex
  for (Eigen::Index f = 0; f < hull.normals.cols(); ++f) {
    const Eigen::Vector3d n = hull.normals.col(f);
    std::vector<int> on;
    for (int v : hull.vertices)
      if (std::abs(n.dot(points[static_cast<std::size_t>(v)]) + hull.offsets[f]) <= tol)
        on.push_back(v);
    std::sort(on.begin(), on.end());
    if (on.size() < 3 || !seen.insert(on).second) continue;
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int v : on) c += points[static_cast<std::size_t>(v)];
    c /= static_cast<double>(on.size());
    const Eigen::Vector3d u = n.unitOrthogonal(), w = n.cross(u);
    std::vector<std::pair<double, int>> around;
    for (int v : on) {
      const Eigen::Vector3d d = points[static_cast<std::size_t>(v)] - c;
      around.emplace_back(std::atan2(w.dot(d), u.dot(d)), v);
    }
    std::sort(around.begin(), around.end());
    for (const auto& a : around) {
      int& i = index[static_cast<std::size_t>(a.second)];
      if (i < 0) {
        i = static_cast<int>(m.vertices.size());
        m.vertices.push_back(points[static_cast<std::size_t>(a.second)]);
      }
    }
    const auto at = [&](std::size_t k) {
      return index[static_cast<std::size_t>(around[k].second)];
    };
    for (std::size_t k = 1; k + 1 < around.size(); ++k)
      m.faces.emplace_back(at(0), at(k), at(k + 1));
  }
}

}  // namespace

TriangleMesh collisionShapeMesh(const CollisionShape& shape) {
  TriangleMesh m;
  switch (shape.type) {
    case ShapeType::kBox:
      if ((shape.box_size.array() > 0).all()) boxMesh(shape.box_size, m);
      break;
    case ShapeType::kCylinder:
      if (shape.radius > 0 && shape.length > 0) cylinderMesh(shape.radius, shape.length, m);
      break;
    case ShapeType::kSphere:
      if (shape.radius > 0) sphereMesh(shape.radius, m);
      break;
    case ShapeType::kConvex:
      hullMesh(shape.points, m);
      break;
  }
  return m;
}

std::vector<TriangleMesh> posedLinkMeshes(const HandModel& hand, const Eigen::Isometry3d& palm_pose,
                                          const Eigen::VectorXd& q) {
  const std::vector<Eigen::Isometry3d> poses = hand.linkPoses(q);
  std::vector<TriangleMesh> out(hand.links().size());
  for (std::size_t li = 0; li < hand.links().size(); ++li) {
    TriangleMesh& m = out[li];
    for (const CollisionShape& s : hand.links()[li].shapes) {
      const TriangleMesh piece = collisionShapeMesh(s);
      const Eigen::Isometry3d t = palm_pose * poses[li] * s.origin;
      const auto base = static_cast<int>(m.vertices.size());
      for (const auto& v : piece.vertices) m.vertices.push_back(t * v);
      for (const auto& f : piece.faces) m.faces.push_back(f + Eigen::Vector3i::Constant(base));
    }
  }
  return out;
}

}  // namespace taskmap
