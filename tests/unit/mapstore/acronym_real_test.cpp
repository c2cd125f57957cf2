// ACRONYM's own grasp file for a ShapeNet mug (CC BY-NC: read from TASKMAP_REAL_DIR, never
// copied; skipped when absent): imported palms lie on the mug's surface once the gripper base
// frame is moved to the palm frame, and export writes the base frame back.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <unistd.h>

#include "taskmap/builder/map_builder.hpp"
#include "taskmap/mapstore/acronym.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

std::string realDir() {
  const char* env = std::getenv("TASKMAP_REAL_DIR");
  return env ? env : TASKMAP_REAL_DIR;
}

struct RealMug {
  std::string grasps, mesh;
};

std::optional<RealMug> findMug() {
  const fs::path dir = realDir();
  RealMug m;
  std::error_code ec;
  if (!fs::is_directory(dir / "acronym", ec)) return std::nullopt;
  for (const auto& e : fs::directory_iterator(dir / "acronym", ec))
    if (e.path().filename().string().rfind("Mug_", 0) == 0) m.grasps = e.path().string();
  for (const auto& e : fs::directory_iterator(dir / "objects", ec))
    if (e.path().filename().string().rfind("acronym_mug_", 0) == 0) m.mesh = e.path().string();
  if (m.grasps.empty() || m.mesh.empty()) return std::nullopt;
  return m;
}

double medianPalmDistance(const TaskMapData& map, const ObjectModel& object) {
  std::vector<double> d;
  for (std::size_t i = 0; i < map.grasps.size(); ++i)
    d.push_back(object.distanceToSurface(map.grasps.poseAt(i).position));
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  return d[d.size() / 2];
}

TEST(AcronymReal, ImportedPalmsLieOnTheMugSurface) {
  const auto mug = findMug();
  if (!mug) GTEST_SKIP() << "ACRONYM example not found under " << realDir();
  const AcronymGrasps grasps = readAcronym(mug->grasps);
  ASSERT_EQ(grasps.transforms.size(), 2000u);
  MeshLoadOptions load;
  load.scale = grasps.object_scale;
  const ObjectModel object = ObjectModel::load(mug->mesh, load);
  AcronymImportOptions options;
  options.successful_only = true;
  options.cluster = false;
  const TaskMapData map = acronymToMap(grasps, mapObjectOf(object), options);
  EXPECT_EQ(map.grasps.size(), 1290u);
  const double median = medianPalmDistance(map, object);
  EXPECT_LT(median, 0.01) << "median palm-to-surface distance " << median << " m";
  // The base frame itself sits about a gripper length away (what the import used to store).
  options.base_to_palm = Eigen::Isometry3d::Identity();
  const double base =
      medianPalmDistance(acronymToMap(grasps, mapObjectOf(object), options), object);
  EXPECT_GT(base, 0.05) << base;

  // Export writes the base frames back: the file's own transforms, to rounding.
  const std::string out =
      ::testing::TempDir() + "/acronym_real_" + std::to_string(::getpid()) + ".h5";
  writeAcronym(out, map);
  const AcronymGrasps back = readAcronym(out);
  std::vector<Eigen::Matrix4d> successful;
  for (std::size_t i = 0; i < grasps.transforms.size(); ++i)
    if (grasps.success[i]) successful.push_back(grasps.transforms[i]);
  ASSERT_EQ(back.transforms.size(), successful.size());
  for (std::size_t i = 0; i < successful.size(); ++i)
    EXPECT_LT((back.transforms[i] - successful[i]).cwiseAbs().maxCoeff(), 1e-9) << i;
  fs::remove(out);
}

}  // namespace
}  // namespace taskmap
