// Repair of real scanned meshes (YCB, tests/data/real/README.md): opposite-orientation duplicate
// faces, and open surfaces closed by alpha wrapping (checked against the closed original).
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <string>

#include "taskmap/core/error.hpp"
#include "taskmap/meshes/object_model.hpp"
#include "test_meshes.hpp"

namespace taskmap {
namespace {

std::string real(const std::string& name) {
  return std::string(TEST_DATA_DIR) + "/real/objects/" + name + ".obj";
}

/// The unit cube [0, 1]^3 (corner i at (i & 1, i >> 1 & 1, i >> 2 & 1)).
TriangleMesh unitCube() {
  return testing::makeBox(1, 1, 1, Eigen::Vector3d::Constant(0.5));
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

bool hasRepair(const ObjectModel& m, const std::string& text) {
  const auto& r = m.report().repairs;
  return std::any_of(r.begin(), r.end(),
                     [&](const std::string& s) { return s.find(text) != std::string::npos; });
}

TEST(MeshRepairReal, FinOfOppositeFacesIsRemovedWhole) {
  // A double-sided triangle through the cube (corners 0, 1, 7): keeping one face would leave
  // two border edges; both go and the cube stays.
  TriangleMesh m = unitCube();
  m.faces.emplace_back(0, 1, 7);
  m.faces.emplace_back(0, 7, 1);
  const ObjectModel model = ObjectModel::fromMesh(m, "finned cube");
  EXPECT_TRUE(hasRepair(model, "dropped 1 pair of identical faces with opposite orientation"));
  EXPECT_EQ(model.mesh().faces.size(), 12u);
  EXPECT_NEAR(model.massProperties().volume, 1.0, 1e-12);
  MeshLoadOptions strict;
  strict.repair = false;
  EXPECT_NE(errorOf([&] {
              ObjectModel::fromMesh(m, "finned cube", strict);
            }).find("1 pair of identical faces with opposite orientation (repair is disabled)"),
            std::string::npos);
}

TEST(MeshRepairReal, ReversedCopyOfAFaceKeepsTheConsistentOne) {
  TriangleMesh m = unitCube();
  m.faces.emplace_back(m.faces[0].z(), m.faces[0].y(), m.faces[0].x());
  const ObjectModel model = ObjectModel::fromMesh(m, "cube");
  EXPECT_TRUE(hasRepair(model, "dropped 1 duplicate face"));
  EXPECT_EQ(model.mesh().faces.size(), 12u);
  EXPECT_NEAR(model.massProperties().volume, 1.0, 1e-12);
}

TEST(MeshRepairReal, YcbMeshesLoad) {
  const ObjectModel mug = ObjectModel::load(real("ycb_025_mug"));
  EXPECT_TRUE(mug.report().closed);
  EXPECT_TRUE(hasRepair(mug, "dropped 3 pairs of identical faces with opposite orientation"));
  // A YCB mug holds about 0.3 l; its solid (walls and handle) is much less.
  EXPECT_GT(mug.massProperties().volume, 1e-4);
  EXPECT_LT(mug.massProperties().volume, 2e-4);
  const ObjectModel banana = ObjectModel::load(real("ycb_011_banana"));
  EXPECT_TRUE(banana.report().repairs.empty());
  EXPECT_NEAR(banana.massProperties().volume, 1.715e-4, 0.01e-4);
}

TEST(MeshRepairReal, OpenScanIsRefusedWithTheWrapHintAndClosedByWrapping) {
  const ObjectModel closed = ObjectModel::load(real("ycb_011_banana"));
  TriangleMesh open = closed.mesh();
  open.faces.erase(open.faces.begin() + 5000, open.faces.begin() + 5040);  // a hole
  const std::string msg = errorOf([&] { ObjectModel::fromMesh(open, "banana with a hole"); });
  EXPECT_NE(msg.find("mesh 'banana with a hole': mesh has"), std::string::npos) << msg;
  EXPECT_NE(msg.find("border edges after stitching"), std::string::npos) << msg;
  EXPECT_NE(msg.find("`--repair wrap`"), std::string::npos) << msg;

  MeshLoadOptions wrap;
  wrap.wrap = true;
  const ObjectModel wrapped = ObjectModel::fromMesh(open, "banana with a hole", wrap);
  EXPECT_TRUE(wrapped.report().closed);
  ASSERT_FALSE(wrapped.report().repairs.empty());
  EXPECT_NE(wrapped.report().repairs[0].find("closed the open surface by alpha wrapping (alpha "),
            std::string::npos)
      << wrapped.report().repairs[0];
  EXPECT_NE(wrapped.report().repairs[0].find("enclosed by the open input"), std::string::npos);
  // The wrap lies within alpha of the scan (default alpha: diagonal / 100, about 2 mm) and
  // encloses about the same volume.
  const double v0 = closed.massProperties().volume;
  EXPECT_NEAR(wrapped.massProperties().volume, v0, 0.03 * v0);
  double worst = 0;
  for (const auto& p : wrapped.mesh().vertices)
    worst = std::max(worst, closed.distanceToSurface(p));
  EXPECT_LT(worst, 2.2e-3);
  // A closed mesh is not wrapped.
  const ObjectModel same = ObjectModel::load(real("ycb_011_banana"), wrap);
  EXPECT_EQ(same.mesh().faces.size(), closed.mesh().faces.size());
}

TEST(MeshRepairReal, WrapOptionsAreChecked) {
  MeshLoadOptions o;
  o.wrap = true;
  o.repair = false;
  EXPECT_NE(errorOf([&] { o.validate(); }).find("wrap needs repair"), std::string::npos);
  o.repair = true;
  o.wrap_alpha = -1;
  EXPECT_NE(errorOf([&] { o.validate(); }).find("wrap_alpha and wrap_offset"), std::string::npos);
}

}  // namespace
}  // namespace taskmap
