// The map's hand (`inspect --png`, `view`, `export`): found at the path the build recorded, by
// its SHA-256 among bundled hands, refused with a reason otherwise; its shapes posed by a grasp.
#include "taskmap/inspect/map_hand.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include <nlohmann/json.hpp>

#include "error_matchers.hpp"
#include "taskmap/inspect/hand_check.hpp"
#include "taskmap/mapstore/map_file.hpp"
#include "taskmap/meshes/object_model.hpp"
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

/// The small trajectory planned on the map saved at map_path, ending on its grasp 0.
TrajectoryRecord trajectoryOn(const std::string& map_path) {
  TrajectoryRecord r = testing::smallTrajectory();
  r.map_path = map_path;
  r.map_sha256 = sha256File(map_path);
  r.grasp_index = 0;
  return r;
}

TEST(TrajectoryHand, FromTheRecordedGraspByShaAmongBundledHands) {
  const HandModel hand = testing::humanoidHand();
  TrajectoryRecord r = testing::smallTrajectory();  // its map file is nowhere: not needed
  r.map_hand = hand.name();
  r.map_hand_sha256 = hand.urdfSha256();
  r.map_hand_path = "/elsewhere/humanoid.urdf";
  r.grasp_joint_names = hand.jointNames();
  r.grasp_joints = Eigen::VectorXd::Constant(hand.preshape().size(), 0.3);
  MapHandOptions options;
  options.hands_dir = TASKMAP_HANDS_DIR;
  const TrajectoryHand found = findTrajectoryHand(r, options);
  ASSERT_EQ(found.found.status, MapHandResult::Status::kLoaded) << found.found.message;
  EXPECT_EQ(found.found.hand->urdfSha256(), hand.urdfSha256());
  EXPECT_EQ(found.grasp_joints, r.grasp_joints);
  // Not among the hands searched: the reason names the hand and the recorded path.
  options.hands_dir.clear();
  const TrajectoryHand missing = findTrajectoryHand(r, options);
  EXPECT_EQ(missing.found.status, MapHandResult::Status::kNotFound);
  EXPECT_NE(missing.found.message.find("/elsewhere/humanoid.urdf"), std::string::npos);
  EXPECT_EQ(missing.grasp_joints.size(), 0);
  // --hand: another hand's joints do not fit the grasp.
  options.hand = bundled("barrett");
  EXPECT_EQ(findTrajectoryHand(r, options).found.status, MapHandResult::Status::kOtherJoints);
}

TEST(TrajectoryHand, AnOlderFileTakesTheGraspFromItsUnchangedMap) {
  const HandModel hand = testing::humanoidHand();
  TaskMapData map = testing::oneGraspMap(hand, Eigen::Vector3d(0, 0, 0.15));
  map.grasps.joints.row(0).setConstant(0.2);
  map.sampling.params_json = nlohmann::json{{"hand", bundled("humanoid")}}.dump();
  const std::string path =
      ::testing::TempDir() + "trajectory_hand_" + std::to_string(::getpid()) + ".h5";
  writeMap(path, map);
  TrajectoryRecord r = trajectoryOn(path);  // no /plan/grasp
  const TrajectoryHand found = findTrajectoryHand(r, MapHandOptions{});
  ASSERT_EQ(found.found.status, MapHandResult::Status::kLoaded) << found.found.message;
  EXPECT_EQ(found.grasp_joints, map.grasps.joints.row(0).transpose());
  // The map changed since the plan, or is gone: no hand, and the reason says what to do.
  r.map_sha256 = std::string(64, '0');
  TrajectoryHand changed = findTrajectoryHand(r, MapHandOptions{});
  EXPECT_EQ(changed.found.status, MapHandResult::Status::kNotFound);
  EXPECT_NE(changed.found.message.find("has changed since the plan"), std::string::npos);
  EXPECT_NE(changed.found.message.find("taskmap reach --map"), std::string::npos);
  std::filesystem::remove(path);
  changed = findTrajectoryHand(r, MapHandOptions{});
  EXPECT_NE(changed.found.message.find("is not there"), std::string::npos);
}

}  // namespace
}  // namespace taskmap
