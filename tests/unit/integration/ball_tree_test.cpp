// White-box test of the private pose-ball hierarchy (integration/src/ball_tree.hpp) against
// brute-force scans over every sample with the exact pose distance of 12-D embeddings.
#include "ball_tree.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "synthetic_map.hpp"
#include "taskmap/core/pose.hpp"
#include "taskmap/core/random.hpp"

namespace taskmap {
namespace {

using detail::PoseBallTree;
constexpr double kRho = 0.1;
constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

/// Samples as the tree gets them (quaternion signs mixed) and their embeddings.
struct Set {
  double rho = kRho;
  std::vector<Pose> poses;
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector4d> wxyz;
  std::vector<PoseEmbedding> embedded;
  void add(const Pose& pose, bool flip) {
    poses.push_back(pose);
    positions.push_back(pose.position);
    const Eigen::Quaterniond& q = pose.orientation;
    wxyz.emplace_back(Eigen::Vector4d(q.w(), q.x(), q.y(), q.z()) * (flip ? -1.0 : 1.0));
    embedded.push_back(embedPose(pose, rho));
  }
  std::size_t size() const { return poses.size(); }
};

/// A rotation of half-angle near pi/2 (w within 0.05 of 0, either sign).
Eigen::Quaterniond nearZeroW(Rng& rng) {
  const double w = rng.uniform(-0.05, 0.05);
  const Eigen::Vector3d v = std::sqrt(1 - w * w) * rng.direction();
  return Eigen::Quaterniond(w, v.x(), v.y(), v.z());
}

/// n samples: uniform (0.3 m box, uniform SO(3)) or clustered on the bars; 15% with w near 0.
Set makeSet(std::size_t n, bool clustered, std::uint64_t seed) {
  Rng rng(seed, clustered ? 1 : 0);
  Set s;
  for (std::size_t i = 0; i < n; ++i) {
    Pose p;
    if (clustered) {
      p = testing::barPose(rng, static_cast<int>(i % 3));
    } else {
      p.position = Eigen::Vector3d(rng.uniform(-0.15, 0.15), rng.uniform(-0.15, 0.15),
                                   rng.uniform(-0.15, 0.15));
      p.orientation = rng.rotation();
    }
    if (rng.uniform() < 0.15) p.orientation = nearZeroW(rng);
    s.add(p, rng.below(2) == 1);
  }
  return s;
}

/// Random queries: uniform, 1 m away from a sample, exactly a sample, with w near 0 beside a
/// sample, or a sample perturbed by up to 3 mm or 3 cm (rotation: that / rho radians); the
/// quaternion negated half the time.
Pose makeQuery(Rng& rng, const Set& s) {
  const Pose& base = s.poses[rng.below(s.size())];
  Pose q = base;
  const double sigma = rng.uniform(0.0, 0.03) * (rng.below(2) == 1 ? 1.0 : 0.1);
  const Eigen::Vector3d dp(rng.normal(), rng.normal(), rng.normal());
  const Eigen::Vector3d dw(rng.normal(), rng.normal(), rng.normal());
  switch (rng.below(6)) {
    case 0:
      q.position =
          Eigen::Vector3d(rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2));
      q.orientation = rng.rotation();
      break;
    case 1:
      q.position += rng.direction();
      break;
    case 2:
      break;
    case 3: {  // w near 0 beside a sample with w near 0 (if any): the ball straddles w = 0
      const Pose* b = &base;
      for (int t = 0; t < 100 && std::abs(b->orientation.w()) > 0.05; ++t)
        b = &s.poses[rng.below(s.size())];
      const double w = rng.uniform(-0.03, 0.03);
      const Eigen::Vector3d v = std::sqrt(1 - w * w) * b->orientation.vec().normalized();
      q.position = b->position + 0.1 * sigma * dp;
      q.orientation = Eigen::Quaterniond(w, v.x(), v.y(), v.z());
      break;
    }
    default:
      q.position += sigma * dp;
      q.orientation = (Eigen::Quaterniond(rotationExp(sigma / s.rho * dw)) * base.orientation);
      q.orientation.normalize();
  }
  if (rng.below(2) == 1) q.orientation.coeffs() *= -1.0;
  return q;
}

/// Whether sample i is nearer to -q than to q (found only by the search around -q).
bool flipped(const Pose& query, const Set& s, std::size_t i) {
  const Eigen::Quaterniond& q = query.orientation;
  const Eigen::Vector4d u(q.w(), q.x(), q.y(), q.z());
  return u.dot(s.wxyz[i]) * (u[0] < 0 ? -1 : 1) * (s.wxyz[i][0] < 0 ? -1 : 1) < 0;
}

struct Stats {
  std::size_t ball = 0, extra = 0, flipped = 0;
};

/// candidates() against the brute-force ball of radius r around query.
void checkCandidates(const PoseBallTree& tree, const Set& s, const Pose& query, double r,
                     Stats& stats) {
  std::vector<std::uint32_t> out = {7, 7, 7};
  ASSERT_TRUE(tree.candidates(query.position, query.orientation, r, out));
  const PoseEmbedding e = embedPose(query, s.rho);
  std::vector<char> seen(s.size(), 0);
  for (const std::uint32_t k : out) {
    ASSERT_LT(k, s.size());
    const std::uint32_t i = tree.order()[k];
    ASSERT_EQ(seen[i], 0) << "sample " << i << " reported twice, r " << r;
    seen[i] = 1;
    if ((s.embedded[i] - e).norm() > 1.01 * r + 1e-9) ++stats.extra;
  }
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (!((s.embedded[i] - e).norm() <= r)) continue;
    ++stats.ball;
    if (flipped(query, s, i)) ++stats.flipped;
    ASSERT_EQ(seen[i], 1) << "sample " << i << " at " << (s.embedded[i] - e).norm() << " missed, r "
                          << r << ", query w " << query.orientation.w();
  }
}

/// nearest() against the brute-force minimum of the same exact distance (ties: smaller key).
struct Exact {
  const Set* set;
  const PoseBallTree* tree;
  PoseEmbedding query;
  static double distance2(const void* context, std::uint32_t k) {
    const Exact* e = static_cast<const Exact*>(context);
    return (e->set->embedded[e->tree->order()[k]] - e->query).squaredNorm();
  }
};

/// Returns whether the nearest sample is nearer to -q than to q.
bool checkNearest(const PoseBallTree& tree, const Set& s, const Pose& query,
                  const std::vector<std::size_t>& keys) {
  const Exact exact{&s, &tree, embedPose(query, s.rho)};
  std::uint32_t best_k = 0;
  double best = kNan;
  for (std::uint32_t k = 0; k < s.size(); ++k) {
    const double d2 = Exact::distance2(&exact, k);
    if (k == 0 || d2 < best || (d2 == best && keys[k] < keys[best_k])) best_k = k, best = d2;
  }
  std::uint32_t got = 0;
  double got_d2 = kNan;
  EXPECT_TRUE(tree.nearest(query.position, query.orientation, {&exact, &Exact::distance2},
                           keys.data(), got, got_d2));
  EXPECT_EQ(got_d2, best) << "query w " << query.orientation.w();
  EXPECT_EQ(keys[got], keys[best_k]) << "distance " << std::sqrt(best);
  EXPECT_EQ(got_d2, Exact::distance2(&exact, got));
  return flipped(query, s, tree.order()[best_k]);
}

std::vector<std::size_t> orderKeys(const PoseBallTree& tree) {
  return std::vector<std::size_t>(tree.order().begin(), tree.order().end());
}

TEST(PoseBallTree, CandidatesCoverTheExactBallOnce) {
  for (const bool clustered : {false, true}) {
    const Set s = makeSet(3000, clustered, 11);
    const auto tree = PoseBallTree::build(s.positions, s.wxyz, s.rho);
    ASSERT_NE(tree, nullptr);
    const double radii[] = {0.0, 0.005, 0.018, 0.05};
    Stats stats[4];
    Rng rng(5, clustered ? 1 : 0);
    for (int n = 0; n < 2000; ++n) {
      const Pose query = makeQuery(rng, s);
      for (int j = 0; j < 4; ++j) {
        checkCandidates(*tree, s, query, radii[j], stats[j]);
        if (::testing::Test::HasFatalFailure()) return;
      }
    }
    for (int j = 0; j < 4; ++j) {
      SCOPED_TRACE(::testing::Message() << "clustered " << clustered << " r " << radii[j]);
      EXPECT_GT(stats[j].ball, 100u);  // exact-sample queries at least
      EXPECT_LE(stats[j].extra, stats[j].ball / 20);
      EXPECT_GE(stats[j].flipped, j > 0 ? 1u : 0u);  // r > 0: the search around -q mattered
    }
  }
}

TEST(PoseBallTree, OrderIsAPermutation) {
  for (const std::size_t n : {1, 5, 32, 33, 100, 3000}) {
    const Set s = makeSet(n, n % 2 == 0, 3);
    const auto tree = PoseBallTree::build(s.positions, s.wxyz, s.rho);
    ASSERT_NE(tree, nullptr);
    ASSERT_EQ(tree->size(), n);
    std::vector<int> count(n, 0);
    for (const std::uint32_t i : tree->order()) {
      ASSERT_LT(i, n);
      ++count[i];
    }
    for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(count[i], 1) << "sample " << i;
  }
}

TEST(PoseBallTree, NearestEqualsBruteForce) {
  for (const bool clustered : {false, true}) {
    const Set s = makeSet(3000, clustered, 13);
    const auto tree = PoseBallTree::build(s.positions, s.wxyz, s.rho);
    ASSERT_NE(tree, nullptr);
    const std::vector<std::size_t> keys = orderKeys(*tree);
    Rng rng(9, clustered ? 1 : 0);
    int flips = 0;
    for (int n = 0; n < 3000; ++n) flips += checkNearest(*tree, s, makeQuery(rng, s), keys);
    EXPECT_GT(flips, 0);  // the pass around -q mattered
  }
}

TEST(PoseBallTree, NearestBreaksTiesBySmallerKey) {
  // Every pose twice (samples i and n + i, the twin's quaternion negated): always a tie.
  const Set half = makeSet(1500, true, 17);
  Set s;
  for (int twin = 0; twin < 2; ++twin)
    for (std::size_t i = 0; i < half.size(); ++i) s.add(half.poses[i], twin == 1);
  const auto tree = PoseBallTree::build(s.positions, s.wxyz, s.rho);
  ASSERT_NE(tree, nullptr);
  std::vector<std::size_t> keys = orderKeys(*tree), reversed(keys.size());
  for (std::size_t k = 0; k < keys.size(); ++k) reversed[k] = 5 * s.size() - 3 * keys[k];
  Rng rng(21, 0);
  for (int n = 0; n < 1500; ++n) {
    const Pose query = makeQuery(rng, s);
    checkNearest(*tree, s, query, keys);
    checkNearest(*tree, s, query, reversed);
  }
}

TEST(PoseBallTree, RefusesWhatItCannotAnswer) {
  const Set s = makeSet(500, false, 23);
  const auto tree = PoseBallTree::build(s.positions, s.wxyz, s.rho);
  ASSERT_NE(tree, nullptr);
  const Pose q = s.poses[0];
  std::vector<std::uint32_t> out = {1, 2};
  for (const double r : {kNan, std::numeric_limits<double>::infinity(), -HUGE_VAL}) {
    EXPECT_FALSE(tree->candidates(q.position, q.orientation, r, out)) << r;
    EXPECT_TRUE(out.empty());
  }
  // Both signs of a quaternion within reach from r >= 1.94 rho on; just below, still answered.
  out = {1, 2};
  EXPECT_FALSE(tree->candidates(q.position, q.orientation, 1.95 * kRho, out));
  EXPECT_TRUE(out.empty());
  Rng rng(29, 0);
  Stats stats;
  for (int n = 0; n < 300; ++n) checkCandidates(*tree, s, makeQuery(rng, s), 1.9 * kRho, stats);
  EXPECT_GT(stats.flipped, 0u);
  // A non-finite query is refused (the caller then asks the index), not an empty ball.
  out = {1, 2};
  EXPECT_FALSE(tree->candidates(Eigen::Vector3d(kNan, 0, 0), q.orientation, 0.05, out));
  EXPECT_TRUE(out.empty());
  EXPECT_FALSE(tree->candidates(q.position, Eigen::Quaterniond(kNan, 0, 0, 0), 0.05, out));
  const auto coarse = PoseBallTree::build(s.positions, s.wxyz, 0.001);
  ASSERT_NE(coarse, nullptr);
  EXPECT_FALSE(coarse->candidates(q.position, q.orientation, 1.0, out));
  EXPECT_TRUE(out.empty());

  const Exact exact{&s, tree.get(), embedPose(q, s.rho)};
  const std::vector<std::size_t> keys = orderKeys(*tree);
  std::uint32_t best = 77;
  double best_d2 = -1;
  const Eigen::Vector3d bad[] = {{kNan, 0, 0}, {0, HUGE_VAL, 0}};
  for (const Eigen::Vector3d& p : bad)
    EXPECT_FALSE(
        tree->nearest(p, q.orientation, {&exact, &Exact::distance2}, keys.data(), best, best_d2));
  EXPECT_FALSE(tree->nearest(q.position, Eigen::Quaterniond(kNan, 0, 0, 0),
                             {&exact, &Exact::distance2}, keys.data(), best, best_d2));
  EXPECT_EQ(best, 77u);
  EXPECT_EQ(best_d2, -1);

  EXPECT_EQ(PoseBallTree::build({}, {}, kRho), nullptr);
  const std::vector<Eigen::Vector4d> one_q = {Eigen::Vector4d(1, 0, 0, 0)};
  EXPECT_EQ(PoseBallTree::build({Eigen::Vector3d(0, 1e18, 0)}, one_q, kRho), nullptr);
  EXPECT_EQ(PoseBallTree::build({Eigen::Vector3d(0, 0, -2e18)}, one_q, kRho), nullptr);
  EXPECT_NE(PoseBallTree::build({Eigen::Vector3d(0, 1e17, 0)}, one_q, kRho), nullptr);
}

// A radius that meets more leaves than a search defers (256 of 32 points): the rest are
// scanned as they are met, and the candidates still cover the ball once.
TEST(PoseBallTree, RadiusMeetingManyLeaves) {
  Set s = makeSet(20000, false, 31);
  s.rho = 1.0;  // r = 1.9 rho then holds most samples (every position, most rotations)
  for (std::size_t i = 0; i < s.size(); ++i) s.embedded[i] = embedPose(s.poses[i], s.rho);
  const auto tree = PoseBallTree::build(s.positions, s.wxyz, s.rho);
  ASSERT_NE(tree, nullptr);
  Rng rng(37, 0);
  Stats stats;
  for (int n = 0; n < 20; ++n) checkCandidates(*tree, s, makeQuery(rng, s), 1.9 * s.rho, stats);
  EXPECT_GT(stats.ball, 20u * 300u * 32u);  // well over 256 leaves' worth per query
}

TEST(PoseBallTree, TinySets) {
  for (const std::size_t n : {1, 5, 32, 33}) {
    SCOPED_TRACE(n);
    const Set s = makeSet(n, n == 33, 31 + n);
    const auto tree = PoseBallTree::build(s.positions, s.wxyz, s.rho);
    ASSERT_NE(tree, nullptr);
    const std::vector<std::size_t> keys = orderKeys(*tree);
    Rng rng(37, n);
    Stats stats;
    for (int k = 0; k < 500; ++k) {
      const Pose query = makeQuery(rng, s);
      for (const double r : {0.0, 0.05, 0.15}) checkCandidates(*tree, s, query, r, stats);
      checkNearest(*tree, s, query, keys);
    }
    EXPECT_GT(stats.ball, 0u);
  }
}

}  // namespace
}  // namespace taskmap
