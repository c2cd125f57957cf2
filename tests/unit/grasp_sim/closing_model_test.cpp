// The closing check's Bullet shapes (grasp_sim/src/closing_model.hpp, white box).
// Oracles: a hull's bounding box is its points' extremes grown by twice the margin (and the pad),
// not by Bullet's default 4 cm margin that its constructor cached; the compounds keep the contact
// breaking thresholds of the stale boxes; the object's padded pieces give the same contacts with
// a box link and a hull link as the stale shapes (boxes grown by 4 cm: a superset of every pair
// in contact distance) at random poses, in fewer narrow-phase pairs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btCollisionWorld.h>
#include <BulletCollision/CollisionDispatch/btDefaultCollisionConfiguration.h>
#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btCompoundShape.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
#include <Eigen/Geometry>

#include "closing_model.hpp"
#include "collision_data.hpp"

namespace taskmap {
namespace {

constexpr double kMargin = 5e-4;

std::vector<Eigen::Vector3d> blob(std::mt19937* rng, const Eigen::Vector3d& centre, double size) {
  std::uniform_real_distribution<double> u(-size, size);
  std::vector<Eigen::Vector3d> p;
  for (int i = 0; i < 30; ++i) p.push_back(centre + Eigen::Vector3d(u(*rng), u(*rng), u(*rng)));
  return p;
}

/// Pieces of a ring (a non-convex object), 2-3 cm blobs around a 6 cm circle.
std::vector<std::vector<Eigen::Vector3d>> ringPieces() {
  std::mt19937 rng(7);
  std::vector<std::vector<Eigen::Vector3d>> pieces;
  for (int k = 0; k < 12; ++k) {
    const double a = 2.0 * M_PI * k / 12.0;
    pieces.push_back(blob(&rng, Eigen::Vector3d(0.06 * std::cos(a), 0.06 * std::sin(a), 0.0),
                          0.012 + 0.002 * (k % 3)));
  }
  return pieces;
}

/// A hull as the check built it before (Bullet's constructor, then the margin: the cached box
/// keeps the 4 cm default margin).
std::unique_ptr<btConvexHullShape> staleHull(const std::vector<Eigen::Vector3d>& points) {
  auto hull = std::make_unique<btConvexHullShape>(
      points.front().data(), static_cast<int>(points.size()), sizeof(Eigen::Vector3d));
  hull->optimizeConvexHull();
  hull->setMargin(kMargin);
  return hull;
}

TEST(ClosingModel, HullBoxIsItsPointsGrownByTheMarginAndPad) {
  std::mt19937 rng(3);
  const std::vector<Eigen::Vector3d> p = blob(&rng, Eigen::Vector3d(0.1, -0.2, 0.05), 0.01);
  Eigen::AlignedBox3d want;
  for (const auto& v : p) want.extend(v);
  for (const double pad : {0.0, 0.002}) {
    const auto hull = hullShape(p, kMargin, pad);
    btVector3 lo, hi;
    hull->getAabb(btTransform::getIdentity(), lo, hi);
    const double grow = 2.0 * kMargin + pad;  // cached margin + pad, and getAabb's margin
    // optimizeConvexHull rounds the hull's vertices (integer hull computer): a few micrometres
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(lo[i], want.min()[i] - grow, 5e-6) << "axis " << i << " pad " << pad;
      EXPECT_NEAR(hi[i], want.max()[i] + grow, 5e-6) << "axis " << i << " pad " << pad;
    }
  }
  // What the check had before: Bullet's default margin in the cached box.
  btVector3 lo, hi;
  staleHull(p)->getAabb(btTransform::getIdentity(), lo, hi);
  EXPECT_NEAR(hi.x(), want.max().x() + 0.04 + kMargin, 1e-9);
}

struct Scene {
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btCollisionWorld world{&dispatcher, &broadphase, &config};
};

/// Contact distances between `object` (at the identity) and `link` at `pose`, sorted, and the
/// number of narrow-phase pairs (manifolds) Bullet processed.
std::pair<std::vector<double>, int> contacts(btCollisionShape* object, btCollisionShape* link,
                                             const btTransform& pose) {
  Scene s;
  btCollisionObject a, b;
  a.setCollisionShape(object);
  b.setCollisionShape(link);
  b.setWorldTransform(pose);
  s.world.addCollisionObject(&a);
  s.world.addCollisionObject(&b);
  s.world.performDiscreteCollisionDetection();
  std::vector<double> d;
  for (int k = 0; k < s.dispatcher.getNumManifolds(); ++k) {
    const btPersistentManifold* m = s.dispatcher.getManifoldByIndexInternal(k);
    for (int c = 0; c < m->getNumContacts(); ++c) d.push_back(m->getContactPoint(c).getDistance());
  }
  std::sort(d.begin(), d.end());
  const int pairs = s.dispatcher.getNumManifolds();
  s.world.removeCollisionObject(&b);
  s.world.removeCollisionObject(&a);
  return {d, pairs};
}

/// The object (ring pieces) and a link (a box, or a hull) as the check builds them now and as
/// it built them before (stale boxes).
struct Bodies {
  std::vector<std::vector<Eigen::Vector3d>> pieces = ringPieces();
  std::vector<Eigen::Vector3d> finger;
  std::vector<std::unique_ptr<btConvexShape>> own;
  btCompoundShape stale_object{true, 12}, stale_box{true, 1}, stale_hull{true, 1};
  ClosingCompound object{12}, box{1}, hull{1};
  Bodies() {
    std::mt19937 rng(5);
    finger = blob(&rng, Eigen::Vector3d::Zero(), 0.008);
    const btTransform at(btQuaternion::getIdentity(), btVector3(0.003, 0, 0));
    own.push_back(std::make_unique<btBoxShape>(btVector3(0.01, 0.004, 0.02)));
    own.back()->setMargin(kMargin);
    box.addChildShape(at, own.back().get());
    stale_box.addChildShape(at, own.back().get());
    box.disc = staleDisc(box, {nullptr}, kMargin);
    own.push_back(hullShape(finger, kMargin, 0.0));
    hull.addChildShape(at, own.back().get());
    hull.disc = staleDisc(hull, {&finger}, kMargin);
    own.push_back(staleHull(finger));
    stale_hull.addChildShape(at, own.back().get());
    btCompoundShape tight(false, 12);
    std::vector<const std::vector<Eigen::Vector3d>*> points;
    for (const auto& p : pieces) {
      own.push_back(hullShape(p, kMargin, 0.0));
      tight.addChildShape(btTransform::getIdentity(), own.back().get());
      points.push_back(&p);
    }
    object.disc = staleDisc(tight, points, kMargin);
    const double pad =
        gContactBreakingThreshold * std::min(object.disc, std::max(box.disc, hull.disc));
    for (const auto& p : pieces) {
      own.push_back(hullShape(p, kMargin, pad));
      object.addChildShape(btTransform::getIdentity(), own.back().get());
      own.push_back(staleHull(p));
      stale_object.addChildShape(btTransform::getIdentity(), own.back().get());
    }
  }
};

TEST(ClosingModel, ContactBreakingThresholdsAreTheStaleBoxes) {
  Bodies b;
  const double k = gContactBreakingThreshold;
  EXPECT_EQ(b.object.getContactBreakingThreshold(k), b.stale_object.getContactBreakingThreshold(k));
  EXPECT_EQ(b.hull.getContactBreakingThreshold(k), b.stale_hull.getContactBreakingThreshold(k));
  EXPECT_EQ(b.box.getContactBreakingThreshold(k), b.stale_box.getContactBreakingThreshold(k));
  // The stale hull box made the finger's threshold larger than its own box gives.
  btCompoundShape plain(true, 1);
  plain.addChildShape(b.hull.getChildTransform(0), b.hull.getChildShape(0));
  EXPECT_GT(b.hull.getContactBreakingThreshold(k), plain.getContactBreakingThreshold(k) + 1e-3);
}

TEST(ClosingModel, PaddedPiecesFindTheContactsOfStaleBoxesInFewerPairs) {
  Bodies b;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int touching = 0, pairs_now = 0, pairs_stale = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const double a = M_PI * u(rng);
    const Eigen::Vector3d at(0.075 * std::cos(a), 0.075 * std::sin(a), 0.02 * u(rng));
    const Eigen::Quaterniond q =
        Eigen::Quaterniond(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized());
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = q.toRotationMatrix();
    pose.translation() = at;
    const bool hull = trial % 2 == 1;
    const auto [dn, nn] = contacts(&b.object, hull ? &b.hull : &b.box, bt(pose));
    const auto [ds, ns] = contacts(&b.stale_object, hull ? &b.stale_hull : &b.stale_box, bt(pose));
    ASSERT_EQ(dn.size(), ds.size()) << "trial " << trial;
    for (std::size_t i = 0; i < dn.size(); ++i) EXPECT_NEAR(dn[i], ds[i], 1e-12);
    touching += !dn.empty();
    pairs_now += nn;
    pairs_stale += ns;
  }
  EXPECT_GT(touching, 50);                // the poses test contacts, not only misses
  EXPECT_LT(2 * pairs_now, pairs_stale);  // and the tight boxes skip far pairs
}

}  // namespace
}  // namespace taskmap
