// EvaluationSession against TaskMap::evaluate: optimizer-like trajectories (cache reuse),
// random jumps and approaches from far away (re-anchoring and fallbacks), clusters, margin 0,
// ties, the randomized forest, exact mode, and invalid arguments.
#include "taskmap/integration/evaluation_session.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "error_matchers.hpp"
#include "synthetic_map.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/integration/criteria.hpp"
#include "taskmap/integration/task_map.hpp"

namespace taskmap {
namespace {

using testing::randomPose;
using testing::syntheticMap;

constexpr std::size_t kMapSize = 2000;

const TaskMap& sharedMap() {
  static const TaskMap map = TaskMap::fromData(syntheticMap(kMapSize));
  return map;
}

// |a - b| <= rel * max(|a|, |b|) + abs.
bool near(double a, double b, double rel, double abs = 0.0) {
  return std::abs(a - b) <= rel * std::max(std::abs(a), std::abs(b)) + abs;
}
bool nearVec(const Twist& a, const Twist& b, double rel) {
  return (a - b).norm() <= rel * std::max(a.norm(), b.norm());
}

// Worst relative differences seen (printed once per test, to show the margin to the limits).
struct Worst {
  double value = 0, gradient = 0;
  void add(const Evaluation& s, const Evaluation& e) {
    const double v = std::max(std::abs(s.quality.value), std::abs(e.quality.value));
    if (v > 0) value = std::max(value, std::abs(s.quality.value - e.quality.value) / v);
    const double g = std::max(s.quality.gradient.norm(), e.quality.gradient.norm());
    if (g > 0) gradient = std::max(gradient, (s.quality.gradient - e.quality.gradient).norm() / g);
  }
};

// The session's result equals evaluate's: the same nearest sample and distance and the same
// proximity (bitwise: the same computation), the same term count; the mixture's value and
// gradient within 1e-12 relative (the terms are summed in another order). The bounds depend on
// the summed weight only: relative 1e-12, or absolute 1e-13 of the bound for an omitted
// weight fraction of 1 (the difference total - included loses digits when little is omitted).
void expectSame(const TaskMap& map, const Evaluation& s, const Evaluation& e, const char* where,
                std::size_t step, Worst* worst = nullptr) {
  SCOPED_TRACE(std::string(where) + ", step " + std::to_string(step));
  EXPECT_EQ(s.proximity.nearest.index, e.proximity.nearest.index);
  EXPECT_EQ(s.proximity.nearest.distance, e.proximity.nearest.distance);
  EXPECT_EQ(s.proximity.value, e.proximity.value);
  EXPECT_EQ(s.proximity.gradient, e.proximity.gradient);
  EXPECT_EQ(s.quality.terms, e.quality.terms);
  EXPECT_TRUE(near(s.quality.value, e.quality.value, 1e-12))
      << s.quality.value << " vs " << e.quality.value;
  EXPECT_TRUE(nearVec(s.quality.gradient, e.quality.gradient, 1e-12))
      << s.quality.gradient.transpose() << " vs " << e.quality.gradient.transpose();
  const double unit_v =
      map.options().quality_tolerance /
      gaussianNormaliser(*map.options().position_sigma, *map.options().rotation_sigma);
  EXPECT_TRUE(near(s.quality.value_bound, e.quality.value_bound, 1e-12, 1e-13 * unit_v))
      << s.quality.value_bound << " vs " << e.quality.value_bound;
  if (e.quality.value_bound > 0) {
    const double unit_g = unit_v * e.quality.gradient_bound / e.quality.value_bound;
    EXPECT_TRUE(near(s.quality.gradient_bound, e.quality.gradient_bound, 1e-12, 1e-13 * unit_g))
        << s.quality.gradient_bound << " vs " << e.quality.gradient_bound;
  } else {
    EXPECT_EQ(s.quality.gradient_bound, e.quality.gradient_bound);
  }
  if (worst) worst->add(s, e);
}

Pose perturbed(const Pose& p, double dp, double dr, Rng& rng) {
  Pose x = p;
  x.position += dp * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
  x.orientation = Eigen::Quaterniond(
      rotationExp(dr * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal())) *
      x.orientation.toRotationMatrix());
  return x;
}

// x + a (target - x) in position and rotation (geodesic), plus noise.
Pose step(const Pose& x, const Pose& target, double a, double noise_p, double noise_r, Rng& rng) {
  Pose y;
  y.position = x.position + a * (target.position - x.position);
  const Eigen::Matrix3d r = x.orientation.toRotationMatrix();
  const Eigen::Matrix3d rel = target.orientation.toRotationMatrix() * r.transpose();
  y.orientation = Eigen::Quaterniond(rotationExp(a * rotationLog(rel)) * r);
  return perturbed(y, noise_p, noise_r, rng);
}

// An optimizer's iterates: from a few kernel widths away (or from a random pose in the box),
// converging geometrically to a map sample (of cluster `cluster` if >= 0).
std::vector<Pose> trajectory(const TaskMap& map, Rng& rng, int iterates, double start_widths,
                             bool from_far, double rate, int cluster = -1) {
  const double sp = *map.options().position_sigma;
  const double sr = *map.options().rotation_sigma;
  std::size_t target_index = rng.below(map.size());
  if (cluster >= 0)
    while (map.data().clustering->labels[target_index] != cluster)
      target_index = rng.below(map.size());
  const Pose target = map.pose(target_index);
  Pose x =
      from_far ? randomPose(rng) : perturbed(target, start_widths * sp, start_widths * sr, rng);
  std::vector<Pose> out;
  for (int k = 0; k < iterates; ++k) {
    Pose y = x;
    if (k % 2 == 1) y.orientation.coeffs() *= -1.0;  // q and -q are the same pose
    out.push_back(y);
    x = step(x, target, rate, 0.1 * sp, 0.1 * sr, rng);
  }
  return out;
}

TEST(EvaluationSession, TrajectoriesEqualEvaluateAndReuseTheCache) {
  const TaskMap& map = sharedMap();
  Rng rng(11, 0);
  SessionStats total;
  Worst worst;
  for (int t = 0; t < 80; ++t) {
    EvaluationSession session(map);
    const std::vector<Pose> xs = trajectory(map, rng, 25, 3.0, false, 0.25);
    for (std::size_t k = 0; k < xs.size(); ++k)
      expectSame(map, session.evaluate(xs[k]), map.evaluate(xs[k]), "trajectory", k, &worst);
    EXPECT_EQ(session.stats().calls, xs.size());
    total.calls += session.stats().calls;
    total.anchors += session.stats().anchors;
    total.fallbacks += session.stats().fallbacks;
  }
  std::printf(
      "trajectories: %zu calls, %zu anchors, %zu fallbacks; worst relative value %.3g, "
      "gradient %.3g\n",
      total.calls, total.anchors, total.fallbacks, worst.value, worst.gradient);
  // Reuse: the iterates converge, so most calls are answered from the cache.
  EXPECT_LT(4 * total.anchors, total.calls);
}

TEST(EvaluationSession, JumpsAndFarApproachesReanchorAndFallBack) {
  const TaskMap& map = sharedMap();
  Rng rng(12, 0);
  const double sp = *map.options().position_sigma;
  const double sr = *map.options().rotation_sigma;
  // Random jumps: every call far from the previous one.
  {
    EvaluationSession session(map);
    for (std::size_t k = 0; k < 400; ++k) {
      const Pose x = k % 3 == 0 ? randomPose(rng)
                                : perturbed(map.pose(rng.below(map.size())), 2 * sp, 2 * sr, rng);
      expectSame(map, session.evaluate(x), map.evaluate(x), "jump", k);
    }
    EXPECT_EQ(session.stats().calls, 400u);
    EXPECT_GT(session.stats().anchors, 300u);  // nearly every jump leaves the cached ball
  }
  // Slow approaches from random poses in the box: far from the map, the cached ball holds no
  // certified nearest sample, so the session falls back to a search.
  SessionStats total;
  for (int t = 0; t < 30; ++t) {
    EvaluationSession session(map);
    const std::vector<Pose> xs = trajectory(map, rng, 60, 0.0, true, 0.08);
    for (std::size_t k = 0; k < xs.size(); ++k)
      expectSame(map, session.evaluate(xs[k]), map.evaluate(xs[k]), "approach", k);
    total.anchors += session.stats().anchors;
    total.fallbacks += session.stats().fallbacks;
    EXPECT_LE(session.stats().fallbacks, session.stats().anchors);
  }
  EXPECT_GT(total.fallbacks, 0u);
}

TEST(EvaluationSession, ClusterSessionsEqualClusterEvaluate) {
  const TaskMap& map = sharedMap();
  Rng rng(13, 0);
  for (int c = 0; c < map.numClusters(); ++c) {
    EvaluationSession session(map, c);
    EXPECT_EQ(session.cluster(), c);
    for (int t = 0; t < 10; ++t) {
      // Targets in this cluster and in the others (the cluster's nearest is then far away).
      const std::vector<Pose> xs = trajectory(map, rng, 25, 3.0, false, 0.25, t % 2 == 0 ? c : -1);
      for (std::size_t k = 0; k < xs.size(); ++k)
        expectSame(map, session.evaluate(xs[k]), map.evaluate(xs[k], c), "cluster", k);
    }
    EXPECT_LT(session.stats().anchors, session.stats().calls);
  }
}

TEST(EvaluationSession, ZeroMarginReusesOnlyTheSamePose) {
  const TaskMap& map = sharedMap();
  Rng rng(14, 0);
  EvaluationSession session(map, std::nullopt, 0.0);
  EXPECT_EQ(session.margin(), 0.0);
  const std::vector<Pose> xs = trajectory(map, rng, 25, 3.0, false, 0.25);
  for (std::size_t k = 0; k < xs.size(); ++k) {
    expectSame(map, session.evaluate(xs[k]), map.evaluate(xs[k]), "margin 0", k);
    expectSame(map, session.evaluate(xs[k]), map.evaluate(xs[k]), "margin 0, again", k);
  }
  // Each new pose anchors; its repetition (delta = 0) is answered from the cache unless its
  // nearest sample lies beyond the cut-off (then it cannot be certified with R = cut-off).
  EXPECT_EQ(session.stats().calls, 2 * xs.size());
  EXPECT_GE(session.stats().anchors, xs.size());
  EXPECT_LT(session.stats().anchors, 2 * xs.size());
  EXPECT_EQ(session.stats().anchors - xs.size(), session.stats().fallbacks);
}

TEST(EvaluationSession, DefaultMarginStatsAndReset) {
  const TaskMap& map = sharedMap();
  EvaluationSession session(map);
  EXPECT_DOUBLE_EQ(session.margin(), EvaluationSession::kDefaultMarginFactor * map.cutoffRadius());
  EXPECT_FALSE(session.cluster().has_value());
  const Pose x = map.pose(5);
  session.evaluate(x);
  EXPECT_GT(session.cachedSamples(), 0u);
  session.evaluate(x);
  EXPECT_EQ(session.stats().calls, 2u);
  EXPECT_EQ(session.stats().anchors, 1u);
  EXPECT_EQ(session.stats().fallbacks, 0u);
  session.reset();
  EXPECT_EQ(session.stats().calls, 0u);
  EXPECT_EQ(session.cachedSamples(), 0u);
  expectSame(map, session.evaluate(x), map.evaluate(x), "after reset", 0);
  EXPECT_EQ(session.stats().anchors, 1u);
  // A moved session keeps its cache.
  EvaluationSession moved = std::move(session);
  moved.evaluate(x);
  EXPECT_EQ(moved.stats().anchors, 1u);
  EXPECT_EQ(moved.stats().calls, 2u);
}

TEST(EvaluationSession, TiesGoToTheSmallerGraspIndex) {
  // Every sample twice: the cached nearest must pick the smaller index, as evaluate does.
  const std::size_t n = 300;
  const TaskMapData twice = testing::duplicatedMap(n);
  TaskMapOptions o;
  o.position_sigma = 0.005;
  const TaskMap map = TaskMap::fromData(twice, o);
  Rng rng(48, 0);
  EvaluationSession session(map);
  for (std::size_t trial = 0; trial < 300; ++trial) {
    const std::size_t j = rng.below(n);
    Pose x = map.pose(j);
    const Evaluation first = session.evaluate(x);
    EXPECT_EQ(first.proximity.nearest.index, j);
    expectSame(map, first, map.evaluate(x), "tie", trial);
    x.position += Eigen::Vector3d(1e-4, -2e-4, 1e-4);  // small move: from the cache
    const Evaluation second = session.evaluate(x);
    EXPECT_EQ(second.proximity.nearest.index, j);
    expectSame(map, second, map.evaluate(x), "tie, moved", trial);
  }
  EXPECT_LT(session.stats().anchors, session.stats().calls);
}

TEST(EvaluationSession, RandomizedForestKeepsEvaluatesContract) {
  TaskMapOptions o;
  o.index = IndexKind::kRandomizedForest;
  o.trees = 2;
  o.checks = 8;  // few checks: the forest's nearest is often not the exact one
  const TaskMap map = TaskMap::fromData(syntheticMap(kMapSize), o);
  Rng rng(15, 0);
  for (int t = 0; t < 20; ++t) {
    EvaluationSession session(map);
    const bool far = t % 4 == 3;
    const std::vector<Pose> xs = trajectory(map, rng, 25, 3.0, far, far ? 0.08 : 0.25);
    for (std::size_t k = 0; k < xs.size(); ++k)
      expectSame(map, session.evaluate(xs[k]), map.evaluate(xs[k]), "forest", k);
    EXPECT_LT(session.stats().anchors, session.stats().calls);
    EXPECT_EQ(session.stats().fallbacks, 0u);
  }
}

TEST(EvaluationSession, ExactModeDelegatesToEvaluate) {
  TaskMapOptions o;
  o.quality_mode = QualityMode::kExact;
  const TaskMap map = TaskMap::fromData(syntheticMap(500), o);
  Rng rng(16, 0);
  EvaluationSession session(map, 1);
  const std::vector<Pose> xs = trajectory(map, rng, 25, 3.0, false, 0.25);
  for (const Pose& x : xs) {
    const Evaluation s = session.evaluate(x), e = map.evaluate(x, 1);
    EXPECT_EQ(s.proximity.nearest.index, e.proximity.nearest.index);
    EXPECT_EQ(s.proximity.value, e.proximity.value);
    EXPECT_EQ(s.quality.value, e.quality.value);  // the same call: bitwise
    EXPECT_EQ(s.quality.gradient, e.quality.gradient);
    EXPECT_EQ(s.quality.terms, e.quality.terms);
    EXPECT_EQ(s.quality.value_bound, 0.0);
  }
  EXPECT_EQ(session.stats().calls, xs.size());
  EXPECT_EQ(session.stats().anchors, 0u);
  EXPECT_EQ(session.cachedSamples(), 0u);
}

TEST(EvaluationSession, InvalidArgumentsGiveClearErrors) {
  const TaskMap& map = sharedMap();
  for (const double bad : {-1e-3, std::nan(""), std::numeric_limits<double>::infinity()}) {
    try {
      EvaluationSession s(map, std::nullopt, bad);
      ADD_FAILURE() << "margin " << bad << " accepted";
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("margin"), std::string::npos) << what;
      EXPECT_NE(what.find(">= 0"), std::string::npos) << what;
    }
  }
  EXPECT_TRUE(testing::throwsError([&] { EvaluationSession s(map, 7); }, {"cluster 7"}));
  TaskMapData plain = syntheticMap(300);
  plain.clustering.reset();
  const TaskMap unclustered = TaskMap::fromData(plain);
  EXPECT_THROW(EvaluationSession(unclustered, 0), Error);
}

}  // namespace
}  // namespace taskmap
