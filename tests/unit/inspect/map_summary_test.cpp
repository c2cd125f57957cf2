// The map summary (`taskmap inspect`): counts, epsilon statistics and the cluster table against
// the map's own arrays, the JSON form against the struct, and inspectMap's errors.
#include "taskmap/inspect/map_summary.hpp"

#include <algorithm>
#include <set>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "error_matchers.hpp"
#include "scratch_dir.hpp"
#include "synthetic_map.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap {
namespace {

using testing::clusteredBasketMap;
using testing::throwsError;

TEST(EpsilonStats, MedianOfOddAndEvenCountsAndEmpty) {
  const EpsilonStats odd = epsilonStats({3.0, 1.0, 2.0});
  EXPECT_EQ(odd.count, 3u);
  EXPECT_DOUBLE_EQ(odd.min, 1.0);
  EXPECT_DOUBLE_EQ(odd.median, 2.0);
  EXPECT_DOUBLE_EQ(odd.max, 3.0);
  EXPECT_DOUBLE_EQ(epsilonStats({4.0, 1.0, 2.0, 3.0}).median, 2.5);
  const EpsilonStats none = epsilonStats({});
  EXPECT_EQ(none.count, 0u);
  EXPECT_DOUBLE_EQ(none.median, 0.0);
}

TEST(MapSummary, CountsAndStatisticsMatchTheMapArrays) {
  const TaskMapData map = clusteredBasketMap();
  const MapSummary s = summarizeMap(map, "dir/basket.h5");
  EXPECT_EQ(s.path, "dir/basket.h5");
  EXPECT_EQ(s.grasps, map.grasps.size());
  // Oracle: the force-closure flags and epsilons, counted and sorted here.
  std::vector<double> fc;
  for (std::size_t i = 0; i < map.grasps.size(); ++i)
    if (map.grasps.force_closure[i]) fc.push_back(map.grasps.epsilon[i]);
  std::sort(fc.begin(), fc.end());
  EXPECT_EQ(s.force_closure, fc.size());
  EXPECT_EQ(s.epsilon.count, fc.size());
  EXPECT_DOUBLE_EQ(s.epsilon.min, fc.front());
  EXPECT_DOUBLE_EQ(s.epsilon.max, fc.back());
  EXPECT_DOUBLE_EQ(s.valid_rate, static_cast<double>(fc.size()) / map.sampling.trials);
  EXPECT_EQ(s.outliers, static_cast<std::size_t>(std::count(map.clustering->labels.begin(),
                                                            map.clustering->labels.end(), -1)));
  ASSERT_EQ(s.clusters.size(), map.clustering->clusters.size());
  for (const ClusterRow& row : s.clusters) {
    const int rep = row.representative;
    EXPECT_TRUE(row.pose.isApprox(map.grasps.pose.row(rep).transpose()));
    // The approach axis is the palm's +z column.
    const Pose p = map.grasps.poseAt(static_cast<std::size_t>(rep));
    EXPECT_TRUE(row.approach.isApprox(p.orientation.toRotationMatrix().col(2), 1e-12));
    EXPECT_EQ(row.color, clusterColorHex(row.id));
  }
  EXPECT_NE(formatSummary(s).find("clusters   3 (single linkage"), std::string::npos);
}

TEST(MapSummary, JsonHoldsTheStructsNumbers) {
  const MapSummary s = summarizeMap(clusteredBasketMap(), "m.h5");
  const nlohmann::json j = nlohmann::json::parse(summaryJson(s));
  EXPECT_EQ(j["grasps"]["count"].get<std::size_t>(), s.grasps);
  EXPECT_EQ(j["epsilon"]["median"].get<double>(), s.epsilon.median);
  EXPECT_EQ(j["clustering"]["clusters"].size(), s.clusters.size());
  EXPECT_EQ(j["clustering"]["clusters"][1]["size"].get<int>(), s.clusters[1].size);
  TaskMapData unclustered = clusteredBasketMap();
  unclustered.clustering.reset();
  EXPECT_TRUE(nlohmann::json::parse(summaryJson(summarizeMap(unclustered, "u.h5")))["clustering"]
                  .is_null());
}

TEST(ClusterColor, DistinctForManyClustersGreyForOutliers) {
  std::set<std::array<std::uint8_t, 3>> seen;
  for (int k = 0; k < 60; ++k) {
    const auto c = clusterColor(k);
    EXPECT_TRUE(seen.insert(c).second) << k;
    EXPECT_FALSE(c[0] == c[1] && c[1] == c[2]) << "cluster " << k << " is grey";
  }
  EXPECT_EQ(clusterColor(-1), (std::array<std::uint8_t, 3>{150, 150, 150}));
  EXPECT_EQ(clusterColorHex(0), "#1f77b4");
}

TEST(InspectMap, ReadsAndSummarisesAFileAndNamesAMissingOne) {
  testing::ScratchDir dir("inspect_map");
  const std::string path = dir.path("m.h5");
  const TaskMapData map = clusteredBasketMap();
  writeMap(path, map);
  InspectOptions options;
  options.map = path;
  const InspectResult r = inspectMap(options);
  EXPECT_EQ(r.status, InspectResult::Status::kOk);
  EXPECT_EQ(summaryJson(r.summary), summaryJson(summarizeMap(map, path)));
  options.map = dir.path("none.h5");
  EXPECT_TRUE(throwsError([&] { inspectMap(options); },
                          {"map file '" + options.map + "' does not exist", "task map (.h5)"}));
  TaskMapData plain = map;
  plain.clustering.reset();
  writeMap(path, plain);
  options.map = path;
  const InspectResult u = inspectMap(options);
  EXPECT_EQ(u.status, InspectResult::Status::kNotClustered);
  EXPECT_EQ(u.message, "the map holds no clustering");
}

}  // namespace
}  // namespace taskmap
