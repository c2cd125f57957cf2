// Dendrograms: single linkage vs an O(n^2) Prim oracle, average/complete vs naive O(n^3)
// agglomeration, scipy's format, cuts and the default threshold.
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <vector>

#include <gtest/gtest.h>

#include "error_matchers.hpp"
#include "taskmap/clustering/clustering.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/random.hpp"

namespace taskmap {
namespace {

double dist2(const PointMatrix& p, int i, int j) {
  double s = 0.0;
  for (Eigen::Index k = 0; k < p.cols(); ++k) {
    const double e = p(i, k) - p(j, k);
    s += e * e;
  }
  return s;
}

/// Brute-force O(n^2) Prim: MST edges (a, b, length).
struct Edge {
  int a, b;
  double d;
};
std::vector<Edge> primMst(const PointMatrix& p) {
  const int n = static_cast<int>(p.rows());
  std::vector<double> best(n, std::numeric_limits<double>::infinity());
  std::vector<int> from(n, -1);
  std::vector<char> in(n, 0);
  std::vector<Edge> edges;
  int cur = 0;
  in[0] = 1;
  for (int step = 1; step < n; ++step) {
    for (int j = 0; j < n; ++j) {
      if (in[j]) continue;
      const double d = dist2(p, cur, j);
      if (d < best[j]) {
        best[j] = d;
        from[j] = cur;
      }
    }
    int next = -1;
    for (int j = 0; j < n; ++j) {
      if (!in[j] && (next < 0 || best[j] < best[next])) next = j;
    }
    in[next] = 1;
    edges.push_back(Edge{from[next], next, std::sqrt(best[next])});
    cur = next;
  }
  return edges;
}

/// Labels of the connected components after joining edges of length <= t.
std::vector<int> components(int n, const std::vector<Edge>& edges, double t) {
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  std::function<int(int)> find = [&](int x) {
    return parent[x] == x ? x : parent[x] = find(parent[x]);
  };
  for (const Edge& e : edges) {
    if (e.d <= t) parent[find(e.a)] = find(e.b);
  }
  std::map<int, int> ids;
  std::vector<int> labels(n);
  for (int i = 0; i < n; ++i) {
    auto it = ids.emplace(find(i), static_cast<int>(ids.size())).first;
    labels[i] = it->second;
  }
  return labels;
}

/// Points in Gaussian blobs (some exact duplicates and grid ties when requested).
PointMatrix blobs(int n, int dim, int num_blobs, double sigma, std::uint64_t seed) {
  Rng rng(seed, 0);
  PointMatrix centres(num_blobs, dim);
  for (int b = 0; b < num_blobs; ++b) {
    for (int k = 0; k < dim; ++k) centres(b, k) = rng.uniform(0.0, 1.0);
  }
  PointMatrix p(n, dim);
  for (int i = 0; i < n; ++i) {
    const int b = static_cast<int>(rng.below(num_blobs));
    for (int k = 0; k < dim; ++k) p(i, k) = centres(b, k) + sigma * rng.normal();
  }
  return p;
}

/// Checks scipy's format: ids exist, smaller first, each used once, sizes, sorted.
void expectScipyFormat(const LinkageMatrix& z) {
  const int n = static_cast<int>(z.rows()) + 1;
  std::vector<int> used(2 * n - 1, 0);
  std::vector<double> size(2 * n - 1, 1.0);
  for (int k = 0; k < n - 1; ++k) {
    const int a = static_cast<int>(z(k, 0));
    const int b = static_cast<int>(z(k, 1));
    ASSERT_LT(a, b) << "row " << k;
    ASSERT_LT(b, n + k) << "row " << k;
    ASSERT_EQ(used[a]++, 0);
    ASSERT_EQ(used[b]++, 0);
    size[n + k] = size[a] + size[b];
    ASSERT_EQ(z(k, 3), size[n + k]);
    if (k > 0) {
      ASSERT_LE(z(k - 1, 2), z(k, 2));
    }
  }
}

void expectSamePartition(const std::vector<int>& a, const std::vector<int>& b) {
  ASSERT_EQ(a.size(), b.size());
  std::map<int, int> ab, ba;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(ab.emplace(a[i], b[i]).first->second, b[i]) << "point " << i;
    ASSERT_EQ(ba.emplace(b[i], a[i]).first->second, a[i]) << "point " << i;
  }
}

void checkSingleAgainstPrim(const PointMatrix& p) {
  const int n = static_cast<int>(p.rows());
  const LinkageMatrix z = computeLinkage(p, Linkage::kSingle);
  ASSERT_EQ(z.rows(), n - 1);
  expectScipyFormat(z);
  std::vector<Edge> mst = primMst(p);
  std::vector<double> expected;
  for (const Edge& e : mst) expected.push_back(e.d);
  std::sort(expected.begin(), expected.end());
  for (int k = 0; k < n - 1; ++k) ASSERT_EQ(z(k, 2), expected[k]) << "merge " << k;
  // Same flat clusters at every distinct merge distance (and between them).
  for (int k = 0; k < n - 1; k += std::max(1, n / 40)) {
    const double t = expected[k];
    expectSamePartition(cutAtDistance(z, t), components(n, mst, t));
    expectSamePartition(cutAtDistance(z, 0.999 * t), components(n, mst, 0.999 * t));
  }
}

TEST(Linkage, NamesRoundTrip) {
  for (Linkage m : {Linkage::kSingle, Linkage::kAverage, Linkage::kComplete}) {
    EXPECT_EQ(linkageFromString(toString(m)), m);
  }
  EXPECT_EQ(testing::errorMessage([&] { linkageFromString("ward"); }),
            "unknown linkage method 'ward': use single, average or complete");
}

TEST(SingleLinkage, MatchesPrimOnBlobs) {
  checkSingleAgainstPrim(blobs(700, 12, 9, 0.02, 1));
  checkSingleAgainstPrim(blobs(300, 3, 4, 0.05, 2));
  checkSingleAgainstPrim(blobs(257, 1, 3, 0.1, 3));
  // Large enough for every phase of the EMST (neighbour lists, global tree rounds,
  // per-component rounds).
  checkSingleAgainstPrim(blobs(3000, 12, 60, 0.02, 7));
}

TEST(SingleLinkage, MatchesPrimWithDuplicatesAndTies) {
  // Integer grid points: many equal distances, plus exact duplicates.
  Rng rng(4, 0);
  PointMatrix p(400, 4);
  for (int i = 0; i < 400; ++i) {
    for (int k = 0; k < 4; ++k) p(i, k) = static_cast<double>(rng.below(5));
  }
  checkSingleAgainstPrim(p);
  PointMatrix same = PointMatrix::Constant(50, 12, 0.25);
  const LinkageMatrix z = computeLinkage(same, Linkage::kSingle);
  expectScipyFormat(z);
  EXPECT_EQ(z.col(2).maxCoeff(), 0.0);
}

TEST(SingleLinkage, TwoPoints) {
  PointMatrix p(2, 2);
  p << 0, 0, 3, 4;
  const LinkageMatrix z = computeLinkage(p, Linkage::kSingle);
  ASSERT_EQ(z.rows(), 1);
  EXPECT_EQ(z(0, 0), 0);
  EXPECT_EQ(z(0, 1), 1);
  EXPECT_EQ(z(0, 2), 5.0);
  EXPECT_EQ(z(0, 3), 2);
}

/// Naive O(n^3) agglomeration: recompute every cluster distance from its points each step.
std::vector<double> naiveMerges(const PointMatrix& p, Linkage method,
                                std::vector<std::vector<int>>* partitions) {
  const int n = static_cast<int>(p.rows());
  std::vector<std::vector<int>> clusters(n);
  for (int i = 0; i < n; ++i) clusters[i] = {i};
  std::vector<double> merges;
  while (clusters.size() > 1) {
    double best = std::numeric_limits<double>::infinity();
    std::size_t ba = 0, bb = 0;
    for (std::size_t a = 0; a < clusters.size(); ++a) {
      for (std::size_t b = a + 1; b < clusters.size(); ++b) {
        double acc = 0.0;
        for (int i : clusters[a]) {
          for (int j : clusters[b]) {
            const double d = std::sqrt(dist2(p, i, j));
            acc = method == Linkage::kComplete ? std::max(acc, d) : acc + d;
          }
        }
        if (method == Linkage::kAverage) {
          acc /= static_cast<double>(clusters[a].size() * clusters[b].size());
        }
        if (acc < best) {
          best = acc;
          ba = a;
          bb = b;
        }
      }
    }
    merges.push_back(best);
    clusters[ba].insert(clusters[ba].end(), clusters[bb].begin(), clusters[bb].end());
    clusters.erase(clusters.begin() + static_cast<std::ptrdiff_t>(bb));
    std::vector<int> labels(n);
    for (std::size_t c = 0; c < clusters.size(); ++c) {
      for (int i : clusters[c]) labels[i] = static_cast<int>(c);
    }
    partitions->push_back(labels);
  }
  return merges;
}

TEST(ChainLinkage, AverageAndCompleteMatchNaiveAgglomeration) {
  for (Linkage method : {Linkage::kAverage, Linkage::kComplete}) {
    for (std::uint64_t seed : {5u, 6u}) {
      const PointMatrix p = blobs(70, 5, 4, 0.05, seed);
      std::vector<std::vector<int>> partitions;
      const std::vector<double> expected = naiveMerges(p, method, &partitions);
      const LinkageMatrix z = computeLinkage(p, method);
      expectScipyFormat(z);
      ASSERT_EQ(z.rows(), static_cast<Eigen::Index>(expected.size()));
      for (Eigen::Index k = 0; k < z.rows(); ++k) {
        EXPECT_NEAR(z(k, 2), expected[k], 1e-12 * expected[k]) << toString(method) << " " << k;
        expectSamePartition(cutToCount(z, static_cast<int>(p.rows() - k - 1)), partitions[k]);
      }
    }
  }
}

TEST(Linkage, RejectsBadInput) {
  auto message = [](const PointMatrix& p, Linkage m) {
    return testing::errorMessage([&] { computeLinkage(p, m); });
  };
  EXPECT_EQ(message(PointMatrix::Zero(1, 3), Linkage::kSingle),
            "computeLinkage needs at least 2 points, got 1");
  PointMatrix p = PointMatrix::Zero(4, 3);
  p(2, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(message(p, Linkage::kSingle), "computeLinkage: point 2 has a non-finite coordinate");
  EXPECT_EQ(message(PointMatrix::Zero(20001, 1), Linkage::kAverage),
            "average linkage supports at most 20000 points (O(n^2) memory), got 20001: use "
            "single linkage");
}

TEST(Cuts, LabelsByFirstAppearance) {
  // Points 0..4; merges: (1,3)@1, (0,4)@2, (2,5)@3, (6,7)@4.
  LinkageMatrix z(4, 4);
  z << 1, 3, 1, 2, 0, 4, 2, 2, 2, 5, 3, 3, 6, 7, 4, 5;
  EXPECT_EQ(cutAtDistance(z, 0.5), (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_EQ(cutAtDistance(z, 1.0), (std::vector<int>{0, 1, 2, 1, 3}));
  EXPECT_EQ(cutAtDistance(z, 2.5), (std::vector<int>{0, 1, 2, 1, 0}));
  EXPECT_EQ(cutAtDistance(z, 3.0), (std::vector<int>{0, 1, 1, 1, 0}));
  EXPECT_EQ(cutAtDistance(z, 9.0), (std::vector<int>{0, 0, 0, 0, 0}));
  EXPECT_EQ(cutToCount(z, 5), cutAtDistance(z, 0.5));
  EXPECT_EQ(cutToCount(z, 2), cutAtDistance(z, 3.0));
  EXPECT_EQ(cutToCount(z, 1), cutAtDistance(z, 9.0));
  EXPECT_EQ(testing::errorMessage([&] { cutToCount(z, 6); }),
            "cutToCount: cluster count 6 must be between 1 and 5 (the number of points)");
  LinkageMatrix bad = z;
  bad(2, 1) = 3;  // point 3 merged twice
  EXPECT_EQ(testing::errorMessage([&] { cutAtDistance(bad, 1.0); }),
            "cutAtDistance: linkage row 2 merges cluster 3 a second time");
  bad = z;
  bad(1, 2) = 0.5;
  EXPECT_EQ(testing::errorMessage([&] { cutAtDistance(bad, 1.0); }),
            "cutAtDistance: linkage row 1 has a smaller distance than the row before");
  bad = z;
  bad(3, 3) = 4;
  EXPECT_EQ(testing::errorMessage([&] { cutAtDistance(bad, 1.0); }),
            "cutAtDistance: linkage row 3 has size 4.000000, expected 5.000000");
}

int countClusters(const std::vector<int>& labels, int min_size) {
  std::map<int, int> sizes;
  for (int l : labels) ++sizes[l];
  int k = 0;
  for (const auto& s : sizes) k += s.second >= min_size;
  return k;
}

TEST(DefaultThreshold, SeparatedBlobsWithOutliers) {
  // Three tight, well separated blobs of 300 points and 10 scattered outliers.
  Rng rng(8, 0);
  PointMatrix p(910, 6);
  const double centres[3] = {0.0, 1.0, 2.0};
  std::vector<int> truth(910);
  for (int i = 0; i < 910; ++i) {
    const bool outlier = i >= 900;
    truth[i] = outlier ? 3 + i : i % 3;
    for (int k = 0; k < 6; ++k) {
      p(i, k) = outlier ? rng.uniform(-1.0, 3.0) : centres[i % 3] + 0.02 * rng.normal();
    }
  }
  const LinkageMatrix z = computeLinkage(p, Linkage::kSingle);
  const double t = defaultThreshold(z);
  const std::vector<int> labels = cutAtDistance(z, t);
  EXPECT_EQ(countClusters(labels, 19), 3);
  // Every blob point is in its blob's cluster.
  std::vector<int> blob_label(3, -1);
  for (int i = 0; i < 900; ++i) {
    if (blob_label[i % 3] < 0) blob_label[i % 3] = labels[i];
    EXPECT_EQ(labels[i], blob_label[i % 3]) << i;
  }
  EXPECT_NE(blob_label[0], blob_label[1]);
  EXPECT_NE(blob_label[1], blob_label[2]);
  EXPECT_NE(blob_label[0], blob_label[2]);
}

TEST(DefaultThreshold, OneBlobIsOneCluster) {
  for (std::uint64_t seed : {9u, 10u, 11u}) {
    const PointMatrix p = blobs(1000, 6, 1, 0.05, seed);
    const LinkageMatrix z = computeLinkage(p, Linkage::kSingle);
    const double t = defaultThreshold(z);
    EXPECT_EQ(countClusters(cutAtDistance(z, t), 20), 1) << "seed " << seed;
  }
  PointMatrix u(800, 3);
  Rng rng(12, 0);
  for (int i = 0; i < 800; ++i) {
    for (int k = 0; k < 3; ++k) u(i, k) = rng.uniform();
  }
  const LinkageMatrix z = computeLinkage(u, Linkage::kSingle);
  EXPECT_EQ(countClusters(cutAtDistance(z, defaultThreshold(z)), 16), 1);
  EXPECT_EQ(defaultThreshold(LinkageMatrix(0, 4)), 0.0);
}

}  // namespace
}  // namespace taskmap
