// The export scene of a map (`taskmap export --format ply|glb`): object, points and glyphs
// against the map's arrays, cluster colours, the automatic glyph size, the hand's parts.
#include "taskmap/inspect/map_scene.hpp"

#include <gtest/gtest.h>

#include "error_matchers.hpp"
#include "synthetic_map.hpp"
#include "taskmap/inspect/map_summary.hpp"
#include "viz_fixtures.hpp"

namespace taskmap {
namespace {

using testing::clusteredBasketMap;
using testing::throwsError;

TEST(MapScene, PointsGlyphsAndColoursFollowTheMap) {
  const TaskMapData map = clusteredBasketMap();
  const ExportScene s = mapScene(map);
  EXPECT_NO_THROW(s.validate());
  EXPECT_EQ(s.object.vertices.size(), static_cast<std::size_t>(map.object.vertices.rows()));
  EXPECT_EQ(s.object.faces.size(), static_cast<std::size_t>(map.object.faces.rows()));
  ASSERT_EQ(s.points.size(), map.grasps.size());
  for (std::size_t i = 0; i < map.grasps.size(); ++i) {
    EXPECT_TRUE(s.points[i].isApprox(map.grasps.poseAt(i).position));
    const auto c = clusterColor(map.clustering->labels[i]);
    EXPECT_FLOAT_EQ(s.point_colors[i].x(), c[0] / 255.0f);
  }
  ASSERT_EQ(s.glyphs.size(), map.clustering->clusters.size());
  const int rep = map.clustering->clusters[1].representative;
  EXPECT_TRUE(s.glyphs[1].pose.isApprox(map.grasps.poseAt(rep).toIsometry()));
  // Automatic glyph size: min(rho, a fifth of the object's largest extent).
  const double extent =
      (map.object.vertices.colwise().maxCoeff() - map.object.vertices.colwise().minCoeff())
          .maxCoeff();
  EXPECT_DOUBLE_EQ(s.glyph_size, std::min(map.grasps.rotation_scale, 0.2 * extent));
  EXPECT_TRUE(s.parts.empty());
  MapSceneOptions options;
  options.glyph_size = 0.05;
  EXPECT_DOUBLE_EQ(mapScene(map, options).glyph_size, 0.05);
  options.glyph_size = -1;
  EXPECT_TRUE(throwsError([&] { mapScene(map, options); }, {"--glyph-size", "positive"}));
}

TEST(MapScene, HandPartsAreNamedByClusterAndLink) {
  const HandModel hand = testing::humanoidHand();
  TaskMapData map = testing::oneGraspMap(hand, Eigen::Vector3d(0, 0, 0.15));
  ClusteringResult c;
  c.labels = {0};
  ClusterSummary cs;
  cs.size = 1;
  cs.representative = 0;
  c.clusters = {cs};
  map.clustering = c;
  const ExportScene s = mapScene(map, {}, &hand);
  ASSERT_FALSE(s.parts.empty());
  for (const ScenePart& part : s.parts) {
    EXPECT_EQ(part.name.rfind("cluster0_", 0), 0u) << part.name;
    EXPECT_FALSE(part.mesh.faces.empty());
  }
}

}  // namespace
}  // namespace taskmap
