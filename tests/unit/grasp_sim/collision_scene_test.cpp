// The fast link-versus-mesh queries (BVH culling, box-triangle separating axes, GJK/EPA)
// against a brute-force oracle: exact box-triangle distances from feature pairs over every
// triangle of the mesh.
#include "collision_scene.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "taskmap/core/random.hpp"
#include "taskmap/meshes/object_model.hpp"
#include "test_meshes.hpp"

namespace taskmap {
namespace {

using V = Eigen::Vector3d;
constexpr double kInf = std::numeric_limits<double>::infinity();

/// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection 5.1.5).
V closestOnTriangle(const V& p, const V& a, const V& b, const V& c) {
  const V ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const V bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const V cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

/// Distance between segments p1q1 and p2q2 (Ericson 5.1.9).
double segmentDistance(const V& p1, const V& q1, const V& p2, const V& q2) {
  const V d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0, t = 0;
  const double c = d1.dot(r), b = d1.dot(d2), denom = a * e - b * b;
  s = denom > 1e-20 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
  t = (b * s + f) / e;
  if (t < 0) {
    t = 0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t > 1) {
    t = 1;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
  return ((p1 + d1 * s) - (p2 + d2 * t)).norm();
}

/// Whether segment pq meets the solid axis-aligned box [-h, h] (slab clipping).
bool segmentHitsBox(const V& p, const V& q, const V& h) {
  double t0 = 0, t1 = 1;
  const V d = q - p;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < 1e-15) {
      if (std::abs(p[k]) > h[k]) return false;
      continue;
    }
    double a = (-h[k] - p[k]) / d[k], b = (h[k] - p[k]) / d[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
    if (t0 > t1) return false;
  }
  return true;
}

/// Whether segment pq meets triangle abc (distance-based, exact up to rounding).
bool segmentHitsTriangle(const V& p, const V& q, const V& a, const V& b, const V& c) {
  const V n = (b - a).cross(c - a);
  const double dp = n.dot(p - a), dq = n.dot(q - a);
  if ((dp > 0 && dq > 0) || (dp < 0 && dq < 0)) return false;
  if (dp == dq) return false;  // parallel: edges are handled by the other tests
  const V x = p + (q - p) * (dp / (dp - dq));
  return (closestOnTriangle(x, a, b, c) - x).norm() < 1e-12;
}

/// Exact distance between a box (local frame: centred, half extents h) and a triangle given
/// in the box frame; 0 when they intersect.
double boxTriangleDistance(const V& h, const std::array<V, 3>& tri) {
  std::array<V, 8> corners;
  for (int i = 0; i < 8; ++i)
    corners[i] = V(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z());
  std::vector<std::pair<int, int>> edges;
  for (int i = 0; i < 8; ++i)
    for (int k = 0; k < 3; ++k)
      if (!(i & (1 << k))) edges.emplace_back(i, i | (1 << k));
  for (int e = 0; e < 3; ++e)
    if (segmentHitsBox(tri[e], tri[(e + 1) % 3], h)) return 0.0;
  for (const auto& [i, j] : edges)
    if (segmentHitsTriangle(corners[i], corners[j], tri[0], tri[1], tri[2])) return 0.0;
  double d = kInf;
  for (const V& c : corners)
    d = std::min(d, (closestOnTriangle(c, tri[0], tri[1], tri[2]) - c).norm());
  for (const V& t : tri) d = std::min(d, (t - t.cwiseMax(-h).cwiseMin(h)).norm());
  for (const auto& [i, j] : edges)
    for (int e = 0; e < 3; ++e)
      d = std::min(d, segmentDistance(corners[i], corners[j], tri[e], tri[(e + 1) % 3]));
  return d;
}

TEST(CollisionScene, BoxLinkDistancesMatchBruteForce) {
  const HandModel hand = HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/panda/panda.urdf");
  const int link = hand.linkIndex("panda_leftfinger");
  const CollisionShape& shape = hand.links()[static_cast<std::size_t>(link)].shapes.front();
  ASSERT_EQ(shape.type, ShapeType::kBox);
  const V h = 0.5 * shape.box_size;
  const TriangleMesh mesh = testing::makeCylinder(0.03, 0.08, 12, 2);
  const CollisionScene scene(mesh, hand);
  const double threshold = 0.004;
  int separated = 0, overlapping = 0, far = 0;
  for (int i = 0; i < 600; ++i) {
    Rng rng(5, static_cast<std::uint64_t>(i));
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = rng.rotation().toRotationMatrix();
    t.translation() =
        V(rng.uniform(-0.06, 0.06), rng.uniform(-0.06, 0.06), rng.uniform(-0.07, 0.07));
    // Oracle: exact distance over every triangle, in the box frame.
    const Eigen::Isometry3d box = t * shape.origin;
    const Eigen::Isometry3d inv = box.inverse();
    double oracle = kInf;
    for (const auto& f : mesh.faces) {
      const std::array<V, 3> tri = {inv * mesh.vertices[static_cast<std::size_t>(f[0])],
                                    inv * mesh.vertices[static_cast<std::size_t>(f[1])],
                                    inv * mesh.vertices[static_cast<std::size_t>(f[2])]};
      oracle = std::min(oracle, boxTriangleDistance(h, tri));
    }
    const double fast = scene.linkDistance(link, t, threshold);
    std::vector<TriangleHit> hits;
    const double exact = scene.linkHits(link, t, threshold, &hits);
    SCOPED_TRACE("pose " + std::to_string(i) + " oracle " + std::to_string(oracle));
    if (oracle == 0.0) {
      ++overlapping;
      EXPECT_LT(fast, 0.0);
      EXPECT_LT(exact, 0.0);
      EXPECT_GE(fast, exact - 1e-9);  // the fast depth is a lower bound of the deepest overlap
      EXPECT_FALSE(hits.empty());
    } else if (oracle <= threshold - 1e-9) {
      ++separated;
      EXPECT_NEAR(fast, oracle, 1e-9);
      EXPECT_NEAR(exact, oracle, 1e-9);
      for (const auto& hit : hits) {
        EXPECT_GE(hit.distance, oracle - 1e-9);
        EXPECT_LE(hit.distance, threshold);
      }
    } else if (oracle > threshold + 1e-9) {
      ++far;
      EXPECT_EQ(fast, kInf);
      EXPECT_EQ(exact, kInf);
      EXPECT_TRUE(hits.empty());
    }
  }
  // The pose set exercises all three regimes.
  EXPECT_GT(overlapping, 50);
  EXPECT_GT(separated, 10);
  EXPECT_GT(far, 50);
}

// linkSweepClear against the link's own distance query along the ray: wherever it answers
// clear, the link moved by any of 60 distances up to 0.5 m along the direction has nothing within
// the gap (linkDistance +inf); the pose set has both answers. Box links (barrett palm and
// finger) and a hull link (hull_palm), on the reference mug and a coarse cylinder.
TEST(CollisionScene, LinkSweepClearHoldsAlongTheWholeRay) {
  const ObjectModel mug = ObjectModel::load(std::string(TASKMAP_OBJECTS_DIR) + "/mug.obj");
  for (const TriangleMesh& mesh : {mug.mesh(), testing::makeCylinder(0.03, 0.08, 12, 2)}) {
    for (const auto& [path, link_name] :
         {std::pair<std::string, std::string>{
              std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf", "bh_palm"},
          {std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf", "f1_distal"},
          {std::string(TEST_DATA_DIR) + "/hands/hull_palm.urdf", "palm"}}) {
      SCOPED_TRACE(path + " " + link_name + " " + std::to_string(mesh.faces.size()) + " faces");
      const HandModel hand = HandModel::load(path);
      const int link = hand.linkIndex(link_name);
      ASSERT_GE(link, 0);
      const CollisionScene scene(mesh, hand);
      const double gap = 0.002;
      int clear = 0, unsure = 0;
      for (int i = 0; i < 300; ++i) {
        Rng rng(9, static_cast<std::uint64_t>(i));
        Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
        t.linear() = rng.rotation().toRotationMatrix();
        t.translation() =
            V(rng.uniform(-0.15, 0.15), rng.uniform(-0.15, 0.15), rng.uniform(-0.15, 0.15));
        const V dir = rng.rotation() * V::UnitX();
        if (!scene.linkSweepClear(link, t, dir, gap)) {
          ++unsure;
          continue;
        }
        ++clear;
        for (int k = 0; k <= 60; ++k) {
          Eigen::Isometry3d moved = t;
          moved.translation() += (0.5 * k / 60.0) * dir;
          EXPECT_EQ(scene.linkDistance(link, moved, gap), kInf) << "pose " << i << " step " << k;
        }
      }
      EXPECT_GT(clear, 20);
      EXPECT_GT(unsure, 20);
    }
  }
}

TEST(CollisionScene, InsideTestAndFaceNormals) {
  const HandModel hand = HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/panda/panda.urdf");
  const int link = hand.linkIndex("panda_leftfinger");
  const TriangleMesh mesh = testing::makeBox(0.2, 0.2, 0.2);
  const CollisionScene scene(mesh, hand);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  // Finger wholly inside: no triangle within reach, but inside.
  EXPECT_EQ(scene.linkDistance(link, t, 1e-3), kInf);
  EXPECT_TRUE(scene.linkInside(link, t));
  t.translation() = V(0.3, 0, 0);
  EXPECT_FALSE(scene.linkInside(link, t));
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const V n = scene.faceNormal(static_cast<int>(f));
    const V c = (mesh.vertices[static_cast<std::size_t>(mesh.faces[f][0])] +
                 mesh.vertices[static_cast<std::size_t>(mesh.faces[f][1])] +
                 mesh.vertices[static_cast<std::size_t>(mesh.faces[f][2])]) /
                3.0;
    EXPECT_GT(n.dot(c), 0.0);  // outward for a box centred at the origin
    EXPECT_NEAR(n.norm(), 1.0, 1e-12);
  }
}

/// Compares the culled queries with Bullet's BVH query, bit for bit, for every shaped link of
/// `hand` at `poses` poses around and inside `object` (distances and exact hits at the
/// thresholds `thresholds`); expects both the overlap and the distance paths exercised.
void expectCulledEqualsBullet(const ObjectModel& object, const HandModel& hand, int poses,
                              const std::vector<double>& thresholds) {
  const CollisionScene culled(object.mesh(), hand, CollisionScene::Mode::kCulled);
  const CollisionScene bullet(object.mesh(), hand, CollisionScene::Mode::kBullet);
  int overlaps = 0, near = 0;
  for (int i = 0; i < poses; ++i) {
    Rng rng(11, static_cast<std::uint64_t>(i));
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = rng.rotation().toRotationMatrix();
    t.translation() = object.sampleInside(rng) +
                      0.03 * V(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    for (std::size_t l = 0; l < hand.links().size(); ++l) {
      if (hand.links()[l].shapes.empty()) continue;
      const int link = static_cast<int>(l);
      for (double thr : thresholds) {
        const double a = culled.linkDistance(link, t, thr), b = bullet.linkDistance(link, t, thr);
        ASSERT_EQ(a, b) << "pose " << i << " link " << l << " threshold " << thr;
        overlaps += a < 0.0;
        near += a >= 0.0 && a < kInf;
        std::vector<TriangleHit> ha, hb;
        ASSERT_EQ(culled.linkHits(link, t, thr, &ha), bullet.linkHits(link, t, thr, &hb));
        ASSERT_EQ(ha.size(), hb.size()) << "pose " << i << " link " << l;
        for (std::size_t k = 0; k < ha.size(); ++k) {
          EXPECT_EQ(ha[k].triangle, hb[k].triangle);
          EXPECT_EQ(ha[k].distance, hb[k].distance);
          EXPECT_EQ(ha[k].point, hb[k].point);
          EXPECT_EQ(ha[k].normal, hb[k].normal);
        }
      }
    }
  }
  EXPECT_GT(overlaps, 20);  // both the overlap and the distance paths are exercised
  EXPECT_GT(near, 20) << "overlaps " << overlaps;
}

// The culled queries return what Bullet's BVH query returns, bit for bit: distances with
// and without overlap, and the exact hits (triangles, order, distances, witness points). Box,
// cylinder and sphere links (reference hands) and hull links (a mesh palm and finger), link
// poses all around and inside the reference mug and basket.
TEST(CollisionScene, CulledQueriesMatchBulletQueries) {
  for (const char* object_name : {"mug", "basket"}) {
    const ObjectModel object =
        ObjectModel::load(std::string(TASKMAP_OBJECTS_DIR) + "/" + object_name + ".obj");
    for (const std::string& hand_path : {std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf",
                                         std::string(TASKMAP_HANDS_DIR) + "/humanoid/humanoid.urdf",
                                         std::string(TEST_DATA_DIR) + "/hands/hull_palm.urdf"}) {
      SCOPED_TRACE(std::string(object_name) + " " + hand_path);
      expectCulledEqualsBullet(object, HandModel::load(hand_path), 120, {5e-4, 0.02});
    }
  }
}

// The same on a real scan (YCB banana, 16k faces) with real hands: the Franka hand (mesh hulls,
// the face planes and the overlap proof of hulls), Allegro (boxes and spheres) and the humanoid
// hand (boxes: the one-walk overlap query within 1 mm), at 1 mm and the approach threshold.
TEST(CollisionScene, CulledQueriesMatchBulletOnARealScan) {
  const ObjectModel object =
      ObjectModel::load(std::string(TEST_DATA_DIR) + "/real/objects/ycb_011_banana.obj");
  for (const std::string& hand_path :
       {std::string(TEST_DATA_DIR) + "/real/hands/franka_hand/franka_hand.urdf",
        std::string(TEST_DATA_DIR) +
            "/real/hands/allegro_right/allegro_hand_description_right.urdf",
        std::string(TASKMAP_HANDS_DIR) + "/humanoid/humanoid.urdf"}) {
    SCOPED_TRACE(hand_path);
    expectCulledEqualsBullet(object, HandModel::load(hand_path), 30, {1e-3, 0.02});
  }
}

/// Link-link distances along a random walk of the relative pose of every link pair of `hand`,
/// with the axis carried from pose to pose, with a wrong axis and without: the same bits.
/// Returns the number of calls whose carried axis proved the pair apart (GJK skipped).
int expectAxisGivesSameDistances(const HandModel& hand) {
  const CollisionScene scene(testing::makeCylinder(0.03, 0.08, 12, 2), hand);
  const int n = static_cast<int>(hand.links().size());
  int skipped = 0, compared = 0, near = 0;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      if (a == b || hand.links()[static_cast<std::size_t>(a)].shapes.empty() ||
          hand.links()[static_cast<std::size_t>(b)].shapes.empty())
        continue;
      V axis = V::Zero(), wrong = V(0.3, -0.5, 0.8).normalized();
      Rng rng(17, static_cast<std::uint64_t>(a * n + b));
      Eigen::Isometry3d tb = Eigen::Isometry3d::Identity();
      tb.linear() = rng.rotation().toRotationMatrix();
      tb.translation() = V(rng.uniform(-0.05, 0.05), rng.uniform(-0.05, 0.05), 0.0);
      const Eigen::Isometry3d ta = Eigen::Isometry3d::Identity();
      const double radius = scene.linkRadius(a) + scene.linkRadius(b);
      for (int i = 0; i < 60; ++i) {
        // A small step of b around a, pulled back toward a so that the pair stays near.
        tb.translation() = 0.97 * tb.translation() +
                           0.004 * V(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
        const V turn = V(rng.uniform(-1, 1), 1.0, rng.uniform(-1, 1)).normalized();
        tb.linear() = (tb.linear() * Eigen::AngleAxisd(0.05, turn)).eval();
        for (double threshold : {1e-3, 0.01}) {
          const double plain = scene.linkLinkDistance(a, ta, b, tb, threshold);
          const V before = axis;
          bool apart = false;
          const double with_axis = scene.linkLinkDistance(a, ta, b, tb, threshold, &axis, &apart);
          // Proven apart without GJK: +inf, and +inf with the links swapped (what the closing's
          // second link of a pair reads without asking again).
          if (apart) {
            EXPECT_EQ(with_axis, kInf);
            EXPECT_EQ(scene.linkLinkDistance(b, tb, a, ta, threshold), kInf);
          }
          const double with_wrong = scene.linkLinkDistance(a, ta, b, tb, threshold, &wrong);
          EXPECT_EQ(std::memcmp(&plain, &with_axis, sizeof plain), 0)
              << a << " " << b << " " << i << ": " << plain << " vs " << with_axis;
          EXPECT_EQ(std::memcmp(&plain, &with_wrong, sizeof plain), 0)
              << plain << " " << with_wrong;
          // Spheres within reach, no distance and the axis unchanged: the axis decided.
          const bool by_axis =
              !before.isZero() && before == axis && plain == kInf &&
              (scene.linkCentre(a, ta) - scene.linkCentre(b, tb)).norm() <= radius + threshold;
          skipped += by_axis;
          if (by_axis) {
            EXPECT_TRUE(apart);
          }
          near += plain < kInf;
          ++compared;
        }
      }
    }
  EXPECT_GT(compared, 100);
  EXPECT_GT(near, 10);  // pairs within the threshold were compared
  return skipped;
}

// The separating axis carried from pose to pose (what the closing's self-collision test does)
// gives the distances of the plain call, bit for bit, and skips GJK on pairs with a hull; links
// of boxes and spheres ignore it (their GJK costs about what the test does).
TEST(CollisionScene, LinkLinkAxisGivesTheSameDistances) {
  for (const std::string& hand_path :
       {std::string(TEST_DATA_DIR) + "/hands/hull_palm.urdf",
        std::string(TEST_DATA_DIR) + "/real/hands/franka_hand/franka_hand.urdf"}) {
    SCOPED_TRACE(hand_path);
    EXPECT_GT(expectAxisGivesSameDistances(HandModel::load(hand_path)), 5);
  }
  for (const std::string& hand_path :
       {std::string(TEST_DATA_DIR) +
            "/real/hands/allegro_right/allegro_hand_description_right.urdf",
        std::string(TASKMAP_HANDS_DIR) + "/humanoid/humanoid.urdf"}) {
    SCOPED_TRACE(hand_path);
    EXPECT_EQ(expectAxisGivesSameDistances(HandModel::load(hand_path)), 0);
  }
}

}  // namespace
// The swept link box's own axes: the barrett palm (a box) turned 45 degrees about z, its face
// 5 mm from a face of a cube turned the same way, moved along that face (upward and sideways).
// The line of its box's centre meets the object's box grown by the link box's extent on every
// object axis, so only the box's own axis proves it clear; the distance query agrees along the
// ray. Moved toward the face it is not clear.
TEST(CollisionScene, LinkSweepClearSeesTheLinkBoxItsAxes) {
  TriangleMesh cube = testing::makeBox(0.1, 0.1, 0.1);
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(M_PI / 4, V::UnitZ()).toRotationMatrix();
  for (auto& v : cube.vertices) v = turn * v;
  const HandModel hand = HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf");
  const int link = hand.linkIndex("bh_palm");
  ASSERT_GE(link, 0);
  const CollisionScene scene(cube, hand);
  const double gap = 0.002;
  const V n = turn * V::UnitX();  // the cube face's normal, the link's x axis
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = turn;
  // bh_palm's box: 0.09 x 0.12 x 0.08 m, centred 0.04 m below the link frame.
  t.translation() = (0.05 + 0.045 + 0.005) * n + V(0, 0, 0.04);
  for (const V& dir : {V(V::UnitZ()), V(turn * V::UnitY())}) {
    const V c = t * V(0, 0, -0.04), grown = (turn.cwiseAbs() * V(0.045, 0.06, 0.04)).array() + gap;
    const V lo = -V::Constant(0.1 / std::sqrt(2.0)) - grown, hi = -lo;
    EXPECT_TRUE((c.array() > lo.array()).all() && (c.array() < hi.array()).all());
    EXPECT_TRUE(scene.linkSweepClear(link, t, dir, gap));
    for (int k = 0; k <= 60; ++k) {
      Eigen::Isometry3d moved = t;
      moved.translation() += (0.5 * k / 60.0) * dir;
      EXPECT_EQ(scene.linkDistance(link, moved, gap), kInf) << "step " << k;
    }
  }
  EXPECT_FALSE(scene.linkSweepClear(link, t, -n, gap));
  EXPECT_GE(scene.linkSweepLast(link, t, -n, gap), 0.005 - gap - 1e-9);
}

}  // namespace taskmap
