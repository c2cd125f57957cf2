// `taskmap reach --map`: bad input refused with messages naming the option or file; with
// TASKMAP_REACH_MAP_SLOW (label slow) the paper's scene: a basket map built with the mounted
// hand, three basket positions, the acceptance measures.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <future>
#include <iostream>
#include <numeric>
#include <set>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_run.hpp"
#include "taskmap/mapstore/map_file.hpp"

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
const std::string kMap = std::string(TASKMAP_SOURCE_DIR) + "/meshes/maps/basket_humanoid.h5";

/// The checked-in map (meshes/maps/README.md) rebuilt with its recorded commands (build, then
/// cluster --min-size 6, the clustering the reaching measurements were made with) reproduces it.
TEST(ReachMapCliSlow, ReferenceMapRebuildReproducesTheCheckedInFile) {
  const std::string out = tempPath("basket_rebuilt.h5");
  const testing::CliRun r = testing::runShell(
      std::string("cd ") + TASKMAP_SOURCE_DIR + " && " + TASKMAP_BINARY_DIR +
      "/bin/taskmap build --object meshes/objects/basket.obj --hand "
      "meshes/hands/humanoid/humanoid.urdf --valid 300 --seed 1 --threads 1 -q -o " +
      out + " && " + TASKMAP_BINARY_DIR + "/bin/taskmap cluster --min-size 6 " + out);
  ASSERT_EQ(r.code, 0) << r.out;
  const TaskMapData a = readMap(kMap), b = readMap(out);
  ASSERT_EQ(a.grasps.size(), b.grasps.size());
  EXPECT_TRUE(a.grasps.pose == b.grasps.pose);
  EXPECT_EQ(a.grasps.epsilon, b.grasps.epsilon);
  EXPECT_EQ(a.sampling.trials, b.sampling.trials);
  ASSERT_TRUE(a.clustering && b.clustering);
  EXPECT_EQ(a.clustering->labels, b.clustering->labels);
  EXPECT_EQ(a.sampling.params_json, b.sampling.params_json);
}

nlohmann::json reach(const std::string& scene, const std::string& pose, const std::string& extra) {
  const testing::CliRun r =
      testing::runTaskmap("reach --map basket_humanoid --scene " + kScenes + scene +
                          " --object-pose \"" + pose + "\" --json " + extra);
  EXPECT_EQ(r.code, 0) << r.out;
  nlohmann::json j = parseJson(r.out);
  EXPECT_FALSE(j.is_null()) << r.out;
  return j;
}

TEST(ReachMapCliSlow, ThreeBasketPositionsMeetTheAcceptanceMeasures) {
  const std::vector<std::pair<std::string, std::string> > cases = {
      {"reference", "0.5 0 0 1.5708"},
      {"forward", "0.62 0 0 1.5708"},
      {"sideways", "0.5 0.3 0 1.5708"}};
  std::set<int> clusters;
  const std::string png = tempPath("reach_map.png");
  for (const auto& [name, pose] : cases) {
    const nlohmann::json j = reach("basket_" + name + ".json", pose, "--all-clusters --png " + png);
    ASSERT_TRUE(j.contains("resimulated")) << j.dump();
    const nlohmann::json& s = j["resimulated"];
    std::cout << name << ": cluster " << j["cluster"] << ", grasp " << j["grasp_index"]
              << ", iterations " << j["iterations"] << ", to manifold "
              << j["iterations_to_manifold"] << ", to quality " << j["iterations_to_quality"]
              << ", clearance " << j["min_clearance_m"] << " m, " << j["ms_per_iteration"]
              << " ms/iteration, " << j["ms_per_plan"] << " ms/plan, re-simulated " << s["outcome"]
              << " epsilon " << s["epsilon"] << "\n";
    EXPECT_EQ(j["status"], "planned");
    EXPECT_TRUE(j["collision_free"].get<bool>());
    EXPECT_GE(j["min_clearance_m"].get<double>(), 0.0);
    EXPECT_GE(j["joint_limit_margin_rad"].get<double>(), 0.0);
    EXPECT_LE(j["velocity_ratio"].get<double>(), 1.0 + 1e-9);
    EXPECT_GE(j["iterations_to_manifold"].get<int>(), 0);
    EXPECT_LE(j["iterations_to_manifold"].get<int>(), 15);
    EXPECT_GE(j["iterations_to_quality"].get<int>(), 0);
    EXPECT_LE(j["iterations_to_quality"].get<int>(), 25);
    EXPECT_TRUE(s["force_closure"].get<bool>()) << name << ": " << s.dump();
    EXPECT_EQ(j["cost_history"].size(), j["iterations"].get<std::size_t>() + 1);
    const auto& h = j["cost_history"];
    EXPECT_LT(h.back()["total"].get<double>(), h.front()["total"].get<double>());
    clusters.insert(j["cluster"].get<int>());
  }
  EXPECT_GE(clusters.size(), 2u);  // the chosen grasp depends on where the basket stands
  EXPECT_TRUE(fs::exists(png));    // Fig. 1.17 snapshots
  EXPECT_TRUE(fs::exists(tempPath("reach_map_costs.png")));  // Fig. 1.16 cost terms
}

/// Basket position (i, j) of the 5 x 5 grid: x 0.42..0.62 m, y -0.2..0.2 m, yaw 90 degrees
/// + 15 ((i + j) mod 5 - 2), i.e. 60..120 degrees spread over the grid.
std::string gridPose(int i, int j) {
  const double yaw = (90.0 + 15.0 * ((i + j) % 5 - 2)) * M_PI / 180.0;
  return std::to_string(0.42 + 0.05 * i) + " " + std::to_string(-0.2 + 0.1 * j) + " 0 " +
         std::to_string(yaw);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

/// The g_q comparison (docs/REACHING.md "Quality on and off"): same weights, quality on and off.
TEST(ReachMapCliSlow, QualityTermRaisesTheResimulatedEpsilonOnTheGrid) {
  std::vector<std::future<nlohmann::json> > runs;
  for (int k = 0; k < 50; ++k) {
    const int cell = k / 2, on = 1 - k % 2;
    runs.push_back(std::async(std::launch::deferred, [cell, on] {
      return reach("basket_reference.json", gridPose(cell / 5, cell % 5),
                   "--quality-weight " + std::to_string(on));
    }));
  }
  // Two CLI processes at a time (their results do not depend on it).
  std::vector<nlohmann::json> result(runs.size());
  for (std::size_t k = 0; k < runs.size(); k += 2) {
    auto second = std::async(std::launch::async, [&runs, k] { return runs[k + 1].get(); });
    result[k] = runs[k].get();
    result[k + 1] = second.get();
  }
  std::vector<double> with, without;
  int planned_with = 0, planned_without = 0, wins = 0, losses = 0, closure_with = 0;
  for (std::size_t k = 0; k < result.size(); k += 2) {
    const nlohmann::json &a = result[k], &b = result[k + 1];
    ASSERT_TRUE(a.contains("resimulated") && b.contains("resimulated")) << a.dump() << b.dump();
    planned_with += a["status"] == "planned";
    planned_without += b["status"] == "planned";
    const double ea = a["resimulated"]["epsilon"].get<double>();
    const double eb = b["resimulated"]["epsilon"].get<double>();
    closure_with += a["resimulated"]["force_closure"].get<bool>();
    with.push_back(ea);
    without.push_back(eb);
    wins += ea > eb;
    losses += ea < eb;
    std::cout << "cell " << k / 2 << " ("
              << gridPose(static_cast<int>(k / 2) / 5, static_cast<int>(k / 2) % 5)
              << "): g_q on grasp " << a["grasp_index"] << " epsilon " << ea << ", off grasp "
              << b["grasp_index"] << " epsilon " << eb << "\n";
  }
  const auto mean = [](const std::vector<double>& v) {
    return std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
  };
  std::cout << "planned " << planned_with << " / " << planned_without << " of 25; force closure "
            << "with g_q " << closure_with << "; epsilon mean " << mean(with) << " / "
            << mean(without) << ", median " << median(with) << " / " << median(without)
            << "; g_q on wins " << wins << ", loses " << losses << "\n";
  EXPECT_GE(planned_with, 23);  // >= 90% of 25
  EXPECT_GE(planned_without, 23);
  EXPECT_GE(closure_with, 23);  // success counted as a re-simulated force-closure grasp
  EXPECT_GT(mean(with), mean(without));
  EXPECT_GE(median(with), median(without));
  EXPECT_GT(wins, losses);
}
#endif

}  // namespace
}  // namespace taskmap
