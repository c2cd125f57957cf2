// taskmap view (maps and trajectories) and hand-info --html: pages written with the map's own
// hand, the data block complete, and clear errors for bad input.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli_run.hpp"
#include "synthetic_map.hpp"
#include "taskmap/mapstore/map_file.hpp"
#include "viz_fixtures.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

std::string tempPath(const std::string& name) {
  return (fs::temp_directory_path() / ("view_cli_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

nlohmann::json dataOf(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return testing::pageData(s.str());
}

TEST(ViewCli, ReferenceMapWithItsHand) {
  const std::string out = tempPath("basket.html");
  const testing::CliRun r = testing::runTaskmap("view " + std::string(TASKMAP_SOURCE_DIR) +
                                                "/meshes/maps/basket_humanoid.h5 -o " + out);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("40 grasps, hand humanoid"), std::string::npos) << r.out;
  const nlohmann::json d = dataOf(out);
  EXPECT_EQ(d["grasps"]["n"], 40);
  EXPECT_FALSE(d["hand"].is_null());
  EXPECT_EQ(d["clusters"].size(), 3u);
  fs::remove(out);
}

TEST(ViewCli, TrajectoryFile) {
  const std::string traj = tempPath("t.h5"), out = tempPath("t.html");
  writeTrajectory(traj, testing::smallTrajectory());
  const testing::CliRun r = testing::runTaskmap("view " + traj + " -o " + out);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("trajectory, 11 steps, hand as primitives"), std::string::npos) << r.out;
  // Its map (cube.h5) is not there and the file records no grasp: the page says so.
  EXPECT_NE(r.out.find("is not there"), std::string::npos) << r.out;
  EXPECT_EQ(dataOf(out)["kind"], "reach");
  fs::remove(traj);
  fs::remove(out);
}

TEST(ViewCli, TrajectoryWithItsGraspClosesTheMapsHand) {
  const std::string traj = tempPath("g.h5"), out = tempPath("g.html");
  const HandModel hand = testing::humanoidHand();
  TrajectoryRecord r = testing::smallTrajectory();
  r.grasp_index = 7;
  r.map_hand = hand.name();
  r.map_hand_sha256 = hand.urdfSha256();
  r.map_hand_path = "/elsewhere/humanoid.urdf";  // found among the bundled hands by SHA-256
  r.grasp_joint_names = hand.jointNames();
  r.grasp_joints = hand.preshape() + 0.5 * (hand.upperLimits() - hand.preshape());
  writeTrajectory(traj, r);
  testing::CliRun run = testing::runTaskmap("view " + traj + " -o " + out);
  ASSERT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("hand " + hand.name() + " closing to grasp 7"), std::string::npos)
      << run.out;
  nlohmann::json d = dataOf(out);
  EXPECT_EQ(d["map_hand"]["name"], hand.name());
  EXPECT_EQ(d["hand_motion"]["stage"].size(), r.rows());
  // --hand with other joints: the planner's primitives, a warning, and the reason in the page.
  run = testing::runTaskmap("view " + traj + " -o " + out + " --hand barrett");
  ASSERT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("warning: drawing the hand as the planner's collision primitives"),
            std::string::npos)
      << run.out;
  d = dataOf(out);
  EXPECT_TRUE(d["map_hand"].is_null());
  EXPECT_NE(d["hand_note"].get<std::string>().find("other actuated joints"), std::string::npos);
  fs::remove(traj);
  fs::remove(out);
}

TEST(ViewCli, HandInfoHtml) {
  const std::string out = tempPath("hand.html");
  const testing::CliRun r = testing::runTaskmap("hand-info panda --html " + out);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(dataOf(out)["hand"]["joint_names"].size(), 2u);
  fs::remove(out);
}

TEST(ViewCli, MapWhoseHandIsNotFoundShowsPalmsOnly) {
  const std::string map = tempPath("synthetic.h5"), out = tempPath("synthetic.html");
  writeMap(map, testing::syntheticMap(12));
  const testing::CliRun r = testing::runTaskmap("view " + map + " -o " + out);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("warning: drawing palms only"), std::string::npos) << r.out;
  EXPECT_TRUE(dataOf(out)["hand"].is_null());
  fs::remove(map);
  fs::remove(out);
}

TEST(ViewCli, BadInputIsRefused) {
  testing::CliRun r = testing::runTaskmap("view /nonexistent/m.h5");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find("does not exist"), std::string::npos) << r.out;
  const std::string junk = tempPath("junk.h5");
  std::ofstream(junk) << "not a map";
  r = testing::runTaskmap("view " + junk + " -o " + tempPath("j.html"));
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find(junk), std::string::npos) << r.out;
  fs::remove(junk);
}

}  // namespace
}  // namespace taskmap
