// builder/recluster.hpp: re-clustering a built map (`taskmap cluster`, Python taskmap.recluster)
// equals clustering its grasps from scratch with the same options; the stored dendrogram is
// reused when the method and metric match; bad options are refused naming them.
#include "taskmap/builder/recluster.hpp"

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "error_matchers.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap {
namespace {

const std::string kMap = std::string(TASKMAP_SOURCE_DIR) + "/meshes/maps/basket_humanoid.h5";

std::vector<Pose> posesOf(const TaskMapData& map) {
  std::vector<Pose> poses;
  for (std::size_t i = 0; i < map.grasps.size(); ++i) poses.push_back(map.grasps.poseAt(i));
  return poses;
}

TEST(ReclusterTest, ACutOfTheStoredDendrogramEqualsClusteringFromScratch) {
  TaskMapData map = readMap(kMap);
  ASSERT_TRUE(map.clustering.has_value());
  ReclusterOptions o;
  o.clusters = 4;
  o.method = toString(map.clustering->method);
  const ReclusterResult r = reclusterMap(&map, o);
  EXPECT_TRUE(r.reused_dendrogram);
  EXPECT_EQ(r.grasps, map.grasps.size());
  ClusteringOptions scratch;
  scratch.method = linkageFromString(*o.method);
  scratch.fallback_to_single = false;
  scratch.num_clusters = 4;
  scratch.rotation_scale = map.grasps.rotation_scale;
  const ClusteringResult expected = clusterGrasps(posesOf(map), map.grasps.epsilon, scratch);
  EXPECT_EQ(map.clustering->labels, expected.labels);
  EXPECT_EQ(map.clustering->clusters.size(), expected.clusters.size());
  EXPECT_LE(map.clustering->clusters.size(), 4u);
  const std::string text = reclusterText(map, r, "m.h5");
  EXPECT_NE(text.find("stored dendrogram"), std::string::npos);
  EXPECT_NE(text.find("wrote m.h5"), std::string::npos);
}

TEST(ReclusterTest, AnotherMethodClustersAgain) {
  TaskMapData map = readMap(kMap);
  ReclusterOptions o;
  o.method = map.clustering->method == Linkage::kSingle ? "complete" : "single";
  o.threshold = 0.05;
  const ReclusterResult r = reclusterMap(&map, o);
  EXPECT_FALSE(r.reused_dendrogram);
  EXPECT_EQ(map.clustering->method, linkageFromString(*o.method));
  EXPECT_EQ(map.clustering->labels.size(), map.grasps.size());
}

TEST(ReclusterTest, RefusesContradictingAndOutOfRangeOptions) {
  TaskMapData map = readMap(kMap);
  ReclusterOptions both;
  both.threshold = 0.1;
  both.clusters = 3;
  EXPECT_TRUE(testing::throwsError([&] { reclusterMap(&map, both); }, {"threshold", "not both"}));
  ReclusterOptions method;
  method.method = "ward";
  EXPECT_TRUE(testing::throwsError([&] { reclusterMap(&map, method); }, {"ward"}));
}

}  // namespace
}  // namespace taskmap
