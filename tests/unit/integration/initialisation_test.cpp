// The cluster ranking of paper 1.6.2 with a caller's inverse kinematics and comfort (the
// comfort costs themselves: tests/unit/reaching/robot_costs_test.cpp).
#include "taskmap/integration/initialisation.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <set>
#include <vector>

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

/// A fake arm for the fallbacks: posture = target position; out of reach unless reach(i) for
/// the grasp i whose pose the target is (object at the origin). Counts the grasps asked.
struct FakeArm {
  const TaskMap* map;
  std::function<bool(std::size_t)> reach;
  std::vector<std::size_t> asked;
  IkFunction ik() {
    return [this](const Pose& target) {
      IkSolution s;
      for (std::size_t i = 0; i < map->size(); ++i)
        if (poseDistance(target, map->pose(i), 0.1) < 1e-9) {
          asked.push_back(i);
          if (reach(i)) {
            s.success = true;
            s.q = target.position;
          } else {
            s.message = "out of reach";
          }
          return s;
        }
      ADD_FAILURE() << "the IK was asked for a pose that is no grasp of the map";
      return s;
    };
  }
};

std::size_t representative(const TaskMap& map, int c) {
  return static_cast<std::size_t>(
      map.data().clustering->clusters[static_cast<std::size_t>(c)].representative);
}

int label(const TaskMap& map, std::size_t i) {
  return map.data().clustering->labels[i];
}

bool isRepresentative(const TaskMap& map, std::size_t i) {
  for (int c = 0; c < map.numClusters(); ++c)
    if (representative(map, c) == i) return true;
  return false;
}

double distanceToRepresentative(const TaskMap& map, std::size_t i) {
  return poseDistance(map.pose(i), map.pose(representative(map, label(map, i))),
                      map.rotationScale());
}

TEST(RankClusters, MembersStandInWhenNoRepresentativeIsReachable) {
  const TaskMap map = TaskMap::fromData(testing::syntheticMap(300));
  const ComfortFunction comfort = [](const Eigen::VectorXd& q) { return q.norm(); };
  FakeArm arm{&map, [&](std::size_t i) { return !isRepresentative(map, i); }, {}};
  // Without member tries no cluster is reachable (the paper's rule).
  auto ranks = rankClusters(map, Pose{}, arm.ik(), comfort);
  ASSERT_EQ(ranks.size(), 3u);
  for (const ClusterRank& r : ranks) {
    EXPECT_FALSE(r.reachable);
    EXPECT_EQ(r.target, r.representative);
    EXPECT_EQ(r.tried, 1);
    EXPECT_EQ(r.message, "out of reach");
  }
  // With them, each cluster's farthest member from its representative is tried next, reached.
  arm.asked.clear();
  ranks = rankClusters(map, Pose{}, arm.ik(), comfort, RankOptions{4});
  ASSERT_EQ(ranks.size(), 3u);
  for (const ClusterRank& r : ranks) {
    EXPECT_TRUE(r.reachable) << r.cluster;
    EXPECT_EQ(label(map, r.target), r.cluster);
    EXPECT_EQ(r.representative, representative(map, r.cluster));
    EXPECT_NE(r.target, r.representative);
    EXPECT_EQ(r.tried, 2);
    EXPECT_LT(poseDistance(r.target_world, map.pose(r.target), 0.1), 1e-12);
    EXPECT_TRUE(r.message.empty()) << r.message;
    double farthest = 0.0;
    for (std::size_t i = 0; i < map.size(); ++i)
      if (label(map, i) == r.cluster)
        farthest = std::max(farthest, distanceToRepresentative(map, i));
    EXPECT_DOUBLE_EQ(distanceToRepresentative(map, r.target), farthest);
  }
  EXPECT_EQ(arm.asked.size(), 6u);
}

TEST(RankClusters, NoMemberIsTriedWhileARepresentativeIsReachable) {
  const TaskMap map = TaskMap::fromData(testing::syntheticMap(300));
  const std::size_t rep1 = representative(map, 1);
  const ComfortFunction comfort = [](const Eigen::VectorXd& q) { return q.norm(); };
  FakeArm arm{&map, [&](std::size_t i) { return i != rep1; }, {}};
  const auto ranks = rankClusters(map, Pose{}, arm.ik(), comfort, RankOptions{16});
  ASSERT_EQ(ranks.size(), 3u);
  EXPECT_EQ(arm.asked.size(), 3u);
  EXPECT_EQ(ranks[2].cluster, 1);
  EXPECT_FALSE(ranks[2].reachable);
  EXPECT_EQ(ranks[2].target, rep1);
}

TEST(RankClusters, MemberTriesAreBoundedAndSpreadOverTheCluster) {
  const TaskMap map = TaskMap::fromData(testing::syntheticMap(300));
  const ComfortFunction comfort = [](const Eigen::VectorXd& q) { return q.norm(); };
  FakeArm arm{
      &map, [&](std::size_t i) { return label(map, i) != 2 && !isRepresentative(map, i); }, {}};
  const auto ranks = rankClusters(map, Pose{}, arm.ik(), comfort, RankOptions{5});
  ASSERT_EQ(ranks.size(), 3u);
  EXPECT_EQ(ranks[2].cluster, 2);
  EXPECT_FALSE(ranks[2].reachable);
  EXPECT_EQ(ranks[2].tried, 6);  // the representative and five members
  EXPECT_EQ(ranks[2].target, representative(map, 2));
  EXPECT_EQ(ranks[2].message, "out of reach");
  // The five members run from the farthest to the nearest of the representative.
  std::vector<double> d;
  for (std::size_t i : arm.asked)
    if (label(map, i) == 2 && i != representative(map, 2))
      d.push_back(poseDistance(map.pose(i), map.pose(representative(map, 2)), map.rotationScale()));
  ASSERT_EQ(d.size(), 5u);
  EXPECT_TRUE(std::is_sorted(d.rbegin(), d.rend()));
  double nearest = 1e9;
  for (std::size_t i = 0; i < map.size(); ++i)
    if (label(map, i) == 2 && i != representative(map, 2))
      nearest = std::min(nearest, poseDistance(map.pose(i), map.pose(representative(map, 2)),
                                               map.rotationScale()));
  EXPECT_DOUBLE_EQ(d.back(), nearest);
}

TEST(RankClusters, OutliersAreTheLastResortWhenNoClusterIsReachable) {
  TaskMapData data = testing::syntheticMap(300);
  for (std::size_t i = 0; i < 300; i += 50) data.clustering->labels[i] = -1;  // six outliers
  const TaskMap map = TaskMap::fromData(std::move(data));
  const ComfortFunction comfort = [](const Eigen::VectorXd& q) { return q.norm(); };
  FakeArm arm{&map, [&](std::size_t i) { return i == 250; }, {}};
  auto ranks = rankClusters(map, Pose{}, arm.ik(), comfort, RankOptions{8});
  ASSERT_EQ(ranks.size(), 4u);
  EXPECT_EQ(ranks[0].cluster, -1);
  EXPECT_TRUE(ranks[0].reachable);
  EXPECT_EQ(ranks[0].target, 250u);
  EXPECT_EQ(ranks[0].representative, 250u);
  EXPECT_EQ(ranks[0].tried, 6);  // outliers 0, 50, ..., 250 in index order
  for (int k = 1; k < 4; ++k) EXPECT_FALSE(ranks[static_cast<std::size_t>(k)].reachable);
  // Without member tries, or with a reachable cluster, no outlier is tried.
  arm.asked.clear();
  ranks = rankClusters(map, Pose{}, arm.ik(), comfort);
  EXPECT_EQ(ranks.size(), 3u);
  for (std::size_t i : arm.asked) EXPECT_GE(label(map, i), 0);
  FakeArm easy{&map, [](std::size_t) { return true; }, {}};
  ranks = rankClusters(map, Pose{}, easy.ik(), comfort, RankOptions{8});
  EXPECT_EQ(ranks.size(), 3u);
  EXPECT_EQ(easy.asked.size(), 3u);
}

/// members_only (planGrasp's second round when every plan is unsafe): no representative is
/// given to the IK, every cluster's first reachable member is its target, and the outliers are
/// tried although clusters are reachable.
TEST(RankClusters, MembersOnlySkipsTheRepresentativesAndTriesTheOutliers) {
  TaskMapData data = testing::syntheticMap(300);
  for (std::size_t i = 0; i < 300; i += 50) data.clustering->labels[i] = -1;  // six outliers
  const TaskMap map = TaskMap::fromData(std::move(data));
  const ComfortFunction comfort = [](const Eigen::VectorXd& q) { return q.norm(); };
  FakeArm easy{&map, [](std::size_t) { return true; }, {}};
  RankOptions members{4};
  members.members_only = true;
  const auto ranks = rankClusters(map, Pose{}, easy.ik(), comfort, members);
  ASSERT_EQ(ranks.size(), 4u);  // three clusters and the outliers' rank
  std::set<int> clusters;
  for (const ClusterRank& r : ranks) {
    EXPECT_TRUE(r.reachable) << r.cluster;
    EXPECT_EQ(r.tried, 1) << r.cluster;
    EXPECT_EQ(label(map, r.target), r.cluster);
    if (r.cluster >= 0) {
      EXPECT_NE(r.target, representative(map, r.cluster));
    }
    clusters.insert(r.cluster);
  }
  EXPECT_EQ(clusters, (std::set<int>{-1, 0, 1, 2}));
  for (std::size_t i : easy.asked) EXPECT_FALSE(isRepresentative(map, i)) << i;
  // Without member tries nothing is tried: no target is reachable.
  members.member_tries = 0;
  for (const ClusterRank& r : rankClusters(map, Pose{}, easy.ik(), comfort, members))
    EXPECT_FALSE(r.reachable);
}

TEST(RankClusters, RefusesNegativeMemberTries) {
  const TaskMap map = TaskMap::fromData(testing::syntheticMap(30));
  FakeArm arm{&map, [](std::size_t) { return true; }, {}};
  EXPECT_EQ(testing::errorMessage([&] {
              rankClusters(
                  map, Pose{}, arm.ik(), [](const Eigen::VectorXd&) { return 0.0; },
                  RankOptions{-1});
            }),
            "rank options: member_tries must be >= 0 (0 = the representative only)");
}

}  // namespace
}  // namespace taskmap
