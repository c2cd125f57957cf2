// TaskMap queries against brute-force oracles: nearest/knn/radius, the quality mixture and its
// truncation bound, concurrency, batch, and error handling.
#include "taskmap/integration/task_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <thread>

#include <gtest/gtest.h>

#include "error_matchers.hpp"
#include "synthetic_map.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/integration/criteria.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap {

using taskmap::testing::errorMessage;
namespace {

using testing::randomPose;
using testing::syntheticMap;

constexpr std::size_t kMapSize = 2000;
constexpr int kQueries = 10000;

const TaskMap& sharedMap() {
  static const TaskMap map = TaskMap::fromData(syntheticMap(kMapSize));
  return map;
}

// Queries: near samples (a few sigma away) or uniform; every other one with -q.
std::vector<Pose> queries(const TaskMap& map, int n, std::uint64_t seed) {
  Rng rng(seed, 1);
  std::vector<Pose> out;
  const double sp = *map.options().position_sigma;
  const double sr = *map.options().rotation_sigma;
  for (int i = 0; i < n; ++i) {
    Pose x;
    if (i % 5 == 4) {
      x = randomPose(rng);
    } else {
      x = map.pose(rng.below(map.size()));
      const double scale = rng.uniform(0.0, 3.0);
      x.position += scale * sp * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
      const Eigen::Vector3d w(rng.normal(), rng.normal(), rng.normal());
      x.orientation =
          Eigen::Quaterniond(rotationExp(scale * sr * w) * x.orientation.toRotationMatrix());
    }
    if (i % 2 == 1) x.orientation.coeffs() *= -1.0;
    out.push_back(x);
  }
  return out;
}

struct Hit {
  std::size_t index;
  double distance;
};

// Brute-force oracle: the `keep` nearest samples (of the cluster), plus every sample within r.
std::vector<Hit> bruteForce(const TaskMap& map, const Pose& x, std::optional<int> cluster,
                            std::size_t keep = 1, double r = -1.0) {
  static std::vector<Pose> poses;  // cache of map.pose(i) for the shared map sizes
  static const TaskMap* cached = nullptr;
  if (cached != &map || poses.size() != map.size()) {
    poses.clear();
    for (std::size_t i = 0; i < map.size(); ++i) poses.push_back(map.pose(i));
    cached = &map;
  }
  std::vector<Hit> all;
  all.reserve(map.size());
  for (std::size_t i = 0; i < map.size(); ++i) {
    if (cluster && map.data().clustering->labels[i] != *cluster) continue;
    all.push_back(Hit{i, poseDistance(x, poses[i], map.rotationScale())});
  }
  auto less = [](const Hit& a, const Hit& b) {
    return a.distance < b.distance || (a.distance == b.distance && a.index < b.index);
  };
  auto mid = std::partition(all.begin(), all.end(), [&](const Hit& h) { return h.distance <= r; });
  const std::size_t inside = static_cast<std::size_t>(mid - all.begin());
  if (inside < keep) {
    std::partial_sort(mid,
                      mid + static_cast<std::ptrdiff_t>(
                                std::min(keep - inside, static_cast<std::size_t>(all.end() - mid))),
                      all.end(), less);
  }
  std::sort(all.begin(), mid, less);
  all.resize(std::min(all.size(), std::max(keep, inside)));
  return all;
}

TEST(TaskMap, NearestKnnRadiusEqualBruteForce) {
  const TaskMap& map = sharedMap();
  const auto xs = queries(map, kQueries, 11);
  const double r = 2.0 * *map.options().position_sigma;
  std::size_t radius_hits = 0;
  for (int i = 0; i < kQueries; ++i) {
    const Pose& x = xs[static_cast<std::size_t>(i)];
    const std::optional<int> cluster =
        i % 3 == 0 ? std::optional<int>(i % 9 / 3) : std::optional<int>();
    const auto truth = bruteForce(map, x, cluster, 5, r);
    const Neighbor n = map.nearest(x, cluster);
    ASSERT_EQ(n.index, truth[0].index) << "query " << i;
    ASSERT_NEAR(n.distance, truth[0].distance, 1e-12);
    // evaluate's nearest comes from the cut-off ball's samples, or from the ball tree's branch
    // and bound when the ball is empty (as for most uniform queries).
    const Evaluation ev = map.evaluate(x, cluster);
    ASSERT_EQ(ev.proximity.nearest.index, truth[0].index) << "query " << i;
    ASSERT_NEAR(ev.proximity.nearest.distance, truth[0].distance, 1e-12);
    const auto k = map.knn(x, 5, cluster);
    ASSERT_EQ(k.size(), 5u);
    for (std::size_t j = 0; j < 5; ++j) {
      ASSERT_EQ(k[j].index, truth[j].index) << "query " << i << " rank " << j;
      ASSERT_NEAR(k[j].distance, truth[j].distance, 1e-12);
    }
    const auto rad = map.radius(x, r, cluster);
    std::size_t expected = 0;
    while (expected < truth.size() && truth[expected].distance <= r) ++expected;
    ASSERT_EQ(rad.size(), expected) << "query " << i;
    for (std::size_t j = 0; j < rad.size(); ++j) ASSERT_EQ(rad[j].index, truth[j].index);
    radius_hits += rad.size();
  }
  EXPECT_GT(radius_hits, static_cast<std::size_t>(kQueries));  // the radius test is not vacuous
}

TEST(TaskMap, SignOfQuaternionDoesNotMatter) {
  const TaskMap& map = sharedMap();
  Rng rng(3, 0);
  for (int i = 0; i < 200; ++i) {
    Pose x = randomPose(rng);
    Pose y = x;
    y.orientation.coeffs() *= -1.0;
    const Evaluation a = map.evaluate(x), b = map.evaluate(y);
    EXPECT_EQ(a.proximity.nearest.index, b.proximity.nearest.index);
    EXPECT_NEAR(a.proximity.value, b.proximity.value, 1e-12);
    EXPECT_LT((a.gradient() - b.gradient()).norm(), 1e-9 * (1.0 + a.gradient().norm()));
  }
}

TEST(TaskMap, RandomizedForestFindsMostNearestNeighbours) {
  TaskMapOptions o;
  o.index = IndexKind::kRandomizedForest;
  o.trees = 4;
  o.checks = 512;
  const TaskMap map = TaskMap::fromData(syntheticMap(kMapSize), o);
  const auto xs = queries(map, 1000, 5);
  int exact = 0, inside = 0;
  for (const Pose& x : xs) {
    const Neighbor n = map.nearest(x);
    const auto truth = bruteForce(map, x, std::nullopt);
    EXPECT_GE(n.distance, truth[0].distance - 1e-12);  // never better than the truth
    exact += n.index == truth[0].index;
    // evaluate: the radius search stays exact, and so is its nearest when the cut-off ball
    // holds a sample; otherwise it is the forest's answer, as nearest() gives.
    const Evaluation e = map.evaluate(x);
    const QualityCriterion q = sharedMap().quality(x);
    ASSERT_EQ(e.quality.terms, q.terms);
    ASSERT_NEAR(e.quality.value, q.value, 1e-12 * std::abs(q.value));
    if (truth[0].distance <= map.cutoffRadius()) {
      ++inside;
      ASSERT_EQ(e.proximity.nearest.index, truth[0].index);
    } else {
      ASSERT_EQ(e.proximity.nearest.index, n.index);
    }
  }
  EXPECT_GT(exact, 900);
  EXPECT_GT(inside, 500);
}

TEST(TaskMap, ExactQualityEqualsSumOfDensities) {
  const TaskMap& map = sharedMap();
  const double sp = *map.options().position_sigma, sr = *map.options().rotation_sigma;
  const auto xs = queries(map, 50, 17);
  double wsum = 0;
  for (double e : map.data().grasps.epsilon) wsum += e;
  for (const Pose& x : xs) {
    double v = 0;
    Twist g = Twist::Zero();
    for (std::size_t i = 0; i < map.size(); ++i) {
      Twist gi;
      const double f = gaussianDensity(x, map.pose(i), sp, sr, &gi);
      v -= map.data().grasps.epsilon[i] * f / wsum;
      g -= map.data().grasps.epsilon[i] * gi / wsum;
    }
    const QualityCriterion q = map.quality(x, std::nullopt, QualityMode::kExact);
    EXPECT_NEAR(q.value, v, 1e-10 * std::abs(v) + 1e-300);
    EXPECT_LE((q.gradient - g).norm(), 1e-9 * g.norm() + 1e-300);
    EXPECT_EQ(q.value_bound, 0.0);
  }
}

// The kernel against an oracle that never sees the embedding: d_i from the pose distance
// (isotropic default, d_i = D_i^2 / sp^2) and from the geodesic angle (any sr,
// d_i = |dp|^2 / sp^2 + (2 sin(theta/2))^2 / sr^2).
TEST(TaskMap, QualityKernelIsGaussianInTheEmbedding) {
  const TaskMapData data = syntheticMap(kMapSize);
  double wsum = 0;
  for (double e : data.grasps.epsilon) wsum += e;
  for (int variant = 0; variant < 3; ++variant) {
    TaskMapOptions o;
    if (variant > 0) {
      o.position_sigma = 0.004;
      o.rotation_sigma = variant == 1 ? 0.1 : 0.02;  // rho sr above and below sp
    }
    const TaskMap map = TaskMap::fromData(data, o);
    const double sp = *map.options().position_sigma, sr = *map.options().rotation_sigma;
    const double rho = map.rotationScale();
    const double z = std::pow(2 * M_PI, 3) * std::pow(sp * sr, 3);
    EXPECT_DOUBLE_EQ(gaussianNormaliser(sp, sr), z);
    int checked = 0;
    for (const Pose& x : queries(map, 60, 43)) {
      double v = 0;
      for (std::size_t i = 0; i < map.size(); ++i) {
        const Pose mu = map.pose(i);
        const double dp2 = (x.position - mu.position).squaredNorm();
        const double chord = 2 * std::sin(rotationAngle(x.orientation, mu.orientation) / 2);
        const double d = variant == 0 ? std::pow(poseDistance(x, mu, rho), 2) / (sp * sp)
                                      : dp2 / (sp * sp) + chord * chord / (sr * sr);
        v -= data.grasps.epsilon[i] * std::exp(-0.5 * d) / z / wsum;
      }
      const QualityCriterion q = map.quality(x, std::nullopt, QualityMode::kExact);
      ASSERT_NEAR(q.value, v, 1e-9 * std::abs(v) + 1e-300) << "variant " << variant;
      checked += v < -1e-6 / z;
    }
    EXPECT_GT(checked, 20);  // most queries are near the map: the comparison is not vacuous
  }
}

// Duplicated grasps (rows permuted by the index layout) tie in distance: nearest, knn, radius
// and evaluate all put the smaller grasp index first.
TEST(TaskMap, TiesGoToTheSmallerGraspIndex) {
  const std::size_t n = 300;
  const TaskMapData twice = testing::duplicatedMap(n);
  TaskMapOptions o;
  o.position_sigma = 0.005;  // the sampling density of duplicates is 0
  const TaskMap map = TaskMap::fromData(twice, o);
  Rng rng(47, 0);
  for (int trial = 0; trial < 300; ++trial) {
    const std::size_t j = rng.below(n);
    Pose x = map.pose(j);
    if (trial % 2) x.position += Eigen::Vector3d(1e-4, -2e-4, 1e-4);
    const Neighbor nb = map.nearest(x);
    EXPECT_EQ(nb.index, j);
    EXPECT_EQ(map.evaluate(x).proximity.nearest.index, j);
    const auto k = map.knn(x, 2);
    ASSERT_EQ(k.size(), 2u);
    EXPECT_EQ(k[0].index, j);
    EXPECT_EQ(k[1].index, j + n);
    EXPECT_EQ(k[0].distance, k[1].distance);
    const auto r = map.radius(x, 0.02);
    ASSERT_GE(r.size(), 2u);
    for (std::size_t a = 1; a < r.size(); ++a)
      EXPECT_TRUE(r[a - 1].distance < r[a].distance ||
                  (r[a - 1].distance == r[a].distance && r[a - 1].index < r[a].index));
  }
}

TEST(TaskMap, DefaultSigmaFollowsSamplingDensity) {
  const TaskMap& map = sharedMap();
  // Median nearest-neighbour distance by brute force (every sample: 2000 < kDensitySamples).
  std::vector<double> nn;
  for (std::size_t i = 0; i < map.size(); ++i)
    nn.push_back(bruteForce(map, map.pose(i), std::nullopt, 2)[1].distance);
  std::nth_element(nn.begin(), nn.begin() + static_cast<std::ptrdiff_t>(nn.size() / 2), nn.end());
  EXPECT_NEAR(*map.options().position_sigma, nn[nn.size() / 2], 1e-12);
  EXPECT_NEAR(*map.options().rotation_sigma, *map.options().position_sigma / map.rotationScale(),
              1e-15);
  EXPECT_NEAR(*map.options().angular_weight, map.rotationScale() * map.rotationScale(), 1e-15);
}

TEST(TaskMap, TruncatedQualityWithinReportedBound) {
  // The last two: anisotropic kernels (s = max(sp, rho sr) is rho sr, then sp).
  const double tols[] = {1e-3, 0.1, 0.6, 0.1, 0.1};
  for (int variant = 0; variant < 5; ++variant) {
    const double tol = tols[variant];
    TaskMapOptions o;
    o.quality_tolerance = tol;
    if (variant >= 3) {
      o.position_sigma = 0.004;
      o.rotation_sigma = variant == 3 ? 0.1 : 0.02;
    }
    const TaskMap map = TaskMap::fromData(syntheticMap(600), o);
    const double peak =
        1.0 / gaussianNormaliser(*map.options().position_sigma, *map.options().rotation_sigma);
    const auto xs = queries(map, variant == 0 ? kQueries : 1000, 23);
    double worst_ratio = 0.0;
    for (const Pose& x : xs) {
      const QualityCriterion t = map.quality(x, std::nullopt, QualityMode::kTruncated);
      const QualityCriterion e = map.quality(x, std::nullopt, QualityMode::kExact);
      const double slack = 1e-12 * std::abs(e.value) + 1e-300;
      ASSERT_LE(std::abs(t.value - e.value), t.value_bound + slack);
      ASSERT_LE((t.gradient - e.gradient).norm(),
                t.gradient_bound + 1e-12 * e.gradient.norm() + 1e-300);
      ASSERT_LE(t.value_bound, tol * peak * (1 + 1e-12));
      if (t.value_bound > 0)
        worst_ratio = std::max(worst_ratio, std::abs(t.value - e.value) / t.value_bound);
      // evaluate() shares the search and gives the same quality.
      const Evaluation ev = map.evaluate(x);
      ASSERT_EQ(ev.quality.value, t.value);
      ASSERT_EQ(ev.quality.terms, t.terms);
    }
    // Truncation really omits mass (the comparison is not vacuous), more at loose tolerances.
    EXPECT_GT(worst_ratio, tol > 0.5 ? 1e-3 : 1e-4) << "variant " << variant;
  }
}

TEST(TaskMap, EvaluateMatchesSeparateQueries) {
  const TaskMap& map = sharedMap();
  for (const Pose& x : queries(map, 500, 29)) {
    for (std::optional<int> c : {std::optional<int>(), std::optional<int>(1)}) {
      const Evaluation e = map.evaluate(x, c);
      const ProximityResult p = map.proximity(x, c);
      const QualityCriterion q = map.quality(x, c);
      EXPECT_EQ(e.proximity.nearest.index, p.nearest.index);
      EXPECT_EQ(e.proximity.value, p.value);
      EXPECT_EQ(e.quality.value, q.value);
      EXPECT_EQ(e.cost(), p.value + q.value);
      if (c) {
        EXPECT_EQ(map.data().clustering->labels[e.proximity.nearest.index], *c);
      }
      EXPECT_NEAR(p.value, proximityCost(x, map.pose(p.nearest.index), 1.0, 0.01), 1e-15);
    }
  }
}

TEST(TaskMap, ConcurrentQueriesEqualSequential) {
  const TaskMap& map = sharedMap();
  const auto xs = queries(map, 2000, 31);
  std::vector<Evaluation> seq;
  for (const Pose& x : xs) seq.push_back(map.evaluate(x));
  std::vector<std::vector<Evaluation>> par(8);
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t) {
    threads.emplace_back([&, t] {
      for (const Pose& x : xs) par[static_cast<std::size_t>(t)].push_back(map.evaluate(x));
    });
  }
  for (auto& th : threads) th.join();
  for (const auto& res : par) {
    ASSERT_EQ(res.size(), seq.size());
    for (std::size_t i = 0; i < seq.size(); ++i) {
      ASSERT_EQ(res[i].proximity.nearest.index, seq[i].proximity.nearest.index);
      ASSERT_EQ(res[i].proximity.value, seq[i].proximity.value);
      ASSERT_EQ(res[i].quality.value, seq[i].quality.value);
      ASSERT_TRUE(res[i].gradient() == seq[i].gradient()) << i;
    }
  }
}

TEST(TaskMap, BatchEqualsSequentialForAnyThreadCount) {
  const auto raw = queries(sharedMap(), 1000, 37);
  PoseRows rows(static_cast<Eigen::Index>(raw.size()), 7);
  for (std::size_t i = 0; i < raw.size(); ++i) {
    Eigen::Matrix<double, 7, 1> v;
    v << raw[i].position, raw[i].orientation.w(), raw[i].orientation.vec();
    rows.row(static_cast<Eigen::Index>(i)) = v.transpose();
  }
  const std::vector<Pose> xs = posesFromRows(rows);  // the poses the batch sees
  for (int threads : {1, 3, 8}) {
    TaskMapOptions o;
    o.threads = threads;
    const TaskMap map = TaskMap::fromData(syntheticMap(kMapSize), o);
    const BatchEvaluation b = map.evaluateBatch(rows, 2);
    Eigen::VectorXd d;
    const auto nn = map.nearestBatch(rows, &d);
    for (std::size_t i = 0; i < xs.size(); ++i) {
      const auto r = static_cast<Eigen::Index>(i);
      const Evaluation e = map.evaluate(xs[i], 2);
      ASSERT_EQ(b.proximity[r], e.proximity.value);
      ASSERT_EQ(b.quality[r], e.quality.value);
      ASSERT_TRUE(b.proximity_gradient.row(r).transpose() == e.proximity.gradient);
      ASSERT_TRUE(b.quality_gradient.row(r).transpose() == e.quality.gradient);
      ASSERT_EQ(b.nearest[r], static_cast<std::int64_t>(e.proximity.nearest.index));
      const Neighbor n = map.nearest(xs[i]);
      ASSERT_EQ(nn[r], static_cast<std::int64_t>(n.index));
      ASSERT_EQ(d[r], n.distance);
    }
  }
}

TEST(TaskMap, InvalidDataAndOptionsGiveClearErrors) {
  auto with = [](auto edit) {
    TaskMapData d = syntheticMap(100);
    edit(d);
    return errorMessage([&] { TaskMap::fromData(d); });
  };
  EXPECT_EQ(with([](TaskMapData& d) { d.grasps.pose(5, 1) = NAN; }),
            "/grasps row 5: pose has a non-finite value");
  EXPECT_NE(with([](TaskMapData& d) {
              d.grasps.pose(7, 3) = 2.0;
            }).find("/grasps row 7: orientation is not a unit quaternion"),
            std::string::npos);
  EXPECT_EQ(with([](TaskMapData& d) { d.grasps.epsilon.pop_back(); }),
            "/grasps/epsilon has 99 entries; expected 100 (one per grasp)");
  EXPECT_NE(with([](TaskMapData& d) { d.grasps.epsilon[3] = -1; }).find("/grasps row 3: epsilon"),
            std::string::npos);
  EXPECT_EQ(with([](TaskMapData& d) { d.clustering->labels[4] = 3; }),
            "/grasps row 4: cluster label 3 outside -1..2");
  EXPECT_EQ(with([](TaskMapData& d) { d.grasps.pose.resize(0, 7); }),
            "task map has no grasps; build a map with at least one valid grasp");
  EXPECT_EQ(with([](TaskMapData& d) { d.grasps.rotation_scale = 0; }),
            "/grasps rotation_scale is not a finite positive length (metres per radian)");

  TaskMapOptions o;
  o.quality_tolerance = 1.5;
  EXPECT_NE(errorMessage([&] { TaskMap::fromData(syntheticMap(10), o); }).find("quality_tolerance"),
            std::string::npos);
  o = TaskMapOptions();
  o.position_sigma = -1;
  EXPECT_NE(errorMessage([&] { TaskMap::fromData(syntheticMap(10), o); }).find("position_sigma"),
            std::string::npos);

  const TaskMap& map = sharedMap();
  EXPECT_EQ(errorMessage([&] { map.nearest(Pose(), 3); }),
            "cluster 3 does not exist; the map has clusters 0..2");
  EXPECT_EQ(errorMessage([&] { map.knn(Pose(), 0); }), "knn: k = 0 is invalid; give k >= 1");
  TaskMapData unclustered = syntheticMap(50);
  unclustered.clustering.reset();
  const TaskMap plain = TaskMap::fromData(unclustered);
  EXPECT_EQ(plain.numClusters(), 0);
  EXPECT_NE(errorMessage([&] { plain.evaluate(Pose(), 0); }).find("no clustering"),
            std::string::npos);
  PoseRows bad = PoseRows::Zero(3, 7);
  bad(0, 3) = 1;
  bad(2, 3) = 1;
  EXPECT_NE(errorMessage([&] { map.evaluateBatch(bad); }).find("pose row 1"), std::string::npos);
}

std::string tempPath(const std::string& name) {
  return std::string(TASKMAP_BINARY_DIR) + "/integration_test_" + name;
}

TEST(TaskMap, LoadsWhatWriteMapWrote) {
  const std::string path = tempPath("roundtrip.h5");
  const TaskMapData data = syntheticMap(300);
  writeMap(path, data);
  const TaskMap loaded = TaskMap::load(path);
  const TaskMap direct = TaskMap::fromData(data);
  ASSERT_EQ(loaded.size(), 300u);
  ASSERT_EQ(loaded.numClusters(), 3);
  for (const Pose& x : queries(direct, 200, 41)) {
    const Evaluation a = loaded.evaluate(x), b = direct.evaluate(x);
    EXPECT_EQ(a.proximity.nearest.index, b.proximity.nearest.index);
    EXPECT_NEAR(a.cost(), b.cost(), 1e-12 * std::abs(b.cost()));
  }
  std::remove(path.c_str());
}

TEST(TaskMap, CorruptOrMissingFileRaisesError) {
  const std::string path = tempPath("corrupt.h5");
  {
    std::ofstream f(path, std::ios::binary);
    f << "this is not an HDF5 file";
  }
  const std::string msg = errorMessage([&] { TaskMap::load(path); });
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  std::remove(path.c_str());
  EXPECT_NE(errorMessage([&] { TaskMap::load(tempPath("missing.h5")); }).find("missing.h5"),
            std::string::npos);
  // A truncated real map file.
  const std::string cut = tempPath("truncated.h5");
  writeMap(cut, syntheticMap(100));
  {
    std::ifstream in(cut, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    in.close();
    std::ofstream out(cut, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 2));
  }
  EXPECT_NE(errorMessage([&] { TaskMap::load(cut); }), "no error");
  std::remove(cut.c_str());
}

}  // namespace
}  // namespace taskmap
