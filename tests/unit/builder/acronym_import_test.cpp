// importAcronymFile (acronym_import.hpp): an ACRONYM file written from a map comes back as a map
// file with the same poses and flags, run in a child process with limits; a damaged file, a
// missing mesh and contradicting frame options are refused naming the problem, nothing written.
#include "taskmap/builder/acronym_import.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "error_matchers.hpp"
#include "scratch_dir.hpp"
#include "synthetic_map.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap {
namespace {

using taskmap::testing::errorMessage;

const testing::ScratchDir kDir("acronym_import_test");
const std::string kBasket = std::string(TASKMAP_OBJECTS_DIR) + "/basket.obj";

AcronymFileImportOptions importOf(const std::string& acronym, const std::string& output) {
  AcronymFileImportOptions o;
  o.acronym = acronym;
  o.object = kBasket;
  o.output = output;
  o.scale = 1.0;
  return o;
}

TEST(AcronymImport, ExportedGraspsComeBackAsAMapFile) {
  const TaskMapData map = testing::clusteredBasketMap(20, 3);
  const std::string acronym = kDir.path("basket_grasps.h5");
  writeAcronym(acronym, map);
  const AcronymFileImport r = importAcronymFile(importOf(acronym, kDir.path("imported.h5")));
  const TaskMapData back = readMap(kDir.path("imported.h5"));
  EXPECT_EQ(r.grasps, map.grasps.size());
  EXPECT_EQ(back.grasps.size(), map.grasps.size());
  std::size_t successes = 0;
  for (auto fc : map.grasps.force_closure) successes += fc;
  EXPECT_EQ(r.successes, successes);
  ASSERT_TRUE(back.clustering.has_value());
  ASSERT_TRUE(r.clusters.has_value());
  EXPECT_EQ(*r.clusters, back.clustering->clusters.size());
  EXPECT_EQ(r.object_name, "basket");
  EXPECT_EQ(r.scale, 1.0);
  for (std::size_t i = 0; i < map.grasps.size(); ++i)
    EXPECT_LT((back.grasps.poseAt(i).position - map.grasps.poseAt(i).position).norm(), 1e-12);
  // Without clustering the result says so.
  AcronymFileImportOptions o = importOf(acronym, kDir.path("unclustered.h5"));
  o.import.cluster = false;
  EXPECT_FALSE(importAcronymFile(o).clusters.has_value());
}

TEST(AcronymImport, BadInputIsRefusedAndNothingIsWritten) {
  const std::string damaged = kDir.path("damaged.h5");
  std::ofstream(damaged) << "\x89HDF\r\n\x1a\n this is not HDF5";
  const std::string out = kDir.path("never.h5");
  EXPECT_NE(errorMessage([&] { importAcronymFile(importOf(damaged, out)); }).find(damaged),
            std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(out));
  const std::string acronym = kDir.path("for_missing_mesh.h5");
  writeAcronym(acronym, testing::clusteredBasketMap(5, 0));
  AcronymFileImportOptions o = importOf(acronym, out);
  o.object = kDir.path("no_such_mesh.obj");
  EXPECT_NE(errorMessage([&] { importAcronymFile(o); }).find("does not exist; give the mesh that"),
            std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(out));
  o = importOf(acronym, out);
  o.cpu_seconds = 0;
  EXPECT_EQ(errorMessage([&] { importAcronymFile(o); }),
            "--cpu-seconds must be in [1, 86400], not 0");
  o = importOf(acronym, out);
  o.scale = -1;
  EXPECT_EQ(errorMessage([&] { importAcronymFile(o); }), "--scale must be positive");
}

TEST(AcronymImport, PalmFrameFromOneOption) {
  EXPECT_NEAR(acronymBaseToPalm(std::nullopt, "").translation().z(), kAcronymFrankaPalmOffset,
              1e-15);
  EXPECT_NEAR(acronymBaseToPalm(0.05, "").translation().z(), 0.05, 1e-15);
  EXPECT_EQ(errorMessage([] { acronymBaseToPalm(0.05, "panda"); }),
            "--palm-offset and --hand both set the palm frame: give one");
  EXPECT_EQ(errorMessage([] { acronymBaseToPalm(std::nan(""), ""); }),
            "--palm-offset must be a finite length");
  // A hand's root-to-palm transform (the bundled Panda gripper's URDF).
  const Eigen::Isometry3d t =
      acronymBaseToPalm(std::nullopt, std::string(TASKMAP_HANDS_DIR) + "/panda/panda.urdf");
  EXPECT_TRUE(t.matrix().allFinite());
}

}  // namespace
}  // namespace taskmap
