// The pages of taskmap::viz as text: self-contained (no fetched resource), three.js and its
// licence inlined, the data block complete and parseable, errors for inconsistent input.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "error_matchers.hpp"
#include "synthetic_map.hpp"
#include "taskmap/viz/hand_page.hpp"
#include "taskmap/viz/map_page.hpp"
#include "taskmap/viz/reach_page.hpp"
#include "viz_fixtures.hpp"

namespace taskmap {
namespace {

void expectSelfContained(const std::string& html) {
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_NE(html.find("Permission is hereby granted"), std::string::npos);  // three.js licence
  EXPECT_NE(html.find("REVISION"), std::string::npos);                      // three.js itself
  EXPECT_NE(html.find("ConvexBufferGeometry"), std::string::npos);
  EXPECT_NE(html.find("OrbitControls"), std::string::npos);
  EXPECT_EQ(html.find("<script src"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_NE(html.find("id=\"tm-error\""), std::string::npos);
}

TEST(MapPage, SyntheticMapWithoutHandHasEveryGraspAndCluster) {
  ASSERT_TRUE(viewerAvailable());
  const TaskMapData map = testing::syntheticMap(30);
  MapPageInput in;
  in.map = &map;
  const std::string html = mapPageHtml(in);
  expectSelfContained(html);
  const nlohmann::json d = testing::pageData(html);
  EXPECT_EQ(d["kind"], "map");
  EXPECT_EQ(d["grasps"]["n"], 30);
  EXPECT_EQ(d["grasps"]["pose"].size(), 30u * 7);
  EXPECT_EQ(d["grasps"]["cluster"].size(), 30u);
  EXPECT_EQ(d["clusters"].size(), 3u);
  EXPECT_EQ(d["clusters"][1]["rep"], map.clustering->clusters[1].representative);
  EXPECT_TRUE(d["hand"].is_null());
  EXPECT_TRUE(d["hold"].is_null());
  EXPECT_NEAR(d["grasps"]["pose"][7 * 4 + 1].get<double>(), map.grasps.pose(4, 1), 1e-5);
}

TEST(MapPage, HandModelIsInTheData) {
  const HandModel hand = testing::humanoidHand();
  const TaskMapData map = testing::oneGraspMap(hand, Eigen::Vector3d(0.12, 0, 0));
  MapPageInput in;
  in.map = &map;
  in.hand = &hand;
  const nlohmann::json d = testing::pageData(mapPageHtml(in));
  ASSERT_FALSE(d["hand"].is_null());
  EXPECT_EQ(d["hand"]["links"].size(), hand.links().size());
  EXPECT_EQ(d["hand"]["joints"].size(), hand.joints().size());
  EXPECT_EQ(d["hand"]["joint_names"], hand.jointNames());
  EXPECT_TRUE(d["hold"].is_null());
  EXPECT_EQ(d["grasps"]["cl"][0], hand.palmLink());
  EXPECT_TRUE(d["grasps"]["cluster"].is_null());
}

TEST(MapPage, HoldLabelsFromThePhysicsTest) {
  TaskMapData map = testing::syntheticMap(3);
  MapValidation v;
  v.hold = {1, 0, MapValidation::kNotTested};
  v.status = {0, 3, MapValidation::kNotTested};
  v.translation = {0.001, 0.02, -1};
  v.rotation = {0.01, 0.2, -1};
  v.direction = {-1, 2, -1};
  v.engine = "MuJoCo 2.2.2";
  map.validation = v;
  MapPageInput in;
  in.map = &map;
  const nlohmann::json d = testing::pageData(mapPageHtml(in));
  EXPECT_EQ(d["hold"]["labels"], nlohmann::json({"holds", "slipped", "not tested"}));
  EXPECT_EQ(d["hold"]["translation"][1], 0.02);
  EXPECT_EQ(d["hold"]["engine"], "MuJoCo 2.2.2");
}

TEST(MapPage, InconsistentInputIsRefused) {
  const HandModel hand = testing::humanoidHand();
  const TaskMapData map = testing::syntheticMap(6);  // no joints: not the humanoid's
  MapPageInput in;
  in.map = &map;
  in.hand = &hand;
  EXPECT_TRUE(testing::throwsError([&] { mapPageHtml(in); }, {"other actuated joints"}));
  in.map = nullptr;
  EXPECT_TRUE(testing::throwsError([&] { mapPageHtml(in); }, {"no map"}));
  PageOptions bad;
  bad.ghost_limit = 0;
  EXPECT_TRUE(testing::throwsError([&] { bad.validate(); }, {"ghost_limit"}));
}

TEST(MapPage, ScriptEndInNamesCannotCloseTheDataBlock) {
  TaskMapData map = testing::syntheticMap(3);
  map.object.name = "</script><b>x";
  MapPageInput in;
  in.map = &map;
  const std::string html = mapPageHtml(in);
  EXPECT_EQ(testing::pageData(html)["object"]["name"], "</script><b>x");
  EXPECT_NE(html.find("&lt;/script&gt;&lt;b&gt;x"), std::string::npos);  // the title
}

TEST(MapPage, WrittenAtomically) {
  const TaskMapData map = testing::syntheticMap(5);
  MapPageInput in;
  in.map = &map;
  const std::string path = (std::filesystem::temp_directory_path() / "viz_page_test.html").string();
  writeMapPage(in, path);
  std::ifstream f(path);
  std::stringstream text;
  text << f.rdbuf();
  EXPECT_EQ(text.str(), mapPageHtml(in));
  std::filesystem::remove(path);
  EXPECT_TRUE(testing::throwsError([&] { writeMapPage(in, "/nonexistent/dir/p.html"); },
                                   {"/nonexistent/dir/p.html"}));
}

TEST(HandPage, OpenAndClosedConfigurations) {
  const HandModel hand = testing::humanoidHand();
  const std::string html = handPageHtml(hand);
  expectSelfContained(html);
  const nlohmann::json d = testing::pageData(html);
  EXPECT_EQ(d["kind"], "hand");
  ASSERT_EQ(d["hand"]["closed"].size(), hand.jointNames().size());
  for (const ClosingJoint& c : hand.closing())
    EXPECT_NEAR(d["hand"]["closed"][static_cast<std::size_t>(c.joint)].get<double>(), c.target,
                1e-6);
}

TEST(ReachPage, TrajectoryBodiesShapesAndCosts) {
  const TrajectoryRecord r = testing::smallTrajectory();
  const std::string html = reachPageHtml(r);
  expectSelfContained(html);
  const nlohmann::json d = testing::pageData(html);
  EXPECT_EQ(d["kind"], "reach");
  EXPECT_EQ(d["rows"], r.rows());
  EXPECT_EQ(d["bodies"]["poses"].size(), r.rows() * 7 * r.body_names.size());
  EXPECT_EQ(d["shapes"].size(), 3u);
  EXPECT_EQ(d["plan"]["cost_terms"], r.cost_terms);
  EXPECT_EQ(d["plan"]["quality_peak"], r.quality_peak);
}

/// The humanoid's grasp for the reach page tests: every joint 70 % of the way from the preshape
/// to its upper limit.
Eigen::VectorXd graspJoints(const HandModel& hand) {
  return hand.preshape() + 0.7 * (hand.upperLimits() - hand.preshape());
}

/// Link l's pose at stage k of the page's hand_motion (palm frame).
Eigen::Isometry3d pageLinkPose(const nlohmann::json& motion, std::size_t k, std::size_t l) {
  const std::size_t at = 7 * (k * motion["links"].get<std::size_t>() + l);
  Eigen::Matrix<double, 7, 1> v;
  for (int i = 0; i < 7; ++i) v[i] = motion["poses"][at + static_cast<std::size_t>(i)];
  return Pose::fromVector7(v).toIsometry();
}

/// The page's link poses at stage k equal HandModel::linkPoses(q) (to the page's rounding).
void expectLinkPoses(const nlohmann::json& motion, std::size_t k, const HandModel& hand,
                     const Eigen::VectorXd& q) {
  const std::vector<Eigen::Isometry3d> fk = hand.linkPoses(q);
  ASSERT_EQ(motion["links"].get<std::size_t>(), fk.size());
  for (std::size_t l = 0; l < fk.size(); ++l) {
    const Eigen::Isometry3d page = pageLinkPose(motion, k, l);
    EXPECT_LT((page.translation() - fk[l].translation()).norm(), 1e-6) << hand.links()[l].name;
    EXPECT_LT((page.linear() - fk[l].linear()).norm(), 1e-5) << hand.links()[l].name;
  }
}

TEST(ReachPage, TheMapsHandOpensAtTheStartAndEndsInTheGrasp) {
  const HandModel hand = testing::humanoidHand();
  const TrajectoryRecord r = testing::smallTrajectory();  // 11 steps, dt 0.01 s
  ReachPageInput in;
  in.trajectory = &r;
  in.hand = &hand;
  in.grasp_joints = graspJoints(hand);
  in.close_s = 0.05;  // the last 5 steps
  const nlohmann::json d = testing::pageData(reachPageHtml(in));
  ASSERT_FALSE(d["map_hand"].is_null());
  EXPECT_EQ(d["map_hand"]["links"].size(), hand.links().size());
  const nlohmann::json& m = d["hand_motion"];
  ASSERT_EQ(m["stage"].size(), r.rows());
  EXPECT_EQ(m["close_from"], 5);
  EXPECT_NEAR(m["close_s"].get<double>(), 0.05, 1e-9);
  const auto stage = m["stage"].get<std::vector<int>>();
  EXPECT_EQ(stage, (std::vector<int>{0, 0, 0, 0, 0, 0, 1, 2, 3, 4, 5}));
  ASSERT_EQ(m["poses"].size(), 6 * 7 * hand.links().size());
  expectLinkPoses(m, static_cast<std::size_t>(stage.front()), hand, hand.preshape());
  expectLinkPoses(m, static_cast<std::size_t>(stage.back()), hand, in.grasp_joints);
  // In between, every joint moves monotonically from the preshape to the grasp.
  const std::size_t j = 0;
  for (std::size_t k = 1; k < 6; ++k)
    EXPECT_GE(m["joints"][k][j].get<double>(), m["joints"][k - 1][j].get<double>());
  EXPECT_EQ(d["hand_note"], "");
}

TEST(ReachPage, ClosingLongerThanTheMovementTakesAllOfIt) {
  const HandModel hand = testing::humanoidHand();
  const ReachHandMotion m = reachHandMotion(hand, graspJoints(hand), 11, 0.01, 0.5);
  EXPECT_EQ(m.close_from, 0u);
  EXPECT_EQ(m.stage.back(), 10);
  EXPECT_TRUE(m.joints.front().isApprox(hand.preshape()));
  EXPECT_TRUE(m.joints.back().isApprox(graspJoints(hand)));
  // A single step shows the grasp.
  const ReachHandMotion one = reachHandMotion(hand, graspJoints(hand), 1, 0.01, 0.5);
  ASSERT_EQ(one.stage, std::vector<int>{0});
  EXPECT_TRUE(one.joints.front().isApprox(graspJoints(hand)));
}

TEST(ReachPage, WithoutTheHandThePageSaysWhy) {
  const TrajectoryRecord r = testing::smallTrajectory();
  nlohmann::json d = testing::pageData(reachPageHtml(r));
  EXPECT_TRUE(d["map_hand"].is_null());
  EXPECT_TRUE(d["hand_motion"].is_null());
  EXPECT_EQ(d["hand_note"], "no hand model given");
  ReachPageInput in;
  in.trajectory = &r;
  in.note = "the map's hand 'x' is nowhere";
  d = testing::pageData(reachPageHtml(in));
  EXPECT_EQ(d["hand_note"], in.note);
}

TEST(ReachPage, InconsistentInputIsRefused) {
  const HandModel hand = testing::humanoidHand();
  const TrajectoryRecord r = testing::smallTrajectory();
  ReachPageInput in;
  EXPECT_TRUE(testing::throwsError([&] { reachPageHtml(in); }, {"no trajectory"}));
  in.trajectory = &r;
  in.hand = &hand;
  in.grasp_joints = Eigen::VectorXd::Zero(2);
  EXPECT_TRUE(testing::throwsError([&] { reachPageHtml(in); }, {"2 joint values", "humanoid"}));
  in.grasp_joints = graspJoints(hand);
  in.close_s = 0.0;
  EXPECT_TRUE(testing::throwsError([&] { reachPageHtml(in); }, {"closing time"}));
}

}  // namespace
}  // namespace taskmap
