// The regression statistics (`taskmap regress`): quantiles against numpy's linear interpolation
// (values worked by hand), the golden file round trip, the tolerances of the comparison, and
// the errors for missing and broken golden files.
#include "taskmap/inspect/regression.hpp"

#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "error_matchers.hpp"
#include "scratch_dir.hpp"
#include "synthetic_map.hpp"

namespace taskmap {
namespace {

using testing::clusteredBasketMap;
using testing::throwsError;

/// A map of four force-closure grasps with epsilon 1, 2, 3, 4 and one that is not.
TaskMapData fourGraspMap() {
  TaskMapData m = clusteredBasketMap(4, 1);
  m.grasps.epsilon.assign(m.grasps.size(), 0.0);
  m.grasps.force_closure.assign(m.grasps.size(), 0);
  for (int i = 0; i < 4; ++i) {
    m.grasps.epsilon[static_cast<std::size_t>(i)] = 4.0 - i;
    m.grasps.force_closure[static_cast<std::size_t>(i)] = 1;
  }
  return m;
}

TEST(RegressionStatistics, QuantilesAreNumpysLinearInterpolation) {
  const MapStatistics s = computeStatistics(fourGraspMap());
  EXPECT_EQ(s.valid, 4u);
  // numpy.quantile([1, 2, 3, 4], [0.1, 0.5, 0.9]) = [1.3, 2.5, 3.7]
  EXPECT_NEAR(s.epsilon_q10, 1.3, 1e-12);
  EXPECT_NEAR(s.epsilon_q50, 2.5, 1e-12);
  EXPECT_NEAR(s.epsilon_q90, 3.7, 1e-12);
  EXPECT_TRUE(std::is_sorted(s.cluster_sizes.rbegin(), s.cluster_sizes.rend()));
  EXPECT_EQ(s.representatives.size(), s.cluster_sizes.size());
}

TEST(RegressionStatistics, GoldenFileRoundTripsAndRecordsTheCase) {
  const MapStatistics s = computeStatistics(clusteredBasketMap());
  RegressionCase c;
  c.name = "basket";
  c.object = "objects/basket.obj";
  c.hand = "hands/humanoid/humanoid.urdf";
  c.sampler = "mixed";
  c.seed = 3;
  c.trials = 500;
  const std::string text = goldenFileText(s, c);
  EXPECT_EQ(text.back(), '\n');
  const nlohmann::json j = nlohmann::json::parse(text);
  EXPECT_EQ(j["case"]["seed"].get<int>(), 3);
  EXPECT_FALSE(j["case"].contains("sidecar"));
  const MapStatistics back = statisticsFromJsonText(text, "basket.json");
  const RegressionResult r = compareWithGolden("basket", back, s);
  EXPECT_EQ(r.status, RegressionResult::Status::kPass) << r.message;
  EXPECT_TRUE(r.message.empty());
  for (const ComparisonRow& row : r.rows) EXPECT_EQ(row.golden, row.now) << row.statistic;
}

TEST(RegressionStatistics, ToleranceIsTwoPercentOnEpsilonAndExactOnCounts) {
  const MapStatistics golden = computeStatistics(clusteredBasketMap());
  MapStatistics now = golden;
  now.epsilon_q50 *= 1.015;  // inside 2 %
  EXPECT_EQ(compareWithGolden("c", golden, now).status, RegressionResult::Status::kPass);
  now.epsilon_q50 = golden.epsilon_q50 * 1.03;  // outside
  RegressionResult r = compareWithGolden("c", golden, now);
  EXPECT_EQ(r.status, RegressionResult::Status::kFail);
  EXPECT_EQ(r.message, "1 statistic(s) failed");
  now = golden;
  now.cluster_sizes[0] += 1;
  now.outliers -= 1;
  r = compareWithGolden("c", golden, now);
  EXPECT_EQ(r.message, "2 statistic(s) failed");
  now = golden;
  now.representatives[0][0] += 0.002;  // 2 mm > 1 mm
  EXPECT_EQ(compareWithGolden("c", golden, now).status, RegressionResult::Status::kFail);
}

TEST(RegressionStatistics, MissingAndBrokenGoldenFiles) {
  testing::ScratchDir dir("regression_golden");
  EXPECT_FALSE(readGoldenFile(dir.path("none.json")).has_value());
  const std::string bad = dir.path("bad.json");
  std::ofstream(bad) << "{\"trials\": 3";
  EXPECT_TRUE(throwsError([&] { readGoldenFile(bad); }, {bad, "not valid JSON"}));
  std::ofstream(bad) << "{\"trials\": 3}";
  EXPECT_TRUE(throwsError([&] { readGoldenFile(bad); },
                          {bad, "not a golden statistics file", "taskmap regress --update"}));
}

TEST(RegressionCases, BadEntriesNameTheFile) {
  testing::ScratchDir dir("regression_cases");
  const std::string path = dir.path("cases.json");
  std::ofstream(path) << R"({"cases": [{"name": "a", "object": "o.obj", "hand": "h.urdf",
                            "trials": 0}]})";
  EXPECT_TRUE(throwsError([&] { readCases(path); }, {path, "trials = 0"}));
  std::ofstream(path) << R"({"cases": [{"name": "a", "object": "o.obj", "hand": "h.urdf",
                            "trials": 10}]})";
  const auto cases = readCases(path);
  ASSERT_EQ(cases.size(), 1u);
  EXPECT_EQ(cases[0].sampler, "mixed");
  EXPECT_EQ(cases[0].seed, 1u);
}

}  // namespace
}  // namespace taskmap
