// clusterGrasps / clusterFromLinkage: pose metric, cuts, outliers, summaries vs brute force.
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <vector>

#include <gtest/gtest.h>

#include "error_matchers.hpp"
#include "taskmap/clustering/clustering.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/random.hpp"

namespace taskmap {

using taskmap::testing::errorMessage;
namespace {

struct Grasps {
  std::vector<Pose> poses;
  std::vector<double> epsilon;
  std::vector<int> blob;  ///< generating blob, -1 for scattered outliers
};

/// num_blobs blobs of poses (1 cm, 0.05 rad) far apart, plus scattered outliers.
Grasps blobGrasps(const std::vector<int>& blob_sizes, int outliers, std::uint64_t seed) {
  Rng rng(seed, 0);
  Grasps g;
  for (std::size_t b = 0; b < blob_sizes.size(); ++b) {
    Pose centre;
    centre.position = Eigen::Vector3d(0.5 * static_cast<double>(b), 0.1, -0.2);
    centre.orientation = rng.rotation();
    for (int i = 0; i < blob_sizes[b]; ++i) {
      Pose p;
      p.position =
          centre.position + 0.01 * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
      const Eigen::Vector3d w = 0.05 * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
      p.orientation = Eigen::Quaterniond(centre.orientation.toRotationMatrix() * rotationExp(w));
      if (i % 2) p.orientation.coeffs() *= -1.0;  // q and -q are the same orientation
      g.poses.push_back(p);
      g.epsilon.push_back(rng.uniform(0.0, 0.2));
      g.blob.push_back(static_cast<int>(b));
    }
  }
  for (int i = 0; i < outliers; ++i) {
    Pose p;
    p.position = Eigen::Vector3d(rng.uniform(-3, 3), rng.uniform(3, 6), rng.uniform(-3, 3));
    p.orientation = rng.rotation();
    g.poses.push_back(p);
    g.epsilon.push_back(rng.uniform(0.0, 0.2));
    g.blob.push_back(-1);
  }
  // Interleave deterministically so that blobs are not contiguous in index order.
  Rng shuffle(seed, 1);
  for (std::size_t i = g.poses.size(); i > 1; --i) {
    const std::size_t j = shuffle.below(i);
    std::swap(g.poses[i - 1], g.poses[j]);
    std::swap(g.epsilon[i - 1], g.epsilon[j]);
    std::swap(g.blob[i - 1], g.blob[j]);
  }
  return g;
}

TEST(PoseMetric, OppositeQuaternionsAreOnePose) {
  Pose a;
  a.position = Eigen::Vector3d(0.1, 0.2, 0.3);
  a.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  Pose b = a;
  b.orientation.coeffs() *= -1.0;
  const ClusteringResult r = clusterGrasps({a, b}, {0.1, 0.2});
  ASSERT_EQ(r.linkage.rows(), 1);
  EXPECT_NEAR(r.linkage(0, 2), 0.0, 1e-15);
}

TEST(PoseMetric, HalfTurnTwinIsTwoRhoAway) {
  Pose a;
  a.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()));
  Pose b = a;
  b.orientation =
      a.orientation * Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()));
  for (double rho : {0.1, 0.25}) {
    ClusteringOptions options;
    options.rotation_scale = rho;
    const ClusteringResult r = clusterGrasps({a, b}, {0.1, 0.2}, options);
    EXPECT_NEAR(r.linkage(0, 2), 2.0 * rho, 1e-14);
    EXPECT_NEAR(r.linkage(0, 2), poseDistance(a, b, rho), 1e-14);
    EXPECT_EQ(r.rotation_scale, rho);
  }
}

TEST(ClusterGrasps, BlobsBecomeClustersAndStragglersOutliers) {
  const Grasps g = blobGrasps({300, 200, 120}, 8, 21);
  const ClusteringResult r = clusterGrasps(g.poses, g.epsilon);
  const int n = static_cast<int>(g.poses.size());
  EXPECT_EQ(r.min_size, std::max(3, static_cast<int>(std::ceil(0.03 * n))));
  ASSERT_EQ(r.clusters.size(), 3u);
  ASSERT_EQ(r.labels.size(), g.poses.size());
  // Largest first: blob b has label b; outliers are -1.
  for (int i = 0; i < n; ++i) EXPECT_EQ(r.labels[i], g.blob[i]) << "grasp " << i;
  // Summaries against brute force.
  for (int c = 0; c < 3; ++c) {
    const ClusterSummary& s = r.clusters[c];
    int size = 0, best = -1;
    double eps_sum = 0.0;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
    std::vector<Eigen::Quaterniond> qs;
    for (int i = 0; i < n; ++i) {
      if (r.labels[i] != c) continue;
      ++size;
      eps_sum += g.epsilon[i];
      if (best < 0 || g.epsilon[i] > g.epsilon[best]) best = i;
      sum += g.poses[i].position;
      lo = lo.cwiseMin(g.poses[i].position);
      hi = hi.cwiseMax(g.poses[i].position);
      qs.push_back(g.poses[i].orientation);
    }
    EXPECT_EQ(s.size, size);
    EXPECT_EQ(s.representative, best);
    EXPECT_DOUBLE_EQ(s.best_epsilon, g.epsilon[best]);
    EXPECT_NEAR(s.mean_epsilon, eps_sum / size, 1e-15);
    EXPECT_LT((s.mean_pose.position - sum / size).norm(), 1e-12);
    EXPECT_EQ(s.bounds_min, lo);
    EXPECT_EQ(s.bounds_max, hi);
    EXPECT_NEAR(rotationAngle(s.mean_pose.orientation, meanOrientation(qs)), 0.0, 1e-9);
    // The mean orientation is inside the blob (spread 0.05 rad), whatever the signs of q.
    EXPECT_LT(rotationAngle(s.mean_pose.orientation, g.poses[best].orientation), 0.3);
  }
  // Default threshold separates: it lies between the blobs' inner and outer distances.
  EXPECT_GT(r.threshold, 0.0);
  EXPECT_LT(r.threshold, 0.5);
}

TEST(ClusterGrasps, CutsByCountAndThresholdAndMinSize) {
  const Grasps g = blobGrasps({60, 40, 30}, 0, 22);
  ClusteringOptions by_count;
  by_count.num_clusters = 2;
  const ClusteringResult two = clusterGrasps(g.poses, g.epsilon, by_count);
  ASSERT_EQ(two.clusters.size(), 2u);
  EXPECT_EQ(two.clusters[0].size + two.clusters[1].size, 130);
  EXPECT_EQ(two.threshold, two.linkage(127, 2));
  ClusteringOptions tiny;
  tiny.threshold = 0.0;  // nothing merges: every grasp is a cluster of one
  tiny.min_size = 1;
  const ClusteringResult singles = clusterGrasps(g.poses, g.epsilon, tiny);
  EXPECT_EQ(singles.clusters.size(), 130u);
  for (int i = 0; i < 130; ++i) EXPECT_EQ(singles.labels[i], i);  // equal sizes: index order
  ClusteringOptions big;
  big.min_size = 45;
  big.outlier_budget = 1.0;  // gap rule alone: the two blobs below 45 become outliers
  const ClusteringResult only_big = clusterGrasps(g.poses, g.epsilon, big);
  ASSERT_EQ(only_big.clusters.size(), 1u);
  EXPECT_EQ(only_big.clusters[0].size, 60);
  for (int i = 0; i < 130; ++i) EXPECT_EQ(only_big.labels[i], g.blob[i] == 0 ? 0 : -1);
  // Default budget (10 %): 70 of 130 outliers is too many, the cut rises until the two small
  // blobs join a cluster of >= 45 (here all three blobs merge).
  big.outlier_budget = kDefaultOutlierBudget;
  const ClusteringResult budgeted = clusterGrasps(g.poses, g.epsilon, big);
  ASSERT_EQ(budgeted.clusters.size(), 1u);
  EXPECT_EQ(budgeted.clusters[0].size, 130);
}

TEST(ClusterGrasps, FromLinkageReproducesAndRecuts) {
  const Grasps g = blobGrasps({50, 50, 20}, 3, 23);
  ClusteringOptions options;
  options.method = Linkage::kAverage;
  const ClusteringResult a = clusterGrasps(g.poses, g.epsilon, options);
  const ClusteringResult b = clusterFromLinkage(g.poses, g.epsilon, a.linkage, options);
  EXPECT_EQ(a.labels, b.labels);
  EXPECT_EQ(a.linkage, b.linkage);
  EXPECT_EQ(a.threshold, b.threshold);
  const ClusteringResult again = clusterGrasps(g.poses, g.epsilon, options);
  EXPECT_EQ(a.labels, again.labels);  // deterministic
  options.num_clusters = 3;
  const ClusteringResult three = clusterFromLinkage(g.poses, g.epsilon, a.linkage, options);
  EXPECT_LE(three.clusters.size(), 3u);
  EXPECT_EQ(
      errorMessage([&] { clusterFromLinkage(g.poses, g.epsilon, LinkageMatrix(5, 4), options); }),
      "clusterFromLinkage: the dendrogram has 5 rows but 123 grasps need 122; recompute it "
      "with computeLinkage");
  options.num_clusters = 124;
  EXPECT_EQ(errorMessage([&] { clusterFromLinkage(g.poses, g.epsilon, a.linkage, options); }),
            "number of clusters (--clusters) 124 exceeds the number of grasps (123)");
}

TEST(ClusterGrasps, TinyInputs) {
  const ClusteringResult none = clusterGrasps({}, {});
  EXPECT_TRUE(none.labels.empty());
  EXPECT_TRUE(none.clusters.empty());
  EXPECT_EQ(none.linkage.rows(), 0);
  Pose p;
  p.position = Eigen::Vector3d(1, 2, 3);
  const ClusteringResult one = clusterGrasps({p}, {0.3});
  ASSERT_EQ(one.clusters.size(), 1u);
  EXPECT_EQ(one.labels, std::vector<int>{0});
  EXPECT_EQ(one.clusters[0].representative, 0);
  EXPECT_EQ(one.clusters[0].mean_pose.position, p.position);
}

TEST(ClusteringOptions, Validation) {
  ClusteringOptions o;
  EXPECT_NO_THROW(o.validate());
  o.threshold = 0.1;
  o.num_clusters = 3;
  EXPECT_EQ(errorMessage([&] { o.validate(); }),
            "clustering options threshold and num_clusters exclude each other: set one");
  o = ClusteringOptions{};
  o.rotation_scale = 0.0;
  EXPECT_EQ(errorMessage([&] { o.validate(); }),
            "clustering option rotation_scale must be a positive length per radian, got 0.000000");
  o = ClusteringOptions{};
  o.threshold = -1.0;
  EXPECT_EQ(errorMessage([&] { o.validate(); }),
            "clustering option threshold must be a finite distance >= 0 (metres), got -1.000000");
  o = ClusteringOptions{};
  o.num_clusters = 0;
  EXPECT_EQ(errorMessage([&] { o.validate(); }),
            "clustering option num_clusters must be >= 1, got 0");
  o = ClusteringOptions{};
  o.min_size_fraction = 1.5;
  EXPECT_EQ(errorMessage([&] { o.validate(); }),
            "clustering option min_size_fraction must be in [0, 1], got 1.500000");
  o = ClusteringOptions{};
  o.min_size = -2;
  EXPECT_EQ(errorMessage([&] { o.validate(); }),
            "clustering option min_size must be >= 0 (0: use min_size_fraction), got -2");
  o = ClusteringOptions{};
  EXPECT_EQ(resolveMinSize(o, 1000), 30);
  EXPECT_EQ(resolveMinSize(o, 1001), 31);
  EXPECT_EQ(resolveMinSize(o, 10), 3);
  o.min_size = 7;
  EXPECT_EQ(resolveMinSize(o, 1000), 7);
}

/// Points in clusters of >= min_size after cutting at t (brute force).
int coveredAt(const LinkageMatrix& z, double t, int min_size) {
  const std::vector<int> labels = cutAtDistance(z, t);
  std::map<int, int> size;
  for (int l : labels) ++size[l];
  int covered = 0;
  for (int l : labels) covered += size[l] >= min_size;
  return covered;
}

TEST(DefaultCut, CoverageThresholdMatchesBruteForce) {
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    Rng rng(seed, 7);
    const int n = 60 + 20 * static_cast<int>(seed);
    PointMatrix pts(n, 3);
    for (int i = 0; i < n; ++i) {
      // A few blobs of varied spread plus uniform scatter.
      const double s = i % 4 == 3 ? 1.0 : 0.05 * (1 + i % 3);
      pts.row(i) << (i % 3) + s * rng.normal(), s * rng.normal(), s * rng.normal();
    }
    for (Linkage method : {Linkage::kSingle, Linkage::kAverage, Linkage::kComplete}) {
      const LinkageMatrix z = computeLinkage(pts, method);
      for (int m : {1, 2, 5, 12, n}) {
        for (double budget : {0.0, 0.1, 0.37, 1.0}) {
          const int needed = static_cast<int>(std::ceil((1.0 - budget) * n - 1e-9));
          // Oracle: the lowest candidate cut (0 or a merge distance) reaching the coverage.
          std::vector<double> candidates = {0.0};
          for (Eigen::Index k = 0; k < z.rows(); ++k) candidates.push_back(z(k, 2));
          double expected = -1.0;
          for (double t : candidates) {
            if (coveredAt(z, t, m) >= needed) {
              expected = t;
              break;
            }
          }
          const double t = coverageThreshold(z, m, budget);
          EXPECT_EQ(t, expected) << toString(method) << " m " << m << " budget " << budget;
          EXPECT_GE(coveredAt(z, t, m), needed);
          // The default cut is max(gap rule, coverage) except where it keeps a clear split
          // or cuts a continuum at the coverage floor: both lower, never below the lower of
          // the two (default_cut_test.cpp checks those cases).
          const double cut = defaultCut(z, m, budget), gap = defaultThreshold(z, m);
          // Then moved to the middle of its merge gap (midGapCut, non-decreasing).
          EXPECT_LE(cut, midGapCut(z, std::max(gap, t)));
          EXPECT_GE(cut, midGapCut(z, std::min(gap, t)));
        }
      }
    }
  }
  EXPECT_EQ(coverageThreshold(LinkageMatrix(0, 4), 3, 0.1), 0.0);
  EXPECT_EQ(errorMessage([] { coverageThreshold(LinkageMatrix(0, 4), 3, 1.5); }),
            "coverageThreshold: outlier_budget must be a share in [0, 1], got 1.500000");
}

// The default cut on a map where the gap rule alone drops more than the outlier budget: 40
// scattered stragglers next to two blobs of 60. Gap rule: two clusters, 40 outliers (25 %).
// The coverage floor (budget 10 %) lies above the blobs' merge: reaching it would put both
// blobs in one cluster. Each blob is a family larger than the budget (60 > 16 grasps), so the
// default cut keeps them apart (at the highest merge below theirs) and the stragglers stay
// outliers; with a budget that the stragglers fit in (30 %), the coverage floor applies.
TEST(DefaultCut, OutlierBudgetBoundsTheGapRule) {
  const Grasps g = blobGrasps({60, 60}, 40, 24);
  const int n = static_cast<int>(g.poses.size());
  ClusteringOptions gap_only;
  gap_only.outlier_budget = 1.0;
  const ClusteringResult gap = clusterGrasps(g.poses, g.epsilon, gap_only);
  EXPECT_EQ(gap.method, Linkage::kAverage);
  EXPECT_EQ(gap.threshold, midGapCut(gap.linkage, defaultThreshold(gap.linkage, gap.min_size)));
  ASSERT_EQ(gap.clusters.size(), 2u);
  for (int i = 0; i < n; ++i) EXPECT_EQ(gap.labels[i], g.blob[i]) << "grasp " << i;

  const ClusteringResult r = clusterGrasps(g.poses, g.epsilon);
  EXPECT_EQ(r.linkage, gap.linkage);
  EXPECT_EQ(r.min_size, gap.min_size);
  const double coverage = coverageThreshold(r.linkage, r.min_size, kDefaultOutlierBudget);
  EXPECT_EQ(r.threshold, defaultCut(r.linkage, r.min_size, kDefaultOutlierBudget));
  EXPECT_LT(r.threshold, coverage);
  EXPECT_GE(r.threshold, gap.threshold);
  ASSERT_EQ(r.clusters.size(), 2u);
  for (int i = 0; i < n; ++i) EXPECT_EQ(r.labels[i], g.blob[i]) << "grasp " << i;
  // At the coverage floor the blobs would be one cluster.
  const std::vector<int> merged = cutAtDistance(r.linkage, coverage);
  int blob0 = -1, blob1 = -1;
  for (int i = 0; i < n; ++i) {
    if (g.blob[i] == 0) blob0 = i;
    if (g.blob[i] == 1) blob1 = i;
  }
  EXPECT_EQ(merged[static_cast<std::size_t>(blob0)], merged[static_cast<std::size_t>(blob1)]);

  ClusteringOptions roomy;
  roomy.outlier_budget = 0.3;
  const ClusteringResult loose = clusterGrasps(g.poses, g.epsilon, roomy);
  EXPECT_EQ(
      loose.threshold,
      midGapCut(loose.linkage, std::max(defaultThreshold(loose.linkage, loose.min_size),
                                        coverageThreshold(loose.linkage, loose.min_size, 0.3))));
  EXPECT_EQ(loose.clusters.size(), 2u);
}

// The cut moves to the middle of the gap between the merge heights around it: the same
// partition, never on a merge height (issue 30: scipy's own linkage, 5e-17 away, split a
// cluster there).
TEST(DefaultCut, MidGapCutKeepsThePartitionOffMergeHeights) {
  PointMatrix points(5, 1);
  points << 0.0, 0.1, 0.3, 0.5, 1.0;  // single linkage merges at 0.1, 0.2, 0.2, 0.5
  const LinkageMatrix z = computeLinkage(points, Linkage::kSingle);
  ASSERT_NEAR(z(0, 2), 0.1, 1e-15);
  ASSERT_NEAR(z(3, 2), 0.5, 1e-15);
  const double h1 = z(0, 2), h2 = z(2, 2), h3 = z(3, 2);
  EXPECT_DOUBLE_EQ(midGapCut(z, h2), 0.5 * (h2 + h3));    // on a merge height: up to the middle
  EXPECT_DOUBLE_EQ(midGapCut(z, 0.15), 0.5 * (h1 + h2));  // inside a gap: its middle
  EXPECT_DOUBLE_EQ(midGapCut(z, 0.05), 0.5 * h1);         // below every merge
  EXPECT_DOUBLE_EQ(midGapCut(z, h3), 1.5 * h3);           // at the top: one cluster, clear of it
  for (double t : {0.0, 0.05, h1, 0.15, h2, 0.3, h3, 0.9}) {
    const double m = midGapCut(z, t);
    EXPECT_EQ(cutAtDistance(z, m), cutAtDistance(z, t)) << t;
    for (Eigen::Index k = 0; k < z.rows(); ++k) EXPECT_NE(m, z(k, 2)) << t;
    // A dendrogram whose heights differ by rounding cuts the same way at m.
    LinkageMatrix nudged = z;
    for (Eigen::Index k = 0; k < z.rows(); ++k) nudged(k, 2) *= 1.0 - 1e-15;
    EXPECT_EQ(cutAtDistance(nudged, m), cutAtDistance(z, t)) << t;
  }
  EXPECT_EQ(errorMessage([&] { midGapCut(z, -1.0); }),
            "midGapCut: the cut distance must be finite and >= 0 (metres), got -1.000000");
  // The default cut of clusterGrasps is never a merge height.
  const Grasps g = blobGrasps({60, 60, 30}, 20, 31);
  const ClusteringResult r = clusterGrasps(g.poses, g.epsilon);
  for (Eigen::Index k = 0; k < r.linkage.rows(); ++k) EXPECT_NE(r.threshold, r.linkage(k, 2));
}

// No cluster under max(3 grasps, 3 % of the map) by default (issue 30: clusters of two).
TEST(ClusteringOptions, DefaultMinSizeIsThreeGraspsOrThreePercent) {
  const ClusteringOptions o;
  EXPECT_EQ(resolveMinSize(o, 1000), 30);
  EXPECT_EQ(resolveMinSize(o, 150), 5);
  EXPECT_EQ(resolveMinSize(o, 100), 3);
  EXPECT_EQ(resolveMinSize(o, 50), 3);
  EXPECT_EQ(resolveMinSize(o, 2), 2);  // a map of two grasps is one cluster, not outliers
  EXPECT_EQ(resolveMinSize(o, 1), 1);
  ClusteringOptions fixed;
  fixed.min_size = 2;
  EXPECT_EQ(resolveMinSize(fixed, 1000), 2);
  // 50 grasps in pairs: no cluster of two survives the default.
  const Grasps g = blobGrasps(std::vector<int>(25, 2), 0, 5);
  const ClusteringResult r = clusterGrasps(g.poses, g.epsilon);
  for (const ClusterSummary& c : r.clusters) EXPECT_GE(c.size, 3);
}

TEST(ClusteringOptions, DefaultMethodIsAverageUpToTheLimit) {
  ClusteringOptions o;
  EXPECT_EQ(o.method, Linkage::kAverage);
  EXPECT_EQ(o.outlier_budget, 0.1);
  EXPECT_EQ(resolveMethod(o, kMaxPairwiseLinkagePoints), Linkage::kAverage);
  EXPECT_EQ(resolveMethod(o, kMaxPairwiseLinkagePoints + 1), Linkage::kSingle);
  o.fallback_to_single = false;
  EXPECT_EQ(resolveMethod(o, kMaxPairwiseLinkagePoints + 1), Linkage::kAverage);
  o.method = Linkage::kComplete;
  o.fallback_to_single = true;
  EXPECT_EQ(resolveMethod(o, kMaxPairwiseLinkagePoints + 1), Linkage::kSingle);
  o.outlier_budget = -0.5;
  EXPECT_EQ(errorMessage([&] { o.validate(); }),
            "clustering option outlier_budget must be a share in [0, 1], got -0.500000");
}

TEST(ClusterGrasps, RejectsBadGrasps) {
  Pose p;
  EXPECT_EQ(errorMessage([&] {
              clusterGrasps({p, p}, {0.1});
            }),
            "clusterGrasps: 2 poses but 1 epsilon values; give one per grasp");
  EXPECT_EQ(errorMessage([&] {
              clusterGrasps({p, p}, {0.1, std::nan("")});
            }),
            "clusterGrasps: epsilon of grasp 1 is not finite");
  Pose bad;
  bad.position.x() = std::numeric_limits<double>::infinity();
  EXPECT_EQ(errorMessage([&] {
              clusterGrasps({p, bad}, {0.1, 0.1});
            }),
            "clusterGrasps: pose of grasp 1 is not finite or has a zero quaternion");
}

}  // namespace
}  // namespace taskmap
