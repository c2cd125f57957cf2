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
  EXPECT_NE(r.out.find("182 grasps, hand humanoid"), std::string::npos) << r.out;
  const nlohmann::json d = dataOf(out);
  EXPECT_EQ(d["grasps"]["n"], 182);
  EXPECT_FALSE(d["hand"].is_null());
  EXPECT_EQ(d["clusters"].size(), 8u);
  fs::remove(out);
}

TEST(ViewCli, TrajectoryFile) {
  const std::string traj = tempPath("t.h5"), out = tempPath("t.html");
  writeTrajectory(traj, testing::smallTrajectory());
  const testing::CliRun r = testing::runTaskmap("view " + traj + " -o " + out);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("trajectory, 11 steps"), std::string::npos) << r.out;
  EXPECT_EQ(dataOf(out)["kind"], "reach");
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
