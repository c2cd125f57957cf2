// The cluster ranking of paper 1.6.2 with a caller's inverse kinematics and comfort (the
// comfort costs themselves: tests/unit/reaching/robot_costs_test.cpp).
#include "taskmap/integration/initialisation.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "error_matchers.hpp"
#include "synthetic_map.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

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
  // Squared distance from the middle of the box: any comfort the caller gives.
  const auto middle_distance = [lo, hi](const Eigen::VectorXd& q) {
    return (q - 0.5 * (lo + hi)).squaredNorm();
  };
  const ComfortFunction comfort = middle_distance;
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
    EXPECT_DOUBLE_EQ(r.comfort, middle_distance(r.q));
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
