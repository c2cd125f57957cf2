// Collision shapes as triangle meshes (shape_mesh.hpp): every mesh is closed (each directed
// edge once, its reverse once), oriented outwards (positive signed volume), and encloses the
// volume of its shape: exactly for a box and a convex hull, the inscribed prism / UV sphere's
// closed-form volume for a cylinder and a sphere. Posed link meshes follow the hand's forward
// kinematics.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <utility>

#include "taskmap/hands/hand_model.hpp"
#include "taskmap/hands/shape_mesh.hpp"

namespace taskmap {
namespace {

constexpr double kPi = 3.14159265358979323846;

double signedVolume(const TriangleMesh& m) {
  double v = 0;
  for (const auto& f : m.faces)
    v += m.vertices[f[0]].dot(m.vertices[f[1]].cross(m.vertices[f[2]])) / 6.0;
  return v;
}

// Each directed edge exactly once and its reverse exactly once: a closed, consistently
// oriented surface.
bool closedAndConsistent(const TriangleMesh& m) {
  std::map<std::pair<int, int>, int> edges;
  for (const auto& f : m.faces)
    for (int k = 0; k < 3; ++k) ++edges[{f[k], f[(k + 1) % 3]}];
  for (const auto& [e, n] : edges) {
    const auto back = edges.find({e.second, e.first});
    if (n != 1 || back == edges.end() || back->second != 1) return false;
  }
  return !m.faces.empty();
}

TEST(ShapeMesh, BoxIsExact) {
  CollisionShape s;
  s.type = ShapeType::kBox;
  s.box_size = Eigen::Vector3d(0.02, 0.03, 0.05);
  const TriangleMesh m = collisionShapeMesh(s);
  EXPECT_EQ(m.vertices.size(), 8u);
  EXPECT_EQ(m.faces.size(), 12u);
  EXPECT_TRUE(closedAndConsistent(m));
  EXPECT_NEAR(signedVolume(m), 0.02 * 0.03 * 0.05, 1e-15);
}

TEST(ShapeMesh, CylinderIsTheInscribedPrism) {
  CollisionShape s;
  s.type = ShapeType::kCylinder;
  s.radius = 0.01;
  s.length = 0.04;
  const TriangleMesh m = collisionShapeMesh(s);
  EXPECT_TRUE(closedAndConsistent(m));
  // A regular 24-gon of circumradius r has area 24/2 r^2 sin(2 pi / 24).
  EXPECT_NEAR(signedVolume(m), 12 * s.radius * s.radius * std::sin(2 * kPi / 24) * s.length, 1e-15);
  for (const auto& v : m.vertices) EXPECT_LE(std::hypot(v.x(), v.y()), s.radius + 1e-15);
}

TEST(ShapeMesh, SphereVerticesLieOnTheSphere) {
  CollisionShape s;
  s.type = ShapeType::kSphere;
  s.radius = 0.015;
  const TriangleMesh m = collisionShapeMesh(s);
  EXPECT_TRUE(closedAndConsistent(m));
  for (const auto& v : m.vertices) EXPECT_NEAR(v.norm(), s.radius, 1e-15);
  const double ball = 4.0 / 3.0 * kPi * std::pow(s.radius, 3);
  EXPECT_LT(signedVolume(m), ball);
  EXPECT_GT(signedVolume(m), 0.85 * ball);
}

TEST(ShapeMesh, ConvexShapeIsTheHullOfItsPoints) {
  // An octahedron's 6 vertices, an inner point and the 8 corners of a cube inside it.
  CollisionShape s;
  s.type = ShapeType::kConvex;
  for (int a = 0; a < 3; ++a)
    for (double sign : {-1.0, 1.0}) s.points.push_back(sign * 0.03 * Eigen::Vector3d::Unit(a));
  s.points.emplace_back(0.001, 0.002, 0.0);
  for (int i = 0; i < 8; ++i)
    s.points.emplace_back(i & 1 ? 0.005 : -0.005, i & 2 ? 0.005 : -0.005, i & 4 ? 0.005 : -0.005);
  const TriangleMesh m = collisionShapeMesh(s);
  EXPECT_EQ(m.vertices.size(), 6u);
  EXPECT_EQ(m.faces.size(), 8u);
  EXPECT_TRUE(closedAndConsistent(m));
  EXPECT_NEAR(signedVolume(m), 4.0 / 3.0 * std::pow(0.03, 3), 1e-15);
  // A cube's square faces are fanned once each, though qhull splits them.
  CollisionShape cube;
  cube.type = ShapeType::kConvex;
  for (int i = 0; i < 8; ++i)
    cube.points.emplace_back(i & 1 ? 0.01 : -0.01, i & 2 ? 0.01 : -0.01, i & 4 ? 0.01 : -0.01);
  const TriangleMesh c = collisionShapeMesh(cube);
  EXPECT_EQ(c.faces.size(), 12u);
  EXPECT_TRUE(closedAndConsistent(c));
  EXPECT_NEAR(signedVolume(c), 8e-6, 1e-18);
}

TEST(ShapeMesh, DegenerateShapesGiveEmptyMeshes) {
  CollisionShape flat;
  flat.type = ShapeType::kConvex;
  flat.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  EXPECT_TRUE(collisionShapeMesh(flat).faces.empty());
  CollisionShape zero;
  zero.type = ShapeType::kBox;
  EXPECT_TRUE(collisionShapeMesh(zero).faces.empty());
}

TEST(ShapeMesh, PosedLinksFollowTheForwardKinematics) {
  const HandModel hand = HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf");
  Eigen::Isometry3d palm = Eigen::Isometry3d::Identity();
  palm.translate(Eigen::Vector3d(0.1, -0.2, 0.3))
      .rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  const Eigen::VectorXd q = hand.preshape();
  const std::vector<TriangleMesh> links = posedLinkMeshes(hand, palm, q);
  const std::vector<Eigen::Isometry3d> poses = hand.linkPoses(q);
  ASSERT_EQ(links.size(), hand.links().size());
  for (std::size_t li = 0; li < links.size(); ++li) {
    const HandLink& l = hand.links()[li];
    if (l.shapes.empty()) {
      EXPECT_TRUE(links[li].faces.empty()) << l.name;
      continue;
    }
    // Shape by shape: the posed mesh is the shape's mesh moved by palm * link * origin.
    std::size_t at = 0;
    for (const CollisionShape& s : l.shapes) {
      const TriangleMesh alone = collisionShapeMesh(s);
      const Eigen::Isometry3d t = palm * poses[li] * s.origin;
      for (const auto& v : alone.vertices) {
        ASSERT_LT(at, links[li].vertices.size()) << l.name;
        EXPECT_LT((links[li].vertices[at++] - t * v).norm(), 1e-12) << l.name;
      }
    }
    EXPECT_EQ(at, links[li].vertices.size()) << l.name;
    // Rigid motions keep the enclosed volume.
    double volume = 0;
    for (const CollisionShape& s : l.shapes) volume += signedVolume(collisionShapeMesh(s));
    EXPECT_NEAR(signedVolume(links[li]), volume, 1e-12) << l.name;
  }
}

}  // namespace
}  // namespace taskmap
