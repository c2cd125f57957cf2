// The lean exact queries (grasp_sim/src/lean_query.cpp) against their oracle, Bullet's BVH
// query with every exact hit (CollisionScene::Mode::kBullet) scanned in full: the nearest hit
// (all, or those facing a direction; its distance, or the whole first hit of that distance),
// the deep-press test, the penetrating-only hits, the nearest hit from what an overlap question
// saw, and the shrinking thresholds of conservative advancement give the same answers bit for
// bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "collision_scene.hpp"
#include "taskmap/core/random.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap {
namespace {

using V = Eigen::Vector3d;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kTol = 5e-4;

double nearestByScan(const std::vector<TriangleHit>& hits, const CollisionScene& s,
                     const FacingFilter* f) {
  double best = kInf;
  for (const TriangleHit& h : hits) {
    const V& n = s.faceNormal(h.triangle);
    if (!f || (n.dot(f->away) < -f->opposing && h.normal.dot(n) >= f->min_agreement))
      best = std::min(best, h.distance);
  }
  return best;
}

bool deeperByScan(const std::vector<TriangleHit>& hits, const CollisionScene& s, double depth) {
  for (const TriangleHit& h : hits)
    if (-h.distance > depth && h.normal.dot(s.faceNormal(h.triangle)) >= 0.5) return true;
  return false;
}

/// The squeeze's contact by scan: the first of the closest hits whose separation direction is
/// within 60 degrees of its face normal, null when none.
const TriangleHit* firstFacingByScan(const std::vector<TriangleHit>& hits,
                                     const CollisionScene& s) {
  const TriangleHit* first = nullptr;
  for (const TriangleHit& h : hits)
    if (h.normal.dot(s.faceNormal(h.triangle)) >= 0.5 && (!first || h.distance < first->distance))
      first = &h;
  return first;
}

struct Counts {
  int deep = 0, shallow = 0, filtered = 0, penetrating = 0, nearest_hits = 0, seen_hits = 0;
};

/// Every lean query of link `link` at pose `t` against the scan of the baseline's hits.
void compareLink(const CollisionScene& lean, const CollisionScene& base, int link,
                 const Eigen::Isometry3d& t, Rng& rng, Counts* c) {
  std::vector<TriangleHit> all;
  const double base_min = base.linkHits(link, t, kTol, &all);
  ASSERT_EQ(lean.linkNearest(link, t, kTol, nullptr), base_min);
  ASSERT_EQ(base.linkNearest(link, t, kTol, nullptr), base_min);
  for (int k = 0; k < 3; ++k) {
    FacingFilter f;
    f.away = V(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)).normalized();
    const double expect = nearestByScan(all, base, &f);
    ASSERT_EQ(lean.linkNearest(link, t, kTol, &f), expect) << "filter " << k;
    c->filtered += expect < kInf;
  }
  // The squeeze's contact: the closest hit on a facing triangle (any direction), the first in
  // the hits' order among equals, the whole hit.
  {
    FacingFilter f;
    f.any_direction = true;
    const TriangleHit* first = firstFacingByScan(all, base);
    TriangleHit got, got_base;
    const double d = lean.linkNearest(link, t, kTol, &f, &got);
    ASSERT_EQ(base.linkNearest(link, t, kTol, &f, &got_base), d);
    if (!first) {
      ASSERT_EQ(d, kInf);
    } else {
      ASSERT_EQ(d, first->distance);
      for (const TriangleHit* h : {&got, &got_base}) {
        EXPECT_EQ(h->triangle, first->triangle);
        EXPECT_EQ(h->point, first->point);
        EXPECT_EQ(h->normal, first->normal);
      }
      c->nearest_hits += 1;
    }
  }
  for (double depth : {1e-4, 1e-3, 3e-3}) {
    const bool expect = deeperByScan(all, base, depth);
    ASSERT_EQ(lean.linkPressesDeeper(link, t, kTol, depth, 0.5), expect) << "depth " << depth;
    ASSERT_EQ(base.linkPressesDeeper(link, t, kTol, depth, 0.5), expect);
    (expect ? c->deep : c->shallow) += 1;
  }
  // Hits within 1e-9 m: every penetrating hit of the tolerance query, same order and values.
  std::vector<TriangleHit> pen;
  lean.linkHits(link, t, 1e-9, &pen);
  std::vector<TriangleHit> expect_pen, got_pen;
  for (const auto& h : all)
    if (h.distance < 0.0) expect_pen.push_back(h);
  for (const auto& h : pen)
    if (h.distance < 0.0) got_pen.push_back(h);
  ASSERT_EQ(got_pen.size(), expect_pen.size());
  for (std::size_t k = 0; k < got_pen.size(); ++k) {
    EXPECT_EQ(got_pen[k].triangle, expect_pen[k].triangle);
    EXPECT_EQ(got_pen[k].distance, expect_pen[k].distance);
    EXPECT_EQ(got_pen[k].point, expect_pen[k].point);
    EXPECT_EQ(got_pen[k].normal, expect_pen[k].normal);
  }
  c->penetrating += !expect_pen.empty();
}

/// The squeeze's contact (the nearest hit on a facing triangle, any direction) and a facing
/// filter's nearest distance, from what the overlap question at the same pose saw (a link of
/// one box whose walk met no overlap), against the scan of the baseline's hits; another pose
/// falls back to the tree.
void compareSeen(const CollisionScene& lean, const CollisionScene& base, int link,
                 const Eigen::Isometry3d& t, Rng& rng, Counts* c) {
  SeenTriangles seen;
  ASSERT_EQ(lean.linkDistance(link, t, kTol, &seen), lean.linkDistance(link, t, kTol));
  if (!seen.complete) return;
  std::vector<TriangleHit> all;
  base.linkHits(link, t, kTol, &all);
  FacingFilter f;
  f.any_direction = true;
  const TriangleHit* first = firstFacingByScan(all, base);
  TriangleHit got;
  const double d = lean.linkNearest(link, t, kTol, &f, &got, seen);
  ASSERT_EQ(d, first ? first->distance : kInf);
  if (first) {
    EXPECT_EQ(got.triangle, first->triangle);
    EXPECT_EQ(got.point, first->point);
    EXPECT_EQ(got.normal, first->normal);
    c->seen_hits += 1;
  }
  FacingFilter g;
  g.away = V(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)).normalized();
  ASSERT_EQ(lean.linkNearest(link, t, kTol, &g, nullptr, seen), nearestByScan(all, base, &g));
  Eigen::Isometry3d moved = t;
  moved.translation().x() += 1e-4;
  ASSERT_EQ(lean.linkNearest(link, moved, kTol, &f, nullptr, seen),
            lean.linkNearest(link, moved, kTol, &f));
}

/// Link `link` at `t` moved toward its nearest triangle (within 2 cm) to about kTol / 2 from it:
/// where the squeeze asks (a link stopped within the tolerance). `t` when nothing is that near.
Eigen::Isometry3d nearTouch(const CollisionScene& lean, int link, const Eigen::Isometry3d& t) {
  TriangleHit h;
  const double d = lean.linkNearest(link, t, 0.02, nullptr, &h);
  if (!(d > kTol && d < 0.02)) return t;
  Eigen::Isometry3d out = t;
  out.translation() -= (d - 0.5 * kTol) * h.normal;
  return out;
}

/// Conservative advancement (Trial::evalNearest): each link asked within the smallest distance
/// found so far (+1e-9, at least kTol, at most `far`) gives the minimum over the links at `far`
/// and every distance <= kTol unchanged.
void compareAdvancement(const CollisionScene& lean, const CollisionScene& base,
                        const std::vector<int>& links, const Eigen::Isometry3d& t) {
  const double far = 0.02;
  double expect = kInf, mn = kInf;
  for (int l : links) {
    const double b = base.linkDistance(l, t, far);
    expect = std::min(expect, b);
    const double a = lean.linkDistance(l, t, std::min(far, std::max(mn + 1e-9, kTol)));
    if (b <= kTol) {
      ASSERT_EQ(a, b) << "link " << l;
    }
    mn = std::min(mn, a);
  }
  ASSERT_EQ(mn, expect);
}

TEST(LeanQueries, MatchTheScanOfEveryExactHit) {
  for (const char* object_name : {"mug", "basket"}) {
    const ObjectModel object =
        ObjectModel::load(std::string(TASKMAP_OBJECTS_DIR) + "/" + object_name + ".obj");
    for (const std::string& hand_path : {std::string(TASKMAP_HANDS_DIR) + "/humanoid/humanoid.urdf",
                                         std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf",
                                         std::string(TEST_DATA_DIR) + "/hands/hull_palm.urdf"}) {
      SCOPED_TRACE(std::string(object_name) + " " + hand_path);
      const HandModel hand = HandModel::load(hand_path);
      const CollisionScene lean(object.mesh(), hand, CollisionScene::Mode::kCulled);
      const CollisionScene base(object.mesh(), hand, CollisionScene::Mode::kBullet);
      std::vector<int> links;
      for (std::size_t l = 0; l < hand.links().size(); ++l)
        if (!hand.links()[l].shapes.empty()) links.push_back(static_cast<int>(l));
      Counts c;
      for (int i = 0; i < 50; ++i) {
        Rng rng(23, static_cast<std::uint64_t>(i));
        Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
        t.linear() = rng.rotation().toRotationMatrix();
        // Poses near the surface: a point inside, pushed out by up to 3 cm.
        t.translation() = object.sampleInside(rng) +
                          0.03 * V(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
        SCOPED_TRACE("pose " + std::to_string(i));
        for (int l : links) {
          SCOPED_TRACE("link " + std::to_string(l));
          ASSERT_NO_FATAL_FAILURE(compareLink(lean, base, l, t, rng, &c));
          ASSERT_NO_FATAL_FAILURE(compareSeen(lean, base, l, nearTouch(lean, l, t), rng, &c));
        }
        Eigen::Isometry3d away = t;  // the same hand backed off: a free pose to advance from
        away.translation() += 0.01 * t.linear().col(2);
        ASSERT_NO_FATAL_FAILURE(compareAdvancement(lean, base, links, away));
      }
      // Both answers of every question occur.
      EXPECT_GT(c.deep, 5);
      EXPECT_GT(c.shallow, 5);
      EXPECT_GT(c.filtered, 5);
      EXPECT_GT(c.penetrating, 5);
      EXPECT_GT(c.nearest_hits, 5);
      if (hand_path.find("hull_palm") == std::string::npos) {
        EXPECT_GT(c.seen_hits, 5);
      }
    }
  }
}

}  // namespace
}  // namespace taskmap
