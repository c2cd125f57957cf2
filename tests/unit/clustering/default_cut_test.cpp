// The default cut on the two shapes real maps take: a continuum of grasps (no gap) is cut at
// the coverage floor instead of being left as one cluster, and a clear split between two
// families survives stragglers that would push the coverage floor above it.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "taskmap/clustering/clustering.hpp"

namespace taskmap {
namespace {

Pose at(double x, double y) {
  Pose p;
  p.position = Eigen::Vector3d(x, y, 0);
  p.orientation = Eigen::Quaterniond::Identity();
  return p;
}

int clustered(const ClusteringResult& r) {
  int n = 0;
  for (const auto& c : r.clusters) n += c.size;
  return n;
}

TEST(DefaultCut, ContinuumIsSplitAtTheCoverageFloor) {
  // A dendrogram without a gap: four pairs (merged at 1.0 to 1.3), two quadruples (1.8, 1.9),
  // the root (2.5); no merge of two clusters of min_size 2 is twice its children's core
  // distance (ratios 1.64, 1.46, 1.32), as in real maps whose grasps cover the object's
  // orientations continuously.
  LinkageMatrix l(7, 4);
  l << 0, 1, 1.0, 2, 2, 3, 1.1, 2, 4, 5, 1.2, 2, 6, 7, 1.3, 2, 8, 9, 1.8, 4, 10, 11, 1.9, 4, 12, 13,
      2.5, 8;
  EXPECT_EQ(defaultThreshold(l, 2), 2.5);  // the gap rule alone: one cluster
  EXPECT_EQ(coverageThreshold(l, 2, kDefaultOutlierBudget), 1.3);
  // Four clusters of two, the cut in the middle of the gap 1.3 .. 1.8.
  EXPECT_EQ(defaultCut(l, 2, kDefaultOutlierBudget), 0.5 * (1.3 + 1.8));
  std::vector<Pose> poses;
  for (int i = 0; i < 8; ++i) poses.push_back(at(0.1 * i, 0));
  ClusteringOptions o;
  o.min_size = 2;
  const ClusteringResult r = clusterFromLinkage(poses, std::vector<double>(8, 0.1), l, o);
  EXPECT_EQ(r.threshold, 0.5 * (1.3 + 1.8));
  ASSERT_EQ(r.clusters.size(), 4u);
  EXPECT_EQ(clustered(r), 8);
  // With a min_size no cut can reach twice (5 of 8), the one-cluster cut stays.
  EXPECT_EQ(defaultCut(l, 5, kDefaultOutlierBudget), 1.5 * 2.5);  // clear of the root merge
}

TEST(DefaultCut, StragglersDoNotUndoAClearSplit) {
  // Two families 1 m apart (50 grasps each, 1 cm across) and 15 stragglers 3 m from anything:
  // covering 90 % of the 115 grasps would need a cut above the families' merge.
  std::vector<Pose> poses;
  for (int i = 0; i < 50; ++i) poses.push_back(at(0.0002 * i, 0));
  for (int i = 0; i < 50; ++i) poses.push_back(at(1.0 + 0.0002 * i, 0));
  for (int i = 0; i < 15; ++i) poses.push_back(at(0.5, 3.0 * (i + 1)));
  const std::vector<double> eps(poses.size(), 0.1);
  ClusteringOptions o;
  o.min_size = 10;
  const ClusteringResult r = clusterGrasps(poses, eps, o);
  EXPECT_GT(coverageThreshold(r.linkage, 10, kDefaultOutlierBudget), 1.0);
  ASSERT_EQ(r.clusters.size(), 2u);
  EXPECT_EQ(r.clusters[0].size, 50);
  EXPECT_EQ(r.clusters[1].size, 50);
  for (int i = 100; i < 115; ++i) EXPECT_EQ(r.labels[static_cast<std::size_t>(i)], -1);
  // The cut lies between the highest merge inside the families and their merge (about 1 m).
  double below = 0;
  for (Eigen::Index k = 0; k < r.linkage.rows(); ++k)
    if (r.linkage(k, 2) < 0.99) below = std::max(below, r.linkage(k, 2));
  EXPECT_GE(r.threshold, below);
  EXPECT_LT(r.threshold, 0.99);
}

}  // namespace
}  // namespace taskmap
