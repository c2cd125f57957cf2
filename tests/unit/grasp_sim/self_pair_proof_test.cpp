// Self-collision pairs proven apart over their joint's range (grasp_sim/src/self_pair_proof.cpp)
// against a dense scan of the range: a dropped pair is farther apart than the contact
// tolerance at every one of 4001 joint values; a pair that touches somewhere stays.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <string>
#include <vector>

#include "grasp_fixtures.hpp"
#include "sim_model.hpp"
#include "test_meshes.hpp"

namespace taskmap {
namespace {

/// Smallest distance (GJK, +inf beyond 1 m) of links a and b over 4001 values of actuated
/// joint `act`, evenly spaced over its limits.
double scanRange(const SimModel& m, int a, int b, int act) {
  const double lo = m.hand.lowerLimits()[act], hi = m.hand.upperLimits()[act];
  Eigen::VectorXd q = m.hand.preshape();
  double least = std::numeric_limits<double>::infinity();
  constexpr int kSamples = 4000;
  for (int i = 0; i <= kSamples; ++i) {
    q[act] = lo + (hi - lo) * i / kSamples;
    const auto poses = m.hand.linkPoses(q);
    least = std::min(least, m.scene->linkLinkDistance(a, poses[static_cast<std::size_t>(a)], b,
                                                      poses[static_cast<std::size_t>(b)], 1.0));
  }
  return least;
}

struct Pairs {
  std::vector<std::pair<int, int>> all, kept;
};

Pairs pairsOf(const std::string& hand_name) {
  const HandModel hand = HandModel::load(testing::testHandPath(hand_name));
  const TriangleMesh cylinder = testing::makeCylinder(0.03, 0.1, 32, 2);
  GraspSimDiagnostics every;
  every.self_pair_proofs = false;
  const SimModel with(cylinder, hand, {}, {}), without(cylinder, hand, {}, every);
  Pairs p;
  p.all = without.self_pairs;
  p.kept = with.self_pairs;
  // The kept pairs are the first model's, in its order.
  for (const auto& pr : p.kept) EXPECT_NE(std::find(p.all.begin(), p.all.end(), pr), p.all.end());
  const double tol = with.opt.contact_tolerance;
  for (const auto& [a, b] : p.all) {
    const bool dropped =
        std::find(p.kept.begin(), p.kept.end(), std::make_pair(a, b)) == p.kept.end();
    if (!dropped) continue;
    SCOPED_TRACE(hand.links()[static_cast<std::size_t>(a)].name + " / " +
                 hand.links()[static_cast<std::size_t>(b)].name);
    EXPECT_EQ(hand.jointNames().size(), 1u);  // these test hands have one actuated joint
    EXPECT_GT(scanRange(with, a, b, 0), tol);
  }
  return p;
}

// The knuckle jaw (a Robotiq 2F-85's linkage in boxes): every pair of its links stays apart over
// the knuckle's range (the scan's closest pair, the two pads, 1.3 cm apart at the closed
// limit), so none is tested.
TEST(SelfPairProof, AKnuckleJawsPairsAreProvenApart) {
  const Pairs p = pairsOf("knuckle_jaw");
  EXPECT_EQ(p.all.size(), 6u);
  EXPECT_TRUE(p.kept.empty());
}

// Jaws that close onto each other (the Panda's, mimic-coupled) meet at the closed limit: the
// pair stays, and the scan finds it within the tolerance.
TEST(SelfPairProof, JawsThatMeetStay) {
  const Pairs p = pairsOf("panda_mimic");
  ASSERT_EQ(p.all.size(), 1u);
  ASSERT_EQ(p.kept.size(), 1u);
  const HandModel hand = HandModel::load(testing::testHandPath("panda_mimic"));
  const SimModel m(testing::makeCylinder(0.03, 0.1, 32, 2), hand, {}, {});
  EXPECT_LE(scanRange(m, p.kept[0].first, p.kept[0].second, 0), m.opt.contact_tolerance);
}

// Hands whose pairs move with two or more actuated joints keep every pair (barrett: 15).
TEST(SelfPairProof, PairsOfSeveralJointsStay) {
  const HandModel hand = testing::referenceHand("barrett");
  const TriangleMesh cylinder = testing::makeCylinder(0.03, 0.1, 32, 2);
  GraspSimDiagnostics every;
  every.self_pair_proofs = false;
  const SimModel with(cylinder, hand, {}, {}), without(cylinder, hand, {}, every);
  EXPECT_EQ(with.self_pairs, without.self_pairs);
  EXPECT_FALSE(with.self_pairs.empty());
}

}  // namespace
}  // namespace taskmap
