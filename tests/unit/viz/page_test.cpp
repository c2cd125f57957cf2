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
}

}  // namespace
}  // namespace taskmap
