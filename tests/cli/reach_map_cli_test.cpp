// `taskmap reach --map`: bad input refused with messages naming the option or file; with
// TASKMAP_REACH_MAP_SLOW (label slow) the paper's scene: a basket map built with the mounted
// hand, three basket positions, the acceptance measures.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <set>

#include <nlohmann/json.hpp>

#include "cli_run.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

[[maybe_unused]] std::string tempPath(const std::string& name) {
  const fs::path dir =
      fs::path(::testing::TempDir()) / ("reach_map_cli_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return (dir / name).string();
}

[[maybe_unused]] nlohmann::json parseJson(const std::string& out) {
  const auto a = out.find('{'), b = out.rfind('}');
  if (a == std::string::npos || b == std::string::npos) return nullptr;
  return nlohmann::json::parse(out.substr(a, b - a + 1));
}

const std::string kScenes = std::string(TASKMAP_SOURCE_DIR) + "/reaching/scenes/";

#ifndef TASKMAP_REACH_MAP_SLOW
TEST(ReachMapCli, RefusesBadInputWithMessages) {
  testing::CliRun r =
      testing::runTaskmap("reach --map /nonexistent/m.h5 --object-pose \"0.5 0 0 0\"");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find("/nonexistent/m.h5"), std::string::npos) << r.out;
  r = testing::runTaskmap("reach --map /nonexistent/m.h5");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find("--object-pose"), std::string::npos) << r.out;
  r = testing::runTaskmap("reach --map /nonexistent/m.h5 --object-pose \"0.5 0 0\"");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find("x y z yaw"), std::string::npos) << r.out;
  r = testing::runTaskmap(
      "reach --map /nonexistent/m.h5 --object-pose \"0.5 0 0 0\" --target \"0 0 0 1 0 0 0\"");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find("exclude"), std::string::npos) << r.out;
  r = testing::runTaskmap("reach --map no_such_map --object-pose \"0.5 0 0 0\"");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find("bundled map"), std::string::npos) << r.out;
  r = testing::runTaskmap(
      "reach --map basket_humanoid --object-pose \"0.5 0 0 0\" --descent newton");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find("--descent"), std::string::npos) << r.out;
}

/// The bundled reference map by name; the final grasp re-simulated (or not) in the JSON.
TEST(ReachMapCli, BundledMapAndResimulatedGrasp) {
  const std::string base = "reach --map basket_humanoid --scene " + kScenes +
                           "basket_reference.json --object-pose \"0.5 0 0 1.5708\" "
                           "--iterations 2 --json";
  testing::CliRun r = testing::runTaskmap(base);
  ASSERT_EQ(r.code, 0) << r.out;
  nlohmann::json j = parseJson(r.out);
  ASSERT_TRUE(j.contains("resimulated")) << r.out;
  const nlohmann::json& s = j["resimulated"];
  EXPECT_TRUE(s["outcome"].is_string());
  EXPECT_EQ(s["force_closure"].get<bool>(), s["epsilon"].get<double>() > 0.0);
  EXPECT_GE(s["contacts"].get<int>(), 0);
  r = testing::runTaskmap(base + " --no-resimulate");
  ASSERT_EQ(r.code, 0) << r.out;
  j = parseJson(r.out);
  EXPECT_FALSE(j.contains("resimulated"));
}
#else
/// The reference map of the mounted (humanoid) hand on the basket, built once.
const std::string& basketMap() {
  static const std::string path = [] {
    const std::string p = tempPath("basket_humanoid.h5");
    const testing::CliRun r = testing::runTaskmap(
        "build --object " + std::string(TASKMAP_SOURCE_DIR) +
        "/meshes/objects/basket.obj --hand humanoid --valid 300 --seed 1 --threads 1 -o " + p);
    EXPECT_EQ(r.code, 0) << r.out;
    return p;
  }();
  return path;
}

TEST(ReachMapCliSlow, ThreeBasketPositionsMeetTheAcceptanceMeasures) {
  const std::vector<std::pair<std::string, std::string> > cases = {
      {"reference", "0.5 0 0 1.5708"},
      {"forward", "0.62 0 0 1.5708"},
      {"sideways", "0.5 0.3 0 1.5708"}};
  std::set<int> clusters;
  const std::string png = tempPath("reach_map.png");
  for (const auto& [name, pose] : cases) {
    const testing::CliRun r = testing::runTaskmap(
        "reach --map " + basketMap() + " --scene " + kScenes + "basket_" + name +
        ".json --object-pose \"" + pose + "\" --all-clusters --json --png " + png);
    ASSERT_EQ(r.code, 0) << name << "\n" << r.out;
    const nlohmann::json j = parseJson(r.out);
    ASSERT_FALSE(j.is_null()) << r.out;
    std::cout << name << ": cluster " << j["cluster"] << ", grasp " << j["grasp_index"]
              << ", iterations " << j["iterations"] << ", to manifold "
              << j["iterations_to_manifold"] << ", to quality " << j["iterations_to_quality"]
              << ", clearance " << j["min_clearance_m"] << " m, " << j["ms_per_iteration"]
              << " ms/iteration, " << j["ms_per_plan"] << " ms/plan\n";
    EXPECT_EQ(j["status"], "planned");
    EXPECT_TRUE(j["collision_free"].get<bool>());
    EXPECT_GE(j["min_clearance_m"].get<double>(), 0.0);
    EXPECT_GE(j["joint_limit_margin_rad"].get<double>(), 0.0);
    EXPECT_LE(j["velocity_ratio"].get<double>(), 1.0 + 1e-9);
    EXPECT_GE(j["iterations_to_manifold"].get<int>(), 0);
    EXPECT_LE(j["iterations_to_manifold"].get<int>(), 15);
    EXPECT_EQ(j["cost_history"].size(), j["iterations"].get<std::size_t>() + 1);
    const auto& h = j["cost_history"];
    EXPECT_LT(h.back()["total"].get<double>(), h.front()["total"].get<double>());
    clusters.insert(j["cluster"].get<int>());
  }
  EXPECT_GE(clusters.size(), 2u);  // the chosen grasp depends on where the basket stands
  EXPECT_TRUE(fs::exists(png));    // Fig. 1.17 snapshots
  EXPECT_TRUE(fs::exists(tempPath("reach_map_costs.png")));  // Fig. 1.16 cost terms
}
#endif

}  // namespace
}  // namespace taskmap
