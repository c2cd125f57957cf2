// `taskmap reach`: a reachable side grasp (text, JSON, picture), failures with exit status 1,
// bad input with messages naming the option or file.
#include <cairo.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_run.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;
const std::string kSideGrasp = "--target \"-0.07 0 0.02 0.7071068 0 0.7071068 0\"";

std::string tempPath(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("reach_cli_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return (dir / name).string();
}

TEST(ReachCli, ReachesASideGraspAndReportsJson) {
  const testing::CliRun r = testing::runTaskmap("reach " + kSideGrasp + " --json");
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["status"], "reached");
  EXPECT_EQ(j["steps"], 300);
  EXPECT_LT(j["position_error_m"].get<double>(), 1e-3);
  EXPECT_GT(j["min_clearance_m"].get<double>(), 0.0);
  EXPECT_GE(j["joint_limit_margin"].get<double>(), 0.0);
  EXPECT_GT(j["collision_pairs"].get<int>(), 20);
  EXPECT_EQ(j["q_final"].size(), 7u);
}

TEST(ReachCli, DrawsThreeViews) {
  const std::string png = tempPath("reach.png");
  const testing::CliRun r = testing::runTaskmap("reach " + kSideGrasp + " --png " + png);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("min clearance"), std::string::npos) << r.out;
  cairo_surface_t* s = cairo_image_surface_create_from_png(png.c_str());
  ASSERT_EQ(cairo_surface_status(s), CAIRO_STATUS_SUCCESS);
  EXPECT_EQ(cairo_image_surface_get_width(s), 1800);
  // Some pixels are neither white nor grey: the robot is drawn.
  cairo_surface_flush(s);
  const unsigned char* data = cairo_image_surface_get_data(s);
  const int stride = cairo_image_surface_get_stride(s);
  int coloured = 0;
  for (int y = 0; y < cairo_image_surface_get_height(s); y += 4)
    for (int x = 0; x < 1800; x += 4) {
      const unsigned char* p = data + y * stride + 4 * x;  // B G R A
      coloured += std::abs(int(p[2]) - int(p[0])) > 60;
    }
  EXPECT_GT(coloured, 1000);
  cairo_surface_destroy(s);
}

TEST(ReachCli, ObstacleSceneAndFailureExitStatus) {
  // The object where the hand must go, far from any reachable pose: not reached, status 1.
  const std::string scene = tempPath("scene.json");
  std::ofstream(scene) << R"({"bodies": [
    {"name": "table", "pose": [0.3, 0, -0.02, 1, 0, 0, 0], "shapes": [{"type": "box", "size": [1.2, 1.6, 0.04]}]},
    {"name": "jar", "pose": [1.5, 0, 0.1, 1, 0, 0, 0], "shapes": [{"type": "capsule", "p0": [0, 0, -0.06], "p1": [0, 0, 0.06], "radius": 0.04}]}],
    "object": "jar"})";
  const testing::CliRun r =
      testing::runTaskmap("reach " + kSideGrasp + " --scene " + scene + " --json");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("not_reached"), std::string::npos) << r.out;
}

// Another hand than the humanoid: the mount comes from its sidecar, or reach asks for it
// (issue 30: the humanoid's adapter was used silently).
TEST(ReachCli, MountFromTheHandSidecarOrAskedFor) {
  const std::string franka =
      std::string(TEST_DATA_DIR) + "/real/hands/franka_hand/franka_hand.urdf";
  testing::CliRun r = testing::runTaskmap("reach " + kSideGrasp + " --hand " + franka);
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_EQ(r.out.find("\"status\""), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("does not say how it is mounted"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--mount"), std::string::npos) << r.out;
  // With --mount (Franka's flange: the hand turned -45 degrees about z) it runs.
  r = testing::runTaskmap("reach " + kSideGrasp + " --hand " + franka +
                          " --mount \"0 0 0 0.9238795 0 0 -0.3826834\" --json");
  EXPECT_NE(r.out.find("\"status\""), std::string::npos) << r.out;
  // The bundled panda carries its mount in its sidecar.
  r = testing::runTaskmap("reach " + kSideGrasp + " --hand panda --json");
  EXPECT_NE(r.out.find("\"status\""), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("mounted"), std::string::npos) << r.out;
}

// A negative clearance is flagged in words in the text report and the JSON.
TEST(ReachCli, NegativeClearanceIsFlaggedInWords) {
  const std::string into_table = "--target \"0.3 0 0 0 1 0 0\" --frame world";
  testing::CliRun r = testing::runTaskmap("reach " + into_table);
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("NEGATIVE clearance"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("not collision-free"), std::string::npos) << r.out;
  r = testing::runTaskmap("reach " + into_table + " --json");
  // The JSON object, without the status line the tool adds on stderr.
  const nlohmann::json j =
      nlohmann::json::parse(r.out.substr(0, r.out.rfind('}') + 1), nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << r.out;
  ASSERT_LT(j["min_clearance_m"].get<double>(), 0.0) << r.out;
  EXPECT_NE(j["warning"].get<std::string>().find("NEGATIVE clearance"), std::string::npos);
  // A clear reach carries no warning.
  r = testing::runTaskmap("reach " + kSideGrasp);
  EXPECT_EQ(r.out.find("NEGATIVE"), std::string::npos) << r.out;
}

TEST(ReachCli, BadInputNamesTheProblem) {
  testing::CliRun r = testing::runTaskmap("reach --target \"1 2 3\"");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find("--target needs 7 numbers"), std::string::npos) << r.out;
  r = testing::runTaskmap("reach " + kSideGrasp + " --scene /nonexistent/scene.json");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find("/nonexistent/scene.json"), std::string::npos) << r.out;
  const std::string bad = tempPath("bad_scene.json");
  std::ofstream(bad) << R"({"bodies": [{"name": "t", "shapes": [{"type": "cone"}]}]})";
  r = testing::runTaskmap("reach " + kSideGrasp + " --scene " + bad);
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find("unknown shape type \"cone\""), std::string::npos) << r.out;
  r = testing::runTaskmap("reach " + kSideGrasp + " --robot /nonexistent.urdf");
  EXPECT_NE(r.out.find("neither 'panda' nor an existing URDF"), std::string::npos) << r.out;
  r = testing::runTaskmap("reach " + kSideGrasp + " --start \"0 0 0\"");
  EXPECT_NE(r.out.find("--start needs 7 numbers"), std::string::npos) << r.out;
  r = testing::runTaskmap("reach " + kSideGrasp + " --dt 0");
  EXPECT_NE(r.out.find("dt"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace taskmap
