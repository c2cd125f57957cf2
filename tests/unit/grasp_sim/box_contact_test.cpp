// The 13-axis penetration of a box and a triangle (grasp_sim/src/box_contact.cpp) against
// Bullet's EPA on the same pairs: the same depth and normal, the same witness where the deepest
// features are unique; at ties (a face flat on a face) the witness lies in the overlap.
#include <algorithm>
#include <cmath>
#include <random>

#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btTriangleShape.h>
#include <gtest/gtest.h>

#include "collision_data.hpp"

namespace taskmap {
namespace {

struct Epa {
  bool ok = false;
  double depth = 0.0;
  Eigen::Vector3d normal, point;
};

/// Bullet's answer for the pair, as TriangleQuery asks it (box first, triangle at identity).
Epa epa(const Eigen::Vector3d& c, const Eigen::Matrix3d& r, const Eigen::Vector3d& half,
        const btVector3* tri) {
  btBoxShape box(bt(half));
  box.setMargin(0.0);
  btTriangleShape ts(tri[0], tri[1], tri[2]);
  ts.setMargin(0.0);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = r;
  t.translation() = c;
  btGjkEpaSolver2::sResults res;
  double d = 0.0;
  bool overlap = false;
  Epa out;
  out.ok = signedDistance(&box, bt(t), &ts, btTransform::getIdentity(), true, &d, &res, &overlap) &&
           overlap;
  out.depth = -d;
  out.normal = eig(res.normal);
  out.point = eig(res.witnesses[1]);
  return out;
}

/// Distance of `p` from the triangle's plane and how far outside its edges it lies, metres.
double offTriangle(const btVector3* tri, const Eigen::Vector3d& p) {
  const Eigen::Vector3d a = eig(tri[0]), b = eig(tri[1]), c = eig(tri[2]);
  const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
  double off = std::abs(n.dot(p - a));
  const Eigen::Vector3d v[3] = {a, b, c};
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d out = (v[(k + 1) % 3] - v[k]).cross(n).normalized();
    off = std::max(off, out.dot(p - v[k]));
  }
  return off;
}

TEST(BoxContact, MatchesEpaOnRandomOverlaps) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.02, 0.02), ang(-3.14, 3.14);
  const Eigen::Vector3d half(0.01, 0.006, 0.015);
  int compared = 0, depth_same = 0, witness_same = 0;
  for (int k = 0; k < 4000; ++k) {
    const Eigen::Matrix3d r =
        Eigen::AngleAxisd(ang(rng), Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized())
            .toRotationMatrix();
    const Eigen::Vector3d c(u(rng), u(rng), u(rng));
    btVector3 tri[3];
    for (auto& p : tri) p = btVector3(u(rng), u(rng), u(rng));
    const BoxTrianglePenetration p = boxTrianglePenetration(c, r, half, tri);
    // The separation is boxTriangleSeparation's, bit for bit.
    ASSERT_EQ(p.separation, boxTriangleSeparation(c, r, half, tri)) << k;
    if (p.separation > -1e-6) continue;
    ASSERT_NEAR(p.depth, -p.separation, 1e-12);
    ASSERT_LT(offTriangle(tri, p.point), 1e-9) << k;
    const Epa b = epa(c, r, half, tri);
    if (!b.ok) continue;
    ++compared;
    // EPA's polytope lies inside the Minkowski difference: its depth is never above the exact
    // one; converged, it is the same.
    ASSERT_LE(b.depth, p.depth + 1e-12) << k;
    if (std::abs(p.depth - b.depth) > 1e-9 + 1e-6 * b.depth) continue;
    ++depth_same;
    EXPECT_GT(p.normal.dot(b.normal), 1.0 - 1e-6) << k;
    witness_same += (p.point - b.point).norm() < 1e-7;
  }
  EXPECT_GT(compared, 1000);
  EXPECT_GT(depth_same, compared * 99 / 100) << depth_same << " of " << compared;
  // Generic pairs have unique deepest features: EPA finds the same witness.
  EXPECT_GT(witness_same, depth_same * 99 / 100) << witness_same << " of " << depth_same;
}

TEST(BoxContact, TiedFeaturesGiveTheCentreOfTheirOverlap) {
  // An axis-aligned box (half extents 1 cm, 1 cm, 0.5 cm) and a triangle lying flat 1 mm inside
  // its top face: the depth is 1 mm along +z and the witness the centre of the triangle's part
  // inside the face's sides (x <= 0.01), not one corner of it.
  const Eigen::Vector3d c = Eigen::Vector3d::Zero(), half(0.01, 0.01, 0.005);
  const Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  const btVector3 tri[3] = {btVector3(0.0, -0.002, 0.004), btVector3(0.02, -0.002, 0.004),
                            btVector3(0.0, 0.002, 0.004)};
  const BoxTrianglePenetration p = boxTrianglePenetration(c, r, half, tri);
  EXPECT_NEAR(p.depth, 0.001, 1e-15);
  EXPECT_NEAR(p.normal.z(), -1.0, 1e-15);  // object -> box: the box leaves downward
  // Clipped at x = 0.01: corners (0,-2), (0.01,-2), (0.01,0), (0,2) mm-scaled; their mean.
  EXPECT_NEAR(p.point.x(), 0.005, 1e-12);
  EXPECT_NEAR(p.point.y(), -0.0005, 1e-12);
  EXPECT_NEAR(p.point.z(), 0.004, 1e-15);
  // The same triangle 1 mm above the box: apart by 1 mm, no penetration.
  const btVector3 above[3] = {btVector3(0.0, -0.002, 0.006), btVector3(0.02, -0.002, 0.006),
                              btVector3(0.0, 0.002, 0.006)};
  EXPECT_NEAR(boxTrianglePenetration(c, r, half, above).separation, 0.001, 1e-15);
}

}  // namespace
}  // namespace taskmap
