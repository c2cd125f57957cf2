// End-state comfort costs (eq. 1.8-1.10) and the cluster ranking of paper 1.6.2.
#include "taskmap/integration/initialisation.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "error_matchers.hpp"
#include "synthetic_map.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

TEST(JointLimitCost, MatchesFormulaAndGradient) {
  Eigen::VectorXd lo(3), hi(3), q(3);
  lo << -1, 0, -2;
  hi << 1, 2, 0;
  q << 0.5, 2, -2;
  // 1/2 ((0.5 - 0) / 2)^2 + 1/2 ((2 - 1) / 2)^2 + 1/2 ((-2 + 1) / 2)^2
  Eigen::VectorXd g;
  EXPECT_DOUBLE_EQ(jointLimitCost(q, lo, hi, &g), 0.5 * (0.0625 + 0.25 + 0.25));
  for (int i = 0; i < 3; ++i) {
    Eigen::VectorXd a = q, b = q;
    a[i] += 1e-6;
    b[i] -= 1e-6;
    EXPECT_NEAR(g[i], (jointLimitCost(a, lo, hi) - jointLimitCost(b, lo, hi)) / 2e-6, 1e-8);
  }
  EXPECT_DOUBLE_EQ(jointLimitCost(Eigen::Vector3d(0, 1, -1), lo, hi), 0.0);
  EXPECT_EQ(testing::errorMessage([&] { jointLimitCost(q, hi, lo); }),
            "joint limits of joint 0: need finite lower < upper");
}

TEST(CollisionCost, PiecewiseFormulaIsC1) {
  const double zone = 0.05, s = 2.0;
  EXPECT_DOUBLE_EQ(collisionPairCost(0.06, zone, s), 0.0);
  EXPECT_DOUBLE_EQ(collisionPairCost(0.02, zone, s), s * 0.03 * 0.03);
  EXPECT_DOUBLE_EQ(collisionPairCost(-0.01, zone, s), s * zone * (zone + 0.02));
  for (double d : {-1e-12, 1e-12, zone - 1e-12, zone + 1e-12}) {  // continuity at 0 and d_B
    const double a = d < 0 || (d > 0 && d < 0.01) ? 0.0 : zone;
    EXPECT_NEAR(collisionPairCost(d, zone, s), collisionPairCost(a, zone, s), 1e-10);
  }
  double d_minus = 0, d_plus = 0;
  collisionPairCost(-1e-9, zone, s, &d_minus);
  collisionPairCost(1e-9, zone, s, &d_plus);
  EXPECT_NEAR(d_minus, d_plus, 1e-7);  // slope continuous at contact
  EXPECT_DOUBLE_EQ(collisionCost({0.06, 0.02, -0.01}, zone, s),
                   collisionPairCost(0.02, zone, s) + collisionPairCost(-0.01, zone, s));
}

TEST(RankClusters, BestComfortFirstUnreachableLast) {
  const TaskMap map = TaskMap::fromData(testing::syntheticMap(300));
  Pose object;
  object.position = Eigen::Vector3d(0.5, 0, 0.8);
  object.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  // A fake "arm": posture = target position; cluster 1's target is out of reach.
  const Pose rep1 =
      map.pose(static_cast<std::size_t>(map.data().clustering->clusters[1].representative));
  int calls = 0;
  IkFunction ik = [&](const Pose& target) {
    ++calls;
    IkSolution s;
    const Pose in_object =
        Pose{object.orientation.conjugate() * (target.position - object.position),
             object.orientation.conjugate() * target.orientation};
    if (poseDistance(in_object, rep1, 0.1) < 1e-9) {
      s.message = "out of reach";
      return s;
    }
    s.success = true;
    s.q = target.position;
    return s;
  };
  Eigen::Vector3d lo(0, -1, 0), hi(1, 1, 2);
  const ComfortFunction comfort = makeComfort(lo, hi);
  const auto ranks = rankClusters(map, object, ik, comfort);
  ASSERT_EQ(ranks.size(), 3u);
  EXPECT_EQ(calls, 3);
  EXPECT_TRUE(ranks[0].reachable);
  EXPECT_TRUE(ranks[1].reachable);
  EXPECT_LE(ranks[0].comfort, ranks[1].comfort);
  EXPECT_EQ(ranks[2].cluster, 1);
  EXPECT_FALSE(ranks[2].reachable);
  EXPECT_EQ(ranks[2].message, "out of reach");
  for (const auto& r : ranks) {
    if (!r.reachable) continue;
    EXPECT_DOUBLE_EQ(r.comfort, jointLimitCost(r.q, lo, hi));
    EXPECT_LT((r.target_world.position -
               (object.position + object.orientation * r.target_object.position))
                  .norm(),
              1e-12);
  }
  TaskMapData plain = testing::syntheticMap(30);
  plain.clustering.reset();
  EXPECT_EQ(
      testing::errorMessage([&] { rankClusters(TaskMap::fromData(plain), object, ik, comfort); }),
      "rankClusters: the map has no clusters; cluster the map first");
}

}  // namespace
}  // namespace taskmap
