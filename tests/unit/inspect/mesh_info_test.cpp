// inspect/mesh_info.hpp: the `mesh-info` report of an object, JSON and text, against the
// object's own mass properties.
#include "taskmap/inspect/mesh_info.hpp"

#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace taskmap {
namespace {

const std::string kCylinder = std::string(TASKMAP_SOURCE_DIR) + "/meshes/objects/cylinder.obj";

TEST(MeshInfoTest, JsonAndTextReportTheLoadedSolid) {
  const ObjectModel object = ObjectModel::load(kCylinder);
  const MeshInfo info = meshInfo(object);
  const nlohmann::json j = nlohmann::json::parse(info.json);
  const MassProperties& mass = object.massProperties();
  EXPECT_EQ(j["path"], object.report().path);
  EXPECT_EQ(j["sha256"], object.sourceSha256());
  EXPECT_EQ(j["faces"], object.mesh().faces.size());
  EXPECT_TRUE(j["closed"].get<bool>());
  EXPECT_TRUE(j["graspable_size"].get<bool>());
  EXPECT_DOUBLE_EQ(j["volume"].get<double>(), mass.volume);
  EXPECT_DOUBLE_EQ(j["size"][2].get<double>(), mass.bounds_max.z() - mass.bounds_min.z());
  EXPECT_DOUBLE_EQ(j["inertia"][1][1].get<double>(), mass.inertia(1, 1));
  EXPECT_EQ(info.text.rfind("file:           " + object.report().path + "\n", 0), 0u);
  EXPECT_NE(info.text.find("solid:          "), std::string::npos);
  EXPECT_NE(info.text.find("closed\n"), std::string::npos);
  EXPECT_NE(info.text.find("torque scale:"), std::string::npos);
}

TEST(MeshInfoTest, ASizeImplausibleForAGraspableObjectIsFlagged) {
  MeshLoadOptions large;
  large.scale = 10.0;  // 2 m across: loads, but no hand grasps it
  const MeshInfo info = meshInfo(ObjectModel::load(kCylinder, large));
  const nlohmann::json j = nlohmann::json::parse(info.json);
  EXPECT_FALSE(j["graspable_size"].get<bool>());
  EXPECT_NE(info.text.find("warning:        the object is 2 m across: large"), std::string::npos)
      << info.text;
}

TEST(MeshInfoTest, ErrorJsonNamesThePath) {
  const nlohmann::json j = nlohmann::json::parse(meshInfoErrorJson("a.obj", "no faces"));
  EXPECT_EQ(j["path"], "a.obj");
  EXPECT_FALSE(j["closed"].get<bool>());
  EXPECT_EQ(j["error"], "no faces");
}

}  // namespace
}  // namespace taskmap
