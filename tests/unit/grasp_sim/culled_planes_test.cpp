// Culling planes in blocks (grasp_sim/src/culled_planes.hpp) against a plane-by-plane scan: the
// same bound below the limit, the same cull decision above it, the same inside test; every plane
// is a valid separating plane (no shape point beyond it), the padding never culls. The tree's
// normal cones hold the normals of their triangles (YCB banana).
#include "culled_planes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <gtest/gtest.h>

#include "hull_support_shape.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Eigen::Vector3d plane(const ShapePlanes& pl, int i) {
  return Eigen::Vector3d(pl.nx[i], pl.ny[i], pl.nz[i]);
}

/// Plane-by-plane scan of the triangle bound over [0, end).
double scanBound(const ShapePlanes& pl, const std::array<Eigen::Vector3d, 3>& v, int end) {
  double lb = -kInf;
  for (int i = 0; i < end; ++i) {
    const Eigen::Vector3d n = plane(pl, i);
    lb = std::max(lb, std::min({n.dot(v[0]), n.dot(v[1]), n.dot(v[2])}) - pl.h[i]);
  }
  return lb;
}

/// Plane-by-plane scan of the node bound over [0, node_planes).
double scanNode(const ShapePlanes& pl, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const Eigen::Vector3d m = 0.5 * (lo + hi), e = 0.5 * (hi - lo);
  double lb = -kInf;
  for (int i = 0; i < pl.node_planes; ++i) {
    const Eigen::Vector3d n = plane(pl, i);
    lb = std::max(lb, n.dot(m) - n.cwiseAbs().dot(e) - pl.h[i]);
  }
  return lb;
}

/// Points on an ellipsoid (a smooth hull with many faces, like a scanned link).
std::vector<Eigen::Vector3d> ellipsoidPoints(int n, std::mt19937* rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < n; ++i) {
    Eigen::Vector3d v(g(*rng), g(*rng), g(*rng));
    v.normalize();
    pts.push_back(Eigen::Vector3d(0.04 * v.x(), 0.015 * v.y(), 0.025 * v.z()));
  }
  return pts;
}

/// A box link shape (margin 0, as the scene builds it) with its culling data.
ShapeEntry boxEntry() {
  ShapeEntry e;
  e.is_box = true;
  e.half_extents = Eigen::Vector3d(0.03, 0.01, 0.02);
  e.shape = std::make_unique<btBoxShape>(bt(e.half_extents));
  e.shape->setMargin(0.0);
  addCullingData({}, &e);
  return e;
}

/// A hull link shape of `pts` with its culling data.
ShapeEntry hullEntry(const std::vector<Eigen::Vector3d>& pts) {
  ShapeEntry e;
  e.shape = std::make_unique<IndexedHullShape>(pts, 0.0);
  addCullingData(pts, &e);
  return e;
}

Eigen::Isometry3d randomPose(std::mt19937* rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::Quaterniond(g(*rng), g(*rng), g(*rng), g(*rng)).normalized().matrix();
  t.translation() = 0.02 * Eigen::Vector3d(g(*rng), g(*rng), g(*rng));
  return t;
}

void checkShape(const ShapeEntry& e, const std::vector<Eigen::Vector3d>& shape_points,
                unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  ShapePlanes pl;
  for (int pose = 0; pose < 20; ++pose) {
    const Eigen::Isometry3d ts = randomPose(&rng);
    btVector3 amin, amax;
    e.shape->getAabb(bt(ts), amin, amax);
    pl.set(e, ts, amin, amax, 0.01);
    pl.placeAll();
    ASSERT_EQ(pl.count % kPlaneBlock, 0);
    // Valid planes: no point of the shape beyond any (padding: +inf offsets).
    for (const auto& p : shape_points)
      for (int i = 0; i < pl.count; ++i)
        EXPECT_LE(plane(pl, i).dot(ts * p) - pl.h[i], 1e-12) << "plane " << i;
    for (int k = 0; k < 200; ++k) {
      const Eigen::Vector3d c = ts.translation() + 0.05 * Eigen::Vector3d(g(rng), g(rng), g(rng));
      std::array<Eigen::Vector3d, 3> v;
      for (auto& x : v) x = c + 0.01 * Eigen::Vector3d(g(rng), g(rng), g(rng));
      const double full = scanBound(pl, v, pl.facet_begin);
      const double limit = 0.01 * g(rng);
      const Eigen::Vector3d tlo = v[0].cwiseMin(v[1]).cwiseMin(v[2]);
      const Eigen::Vector3d thi = v[0].cwiseMax(v[1]).cwiseMax(v[2]);
      const bool in_box =
          !((tlo.array() > pl.qhi.array()).any() || (thi.array() < pl.qlo.array()).any());
      const double b = pl.bound(v, limit);
      if (!in_box) {
        EXPECT_EQ(b, kInf);
      } else if (full <= limit) {
        EXPECT_NEAR(b, full, 1e-15);  // the full maximum
      } else {
        EXPECT_GT(b, limit);  // culled, by a plane that shows it
        EXPECT_LE(b, full + 1e-15);
      }
      const Eigen::Vector3d lo = c - 0.01 * Eigen::Vector3d(1, 2, 1).cwiseAbs();
      const Eigen::Vector3d hi = c + 0.02 * Eigen::Vector3d(1, 1, 2);
      const double nfull = scanNode(pl, lo, hi);
      const double nb = pl.nodeBound(lo, hi, limit);
      const bool node_in =
          !((lo.array() > pl.qhi.array()).any() || (hi.array() < pl.qlo.array()).any());
      if (!node_in)
        EXPECT_EQ(nb, kInf);
      else if (nfull <= limit)
        EXPECT_NEAR(nb, nfull, 1e-15);
      else
        EXPECT_GT(nb, limit);
      // Inside every face plane (hulls) <=> the scan says so.
      bool scan_inside = e.is_hull;
      for (int i = pl.facet_begin; i < pl.count && scan_inside; ++i)
        scan_inside = plane(pl, i).dot(c) - pl.h[i] < -kInsideSlack;
      if (e.is_hull) {
        EXPECT_EQ(pl.inside(c, pl.facet_begin), scan_inside);
      }
    }
  }
}

TEST(CulledPlanes, BoxBlocksMatchThePlaneScan) {
  const ShapeEntry e = boxEntry();
  EXPECT_EQ(e.node_planes, kPlaneBlock);  // 6 faces, padded
  EXPECT_EQ(e.facet_begin, e.node_planes);
  std::vector<Eigen::Vector3d> corners;
  for (int k = 0; k < 8; ++k)
    corners.push_back(e.half_extents.cwiseProduct(
        Eigen::Vector3d(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1)));
  checkShape(e, corners, 3);
}

TEST(CulledPlanes, HullBlocksMatchThePlaneScan) {
  std::mt19937 rng(5);
  const std::vector<Eigen::Vector3d> pts = ellipsoidPoints(300, &rng);
  const ShapeEntry e = hullEntry(pts);
  ASSERT_TRUE(e.is_hull);
  const int facets = static_cast<int>(e.pr.size()) - e.facet_begin;  // padded
  EXPECT_GT(facets, 100);
  // The triangle planes are a spread subset of the face normals: fewer than the faces.
  EXPECT_LT(e.facet_begin - e.node_planes, facets / 2);
  // Valid against the shape GJK sees (its points after Bullet's hull optimisation).
  const auto& hull = static_cast<const btConvexHullShape&>(*e.shape);
  std::vector<Eigen::Vector3d> shape_points;
  for (int i = 0; i < hull.getNumPoints(); ++i)
    shape_points.push_back(eig(hull.getUnscaledPoints()[i]));
  checkShape(e, shape_points, 7);
}

// The hull face planes' gap of a triangle (faceGap), the face contact proven from it and the
// inside test of its corners (insideFaces) against plane-by-plane scans: the same gap and first
// face at or below the limit, a value above it otherwise; the same proof, depth, normal and
// witness as the scan's; the same inside verdict as ShapePlanes::inside.
TEST(CulledPlanes, HullFaceGapAndContactMatchTheFaceScan) {
  std::mt19937 rng(11);
  const std::vector<Eigen::Vector3d> pts = ellipsoidPoints(300, &rng);
  const ShapeEntry e = hullEntry(pts);
  ASSERT_TRUE(e.is_hull);
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  ShapePlanes pl;
  int proven = 0, culled = 0, unproven = 0;
  for (int pose = 0; pose < 20; ++pose) {
    const Eigen::Isometry3d ts = randomPose(&rng);
    btVector3 amin, amax;
    e.shape->getAabb(bt(ts), amin, amax);
    pl.set(e, ts, amin, amax, 0.0);
    pl.placeAll();
    ShapePlanes lazy;  // face blocks placed as read: the same numbers
    lazy.set(e, ts, amin, amax, 0.0);
    for (int k = 0; k < 300; ++k) {
      // A small triangle about a point inside the hull (scaled ellipsoid point) or near it.
      const Eigen::Vector3d c =
          ts * (pts[static_cast<std::size_t>(k) % pts.size()] * (0.3 + 0.9 * u(rng)));
      std::array<Eigen::Vector3d, 3> v;
      for (auto& x : v) x = c + 0.002 * Eigen::Vector3d(g(rng), g(rng), g(rng));
      double scan = -kInf;
      int scan_face = -1;
      for (int i = pl.facet_begin; i < pl.count; ++i) {
        const Eigen::Vector3d n = plane(pl, i);
        const double gi = std::min({n.dot(v[0]), n.dot(v[1]), n.dot(v[2])}) - pl.h[i];
        if (gi > scan) {
          scan = gi;
          scan_face = i;
        }
      }
      const double limit = 0.002 * g(rng);
      int face = -2;
      const double gap = pl.faceGap(v, limit, &face);
      int lazy_face = -2;
      EXPECT_EQ(lazy.faceGap(v, limit, &lazy_face), gap);
      EXPECT_EQ(lazy_face, face);
      EXPECT_EQ(lazy.bound(v, limit, true), pl.bound(v, limit, true));
      if (scan > limit + 1e-15) {
        EXPECT_GT(gap, limit);
        EXPECT_EQ(face, -1);
        ++culled;
        continue;
      }
      if (scan < limit - 1e-15) {
        EXPECT_NEAR(gap, scan, 1e-15);
        EXPECT_EQ(face, scan_face);
      }
      if (gap > limit) continue;
      for (int c3 = 0; c3 < 3; ++c3) {
        EXPECT_EQ(pl.insideFaces(v, c3),
                  pl.inside(v[static_cast<std::size_t>(c3)], pl.facet_begin));
        EXPECT_EQ(lazy.insideFaces(v, c3), pl.insideFaces(v, c3));
      }
      // The face contact by scan: the corners deepest below the gap's face, each at least -gap
      // inside every face.
      const double min_depth = 1e-9;
      bool scan_proven = face >= 0 && gap < -min_depth;
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      int tied = 0;
      if (scan_proven) {
        const Eigen::Vector3d n = plane(pl, face);
        const double lo = std::min({n.dot(v[0]), n.dot(v[1]), n.dot(v[2])});
        for (const auto& p : v) {
          if (n.dot(p) > lo + 1e-9) continue;
          double inside = kInf;
          for (int i = pl.facet_begin; i < pl.count; ++i)
            inside = std::min(inside, pl.h[i] - plane(pl, i).dot(p));
          scan_proven = scan_proven && inside >= -gap - 1e-12;
          sum += p;
          ++tied;
        }
      }
      double depth = 0.0;
      Eigen::Vector3d normal = Eigen::Vector3d::Zero(), point = Eigen::Vector3d::Zero();
      const bool ok = pl.faceContact(v, gap, face, min_depth, &depth, &normal, &point);
      double lazy_depth = 0.0;
      Eigen::Vector3d lazy_normal = Eigen::Vector3d::Zero(), lazy_point = lazy_normal;
      EXPECT_EQ(lazy.faceContact(v, gap, face, min_depth, &lazy_depth, &lazy_normal, &lazy_point),
                ok);
      EXPECT_EQ(lazy_depth, depth);
      EXPECT_EQ(lazy_normal, normal);
      EXPECT_EQ(lazy_point, point);
      EXPECT_EQ(ok, scan_proven);
      if (ok && scan_proven) {
        EXPECT_EQ(depth, -gap);
        EXPECT_EQ(normal, -plane(pl, face));
        EXPECT_LT((point - sum / tied).norm(), 1e-15);
        ++proven;
      } else {
        ++unproven;
      }
    }
  }
  // Every branch was exercised.
  EXPECT_GT(proven, 100);
  EXPECT_GT(culled, 100);
  EXPECT_GT(unproven, 10);
}

// One ShapePlanes serves shapes of different sizes (its columns only grow): a box after a hull
// gives the bounds of a fresh one.
TEST(CulledPlanes, ReusedForAShorterShape) {
  std::mt19937 rng(9);
  const std::vector<Eigen::Vector3d> pts = ellipsoidPoints(200, &rng);
  const ShapeEntry hull = hullEntry(pts), box = boxEntry();
  ShapePlanes reused, fresh;
  const Eigen::Isometry3d ts = randomPose(&rng);
  btVector3 amin, amax;
  hull.shape->getAabb(bt(ts), amin, amax);
  reused.set(hull, ts, amin, amax, 0.01);
  box.shape->getAabb(bt(ts), amin, amax);
  reused.set(box, ts, amin, amax, 0.01);
  fresh.set(box, ts, amin, amax, 0.01);
  ASSERT_EQ(reused.count, fresh.count);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int k = 0; k < 100; ++k) {
    const Eigen::Vector3d c = ts.translation() + 0.04 * Eigen::Vector3d(g(rng), g(rng), g(rng));
    std::array<Eigen::Vector3d, 3> v;
    for (auto& x : v) x = c + 0.01 * Eigen::Vector3d(g(rng), g(rng), g(rng));
    EXPECT_EQ(reused.bound(v, kInf), fresh.bound(v, kInf));
    EXPECT_EQ(reused.nodeBound(c, c + Eigen::Vector3d::Constant(0.01), kInf),
              fresh.nodeBound(c, c + Eigen::Vector3d::Constant(0.01), kInf));
  }
}

/// Bullet's quantized tree of a mesh with the culling data (normals, node boxes and cones), as
/// CollisionScene builds it.
struct TreeOfMesh {
  CollisionScene::Data d;
  explicit TreeOfMesh(const TriangleMesh& mesh) {
    buildObjectTree(mesh, &d);
    buildCulling(mesh.vertices, mesh.faces, true, &d);
  }
};

// Every node's normal cone holds the normals of the triangles below it, and a node the filter
// turns away holds no triangle the filter's condition admits (the walk may skip it).
TEST(NormalCones, HoldTheirTrianglesNormals) {
  const ObjectModel banana =
      ObjectModel::load(std::string(TEST_DATA_DIR) + "/real/objects/ycb_011_banana.obj");
  const TreeOfMesh tree(banana.mesh());
  const auto& d = tree.d;
  ASSERT_TRUE(d.culled);
  const auto& nodes = d.mesh_shape->getOptimizedBvh()->getQuantizedNodeArray();
  ASSERT_EQ(static_cast<std::size_t>(nodes.size()), d.node_cones.size());
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<NormalFilter> filters;
  for (int k = 0; k < 8; ++k)
    filters.emplace_back(Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized(), 0.5);
  int turned_away = 0, narrow = 0;
  for (int i = 0; i < nodes.size(); i += 7) {
    if (nodes[i].isLeafNode()) continue;
    const auto& cone = d.node_cones[static_cast<std::size_t>(i)];
    narrow += cone.half < 1.0;
    std::vector<bool> admitted(filters.size(), false);
    for (std::size_t k = 0; k < filters.size(); ++k) admitted[k] = filters[k].admits(cone);
    for (int j = i; j < i + nodes[i].getEscapeIndex(); ++j) {
      if (!nodes[j].isLeafNode()) continue;
      const Eigen::Vector3d& n = d.normals[static_cast<std::size_t>(nodes[j].getTriangleIndex())];
      ASSERT_LE(std::acos(std::clamp(n.dot(cone.axis), -1.0, 1.0)), cone.half + 1e-9) << i;
      for (std::size_t k = 0; k < filters.size(); ++k) {
        if (!admitted[k]) {
          ASSERT_LE(n.dot(filters[k].b), 0.5) << "node " << i;
        }
      }
    }
    for (bool a : admitted) turned_away += !a;
  }
  EXPECT_GT(narrow, 100);        // the cones are tight enough to matter
  EXPECT_GT(turned_away, 1000);  // and the filters skip subtrees
}

}  // namespace
}  // namespace taskmap
