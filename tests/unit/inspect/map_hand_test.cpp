// The map's hand (`inspect --png`, `view`, `export`): found at the path the build recorded, by
// its SHA-256 among bundled hands, refused with a reason otherwise; its shapes posed by a grasp.
#include "taskmap/inspect/map_hand.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "error_matchers.hpp"
#include "taskmap/inspect/hand_check.hpp"
#include "viz_fixtures.hpp"

namespace taskmap {
namespace {

using testing::throwsError;

std::string bundled(const std::string& name) {
  return std::string(TASKMAP_HANDS_DIR) + "/" + name + "/" + name + ".urdf";
}

TEST(MapHand, RecordedPathThenBundledHandsBySha) {
  const HandModel hand = testing::humanoidHand();
  TaskMapData map = testing::oneGraspMap(hand, Eigen::Vector3d(0, 0, 0.15));
  map.sampling.params_json = nlohmann::json{{"hand", bundled("humanoid")}}.dump();
  EXPECT_EQ(findMapHandUrdf(map, ""), bundled("humanoid"));
  // Recorded elsewhere: found among the bundled hands by content.
  map.sampling.params_json = nlohmann::json{{"hand", "/elsewhere/humanoid.urdf"}}.dump();
  EXPECT_EQ(findMapHandUrdf(map, TASKMAP_HANDS_DIR), bundled("humanoid"));
  MapHandOptions options;
  options.hands_dir = TASKMAP_HANDS_DIR;
  const MapHandResult found = findMapHand(map, options);
  ASSERT_EQ(found.status, MapHandResult::Status::kLoaded) << found.message;
  EXPECT_EQ(found.hand->urdfSha256(), hand.urdfSha256());
  // Nowhere: the reason names the hand and what was tried.
  options.hands_dir.clear();
  const MapHandResult missing = findMapHand(map, options);
  EXPECT_EQ(missing.status, MapHandResult::Status::kNotFound);
  EXPECT_FALSE(missing.hand.has_value());
  EXPECT_NE(missing.message.find("the map's hand '" + hand.name() + "'"), std::string::npos);
  EXPECT_NE(missing.message.find("/elsewhere/humanoid.urdf"), std::string::npos);
  EXPECT_TRUE(throwsError([&] { findMapHandUrdf(map, ""); }, {hand.name(), "recorded path"}));
}

TEST(MapHand, AnotherHandIsRefusedAndABadPathThrows) {
  const TaskMapData map = testing::oneGraspMap(testing::humanoidHand(), {0, 0, 0.15});
  MapHandOptions options;
  options.hand = bundled("barrett");
  const MapHandResult other = findMapHand(map, options);
  EXPECT_EQ(other.status, MapHandResult::Status::kOtherJoints);
  EXPECT_NE(other.message.find("other actuated joints"), std::string::npos);
  options.hand = "/nonexistent/h.urdf";
  EXPECT_TRUE(throwsError([&] { findMapHand(map, options); }, {"/nonexistent/h.urdf"}));
}

TEST(MapHand, PosedShapesAreTheLinkPosesTimesTheGraspPose) {
  const HandModel hand = testing::humanoidHand();
  const TaskMapData map = testing::oneGraspMap(hand, Eigen::Vector3d(0, 0, 0.15));
  const GraspPosture p = graspPosture(map, 0);
  EXPECT_TRUE(p.palm_pose.isApprox(map.grasps.poseAt(0).toIsometry()));
  const auto shapes = posedShapePoints(hand, p);
  ASSERT_FALSE(shapes.empty());
  // Oracle: the first shape's first point through the link's forward kinematics by hand.
  const std::vector<Eigen::Isometry3d> links = hand.linkPoses(p.joints);
  const auto& first = shapes.front();
  const CollisionShape& s = hand.links()[static_cast<std::size_t>(first.link)].shapes.front();
  const Eigen::Vector3d expected =
      p.palm_pose * links[static_cast<std::size_t>(first.link)] * s.origin * shapePoints(s).front();
  EXPECT_TRUE(first.points.front().isApprox(expected, 1e-12));
  EXPECT_TRUE(throwsError([&] { graspPosture(map, 1); }, {"grasp 1 is out of range", "1 grasps"}));
}

}  // namespace
}  // namespace taskmap
