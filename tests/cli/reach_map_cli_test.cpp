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
  r = testing::runTaskmap(
      "reach --map basket_humanoid --object-pose \"0.5 0 0 0\" --member-tries -1");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find("--member-tries"), std::string::npos) << r.out;
}

/// The basket turned 120 degrees at (0.42, 0.2) m: the arm reaches none of the reference map's
/// representative grasps (the forearm would pass through the basket), but other grasps of the
/// map (docs/REACHING.md "When no representative is reachable").
TEST(ReachMapCli, OtherGraspsStandInWhenNoRepresentativeIsReachable) {
  const std::string base = "reach --map basket_humanoid --scene " + kScenes +
                           "basket_reference.json --object-pose \"0.42 0.2 0 2.0943951\" "
                           "--iterations 2 --no-resimulate --json";
  testing::CliRun r = testing::runTaskmap(base + " --member-tries 0");
  EXPECT_EQ(r.code, 1) << r.out;
  nlohmann::json j = parseJson(r.out);
  EXPECT_EQ(j["status"], "unreachable") << r.out;
  for (const auto& c : j["ranking"]) {
    EXPECT_EQ(c["tried"], 1) << c.dump();
    // Why the representative is out of reach: the rollout's pair and step, or its end error.
    const std::string why = c.value("message", "");
    EXPECT_TRUE(why.rfind("penetrated ", 0) == 0 || why.rfind("target not reached", 0) == 0)
        << c.dump();
  }
  r = testing::runTaskmap(base);
  j = parseJson(r.out);
  ASSERT_EQ(j["status"], "planned") << r.out;
  EXPECT_EQ(r.code, 0) << r.out;
  int tried = 0;
  for (const auto& c : j["ranking"]) tried += c["tried"].get<int>();
  EXPECT_GT(tried, static_cast<int>(j["ranking"].size()));  // members (and outliers) tried
  const nlohmann::json& first = j["ranking"][0];
  EXPECT_TRUE(first["reachable"].get<bool>());
  EXPECT_FALSE(first.contains("message")) << first.dump();  // only unreachable ones say why
  EXPECT_EQ(j["start_cluster"], first["cluster"]);
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

/// The checked-in map (meshes/maps/README.md): built with the build's default hold test, the
/// robust label, so that it stores only grasps that hold robustly. Its recorded parameters are
/// the README's command, and validating its grasps again (`taskmap validate --robust`, the
/// validator apart from the build) gives every grasp the stored labels: nominal hold, robust,
/// every variant held; the displacements under the pushes agree to 1 mm and 0.01 rad (the build
/// tests a grasp before it is written; the validator reads it back from the file). Rebuilding
/// the map itself takes about 1000 CPU seconds (330,000 trials), too long for the suite.
TEST(ReachMapCliSlow, ReferenceMapGraspsHoldRobustlyWhenValidatedAgain) {
  const std::string labels = tempPath("basket_labels.h5");
  const testing::CliRun r =
      testing::runTaskmap("validate " + kMap + " --robust --threads 2 -o " + labels);
  ASSERT_EQ(r.code, 0) << r.out;
  const TaskMapData a = readMap(kMap), c = readMap(labels);
  const nlohmann::json p = nlohmann::json::parse(a.sampling.params_json);
  EXPECT_EQ(p["hold_test"], "robust");
  EXPECT_EQ(p["sampler"], "mixed");
  EXPECT_EQ(p["seed"], 1);
  EXPECT_EQ(p["valid"], 40);
  ASSERT_TRUE(a.validation && c.validation);
  ASSERT_EQ(a.grasps.size(), 40u);
  EXPECT_EQ(c.validation->hold, a.validation->hold);
  EXPECT_EQ(c.validation->robust, a.validation->robust);
  EXPECT_EQ(c.validation->robust_share, a.validation->robust_share);
  for (std::size_t i = 0; i < a.grasps.size(); ++i) {
    EXPECT_EQ(a.validation->robust[i], 1) << i;
    EXPECT_NEAR(c.validation->push_translation[i], a.validation->push_translation[i], 1e-3) << i;
    EXPECT_NEAR(c.validation->push_rotation[i], a.validation->push_rotation[i], 1e-2) << i;
  }
}

nlohmann::json reach(const std::string& scene, const std::string& pose, const std::string& extra) {
  const testing::CliRun r =
      testing::runTaskmap("reach --map basket_humanoid --scene " + kScenes + scene +
                          " --object-pose \"" + pose + "\" --json " + extra);
  nlohmann::json j = parseJson(r.out);
  EXPECT_FALSE(j.is_null()) << r.out;
  // An unreachable position or an unsafe plan is a failed plan, reported with a non-zero exit
  // (the tests count it as one).
  if (j.is_object() && (j["status"] == "unreachable" || j["status"] == "unsafe"))
    EXPECT_NE(r.code, 0) << r.out;
  else
    EXPECT_EQ(r.code, 0) << r.out;
  return j;
}

TEST(ReachMapCliSlow, ThreeBasketPositionsMeetTheAcceptanceMeasures) {
  const std::vector<std::pair<std::string, std::string> > cases = {
      {"reference", "0.5 0 0 1.5708"},
      {"forward", "0.62 0 0 1.5708"},
      {"sideways", "0.5 0.3 0 1.5708"}};
  const std::string png = tempPath("reach_map.png");
  for (const auto& [name, pose] : cases) {
    const nlohmann::json j =
        reach("basket_" + name + ".json", pose, "--all-clusters --hold-test --png " + png);
    ASSERT_TRUE(j.contains("resimulated")) << j.dump();
    const nlohmann::json& s = j["resimulated"];
    std::cout << name << ": cluster " << j["cluster"] << ", grasp " << j["grasp_index"]
              << ", iterations " << j["iterations"] << ", to manifold "
              << j["iterations_to_manifold"] << ", to quality " << j["iterations_to_quality"]
              << ", clearance " << j["min_clearance_m"] << " m, " << j["ms_per_iteration"]
              << " ms/iteration, " << j["ms_per_plan"] << " ms/plan, re-simulated " << s["outcome"]
              << " epsilon " << s["epsilon"] << ", hold test "
              << (s.contains("hold") ? s["hold"].dump() : "none") << "\n";
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
    EXPECT_EQ(j["sample_weight"], "hold_margin");
    ASSERT_TRUE(s.contains("hold")) << s.dump();
    EXPECT_TRUE(s["hold"]["holds"].get<bool>()) << name << ": " << s.dump();
    EXPECT_EQ(j["cost_history"].size(), j["iterations"].get<std::size_t>() + 1);
    const auto& h = j["cost_history"];
    EXPECT_LT(h.back()["total"].get<double>(), h.front()["total"].get<double>());
  }
  // Where the basket stands decides the grasp: QualityTermPicksGraspsThatHoldOnTheGrid (the
  // robust map's reachable grasps from these three positions are two grasps of the top handle's
  // right end, outliers of its three clusters: meshes/maps/README.md).
  EXPECT_TRUE(fs::exists(png));                              // Fig. 1.17 snapshots
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

/// The grid of docs/REACHING.md "Grasps that hold": 25 basket positions, the best cluster, the
/// quality term on and off (same weights otherwise); every planned final grasp re-simulated and
/// tested in physics. Success: planned, and the re-simulated grasp holds.
TEST(ReachMapCliSlow, QualityTermPicksGraspsThatHoldOnTheGrid) {
  std::vector<std::future<nlohmann::json> > runs;
  for (int k = 0; k < 50; ++k) {
    const int cell = k / 2, on = 1 - k % 2;
    runs.push_back(std::async(std::launch::deferred, [cell, on] {
      return reach("basket_reference.json", gridPose(cell / 5, cell % 5),
                   on ? "--hold-test" : "--hold-test --quality-weight 0");
    }));
  }
  // Two CLI processes at a time (their results do not depend on it).
  std::vector<nlohmann::json> result(runs.size());
  for (std::size_t k = 0; k < runs.size(); k += 2) {
    auto second = std::async(std::launch::async, [&runs, k] { return runs[k + 1].get(); });
    result[k] = runs[k].get();
    result[k + 1] = second.get();
  }
  // A position where no grasp tried (representatives, members, outliers) is reachable has no plan
  // and no re-simulation: it counts as neither planned nor holding, with epsilon 0.
  const auto holds = [](const nlohmann::json& j) {
    return j["status"] == "planned" && j.contains("resimulated") &&
           j["resimulated"].contains("hold") && j["resimulated"]["hold"]["holds"].get<bool>();
  };
  const auto epsilon = [](const nlohmann::json& j) {
    return j.contains("resimulated") ? j["resimulated"]["epsilon"].get<double>() : 0.0;
  };
  std::vector<double> with, without;
  std::set<int> targets;  // the grasps the plans end in
  int planned_with = 0, hold_with = 0, hold_without = 0;
  for (std::size_t k = 0; k < result.size(); k += 2) {
    const nlohmann::json &a = result[k], &b = result[k + 1];
    EXPECT_TRUE(a.contains("resimulated") || a["status"] == "unreachable") << a.dump();
    planned_with += a["status"] == "planned";
    if (a["status"] == "planned") targets.insert(a["grasp_index"].get<int>());
    hold_with += holds(a);
    hold_without += holds(b);
    with.push_back(epsilon(a));
    without.push_back(epsilon(b));
    std::cout << "cell " << k / 2 << " ("
              << gridPose(static_cast<int>(k / 2) / 5, static_cast<int>(k / 2) % 5)
              << "): g_q on grasp " << a["grasp_index"] << " epsilon " << with.back() << " hold "
              << holds(a) << ", off grasp " << b["grasp_index"] << " epsilon " << without.back()
              << " hold " << holds(b) << "\n";
  }
  std::cout << "planned " << planned_with << " of 25; the re-simulated grasp holds: with g_q "
            << hold_with << ", without " << hold_without << "; epsilon median " << median(with)
            << " / " << median(without) << "\n";
  EXPECT_GE(planned_with, 23);  // >= 90 % of 25
  EXPECT_GE(hold_with, 23);     // >= 90 % hold (issue 28 part 3)
  // Every grasp of the robust map holds robustly (validated in the build), so the quality term
  // no longer decides whether the final grasp holds; it must not make it worse.
  EXPECT_GE(hold_with, hold_without);
  EXPECT_GE(targets.size(), 2u);  // the chosen grasp depends on where the basket stands
}
#endif

}  // namespace
}  // namespace taskmap
