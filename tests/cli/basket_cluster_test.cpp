// Paper 1.6.1 end to end: `taskmap build` on the basket (meshes/objects/basket.obj) with the
// three-finger Barrett hand, the README's map (grasps that hold robustly), and its DEFAULT
// clustering (average linkage, gap rule with a 10 %
// outlier budget). Grasps on the left bar, the right bar and the top bar of the U-shaped handle
// must fall into different clusters, none of them empty, and at most 10 % of the grasps may be
// outliers (the paper drops only small clusters). Label cli: needs the taskmap tool. Geometry from
// meshes/objects/README.md: bars 2 cm square at x = -0.146 and +0.146 rising from z = 0.08 to 0.28,
// top bar at z = 0.26..0.279, body rim at z = 0.12.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <unistd.h>

#include <gtest/gtest.h>

#include "taskmap/mapstore/map_file.hpp"

namespace taskmap {
namespace {

enum Bar { kLeft = 0, kRight = 1, kTop = 2, kNone = 3 };

/// The bar a grasp holds: every contact on that bar, away from the corners and the body.
Bar barOf(const MapGrasps& g, std::size_t i) {
  const auto begin = g.contact_offsets[i];
  const auto end = g.contact_offsets[i + 1];
  if (begin == end) return kNone;
  std::set<Bar> bars;
  for (auto c = begin; c < end; ++c) {
    const double x = g.contact_points(c, 0);
    const double z = g.contact_points(c, 2);
    if (x < -0.125 && z > 0.14 && z < 0.245) {
      bars.insert(kLeft);
    } else if (x > 0.125 && z > 0.14 && z < 0.245) {
      bars.insert(kRight);
    } else if (z > 0.245 && x > -0.11 && x < 0.11) {
      bars.insert(kTop);
    } else {
      bars.insert(kNone);
    }
  }
  return bars.size() == 1 ? *bars.begin() : kNone;
}

TEST(BasketClusters, HandleBarsAreSeparateClusters) {
  const std::string object = std::string(TASKMAP_OBJECTS_DIR) + "/basket.obj";
  const std::string hand = std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf";
  const std::string cli = std::string(TASKMAP_BINARY_DIR) + "/bin/taskmap";
  ASSERT_TRUE(std::filesystem::exists(cli)) << cli << " missing (build target taskmap_cli)";
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("taskmap_basket_cluster_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string map_path = (dir / "basket.h5").string();
  // TASKMAP_BASKET_MAP: the README's map already built by the same taskmap (ctest's readme_map
  // fixture); else it is built here with the main job's arguments, tools/readme_map.args.
  if (const char* built = std::getenv("TASKMAP_BASKET_MAP")) {
    std::filesystem::copy_file(built, map_path);
  } else {
    ASSERT_TRUE(std::filesystem::exists(object)) << object << " missing (meshes stage)";
    ASSERT_TRUE(std::filesystem::exists(hand)) << hand << " missing (meshes stage)";
    std::ifstream args_file(std::string(TASKMAP_SOURCE_DIR) + "/tools/readme_map.args");
    std::string args;
    std::getline(args_file, args);
    ASSERT_FALSE(args.empty()) << "tools/readme_map.args missing";
    const std::string build = "cd " + std::string(TASKMAP_SOURCE_DIR) + " && " + cli + " build " +
                              args + " -o " + map_path + " --quiet";
    ASSERT_EQ(std::system(build.c_str()), 0) << build;
  }
  const TaskMapData map = readMap(map_path);
  std::filesystem::remove_all(dir);
  ASSERT_TRUE(map.clustering.has_value());
  // Average linkage: single linkage chains the three bars together through grasps at the
  // handle's corners at every cut (measured on the map of 1000 force-closure grasps: one
  // cluster of all of them).
  EXPECT_EQ(map.clustering->method, Linkage::kAverage);
  const ClusteringResult& c = *map.clustering;
  ASSERT_EQ(c.labels.size(), map.grasps.size());
  const auto outliers = std::count(c.labels.begin(), c.labels.end(), -1);
  EXPECT_LE(outliers, static_cast<long>(map.grasps.size() / 10))
      << "the default cut left " << outliers << " of " << map.grasps.size()
      << " grasps as outliers";
  // Clusters a person would name (issue 50): 3 to 12.
  EXPECT_GE(c.clusters.size(), 3u);
  EXPECT_LE(c.clusters.size(), 12u);

  // Labels used by the grasps on each bar, with counts.
  std::map<int, int> labels_on[3];
  int on_bar[3] = {0, 0, 0};
  for (std::size_t i = 0; i < map.grasps.size(); ++i) {
    const Bar b = barOf(map.grasps, i);
    if (b == kNone) continue;
    ++on_bar[b];
    ++labels_on[b][c.labels[i]];
  }
  const char* names[3] = {"left", "right", "top"};
  int main_label[3];
  for (int b = 0; b < 3; ++b) {
    ASSERT_GT(on_bar[b], 0) << "no grasp on the " << names[b] << " bar";
    // The bar's main cluster: the most frequent label other than outlier.
    int best = -1, count = 0;
    for (const auto& [label, n] : labels_on[b]) {
      if (label >= 0 && n > count) {
        best = label;
        count = n;
      }
    }
    ASSERT_GE(best, 0) << "every grasp on the " << names[b] << " bar is an outlier";
    main_label[b] = best;
    EXPECT_GT(c.clusters[best].size, 0);
  }
  // No cluster holds grasps of two bars.
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      if (a == b) continue;
      EXPECT_EQ(labels_on[b].count(main_label[a]), 0u)
          << "cluster " << main_label[a] << " of the " << names[a] << " bar also holds "
          << labels_on[b][main_label[a]] << " grasps of the " << names[b] << " bar";
    }
  }
}

}  // namespace
}  // namespace taskmap
