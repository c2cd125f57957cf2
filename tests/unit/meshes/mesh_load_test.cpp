// Loading: every reference object is a closed solid without repair, every format gives the
// same volume, and bad input gets a clear error naming the file and the defect.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <assimp/scene.h>
#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>

#include "error_matchers.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/meshes/mesh_io.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap {

using taskmap::testing::errorMessage;
namespace {

namespace fs = std::filesystem;

std::string object(const std::string& name) {
  return std::string(TASKMAP_OBJECTS_DIR) + "/" + name + ".obj";
}

std::string data(const std::string& name) {
  return std::string(TEST_DATA_DIR) + "/meshes/" + name;
}

/// A fresh temporary directory, removed at the end of the test.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() / ("taskmap_mesh_load_" + std::string(info->name()) + "_" +
                                         std::to_string(reinterpret_cast<std::uintptr_t>(this)));
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

/// The error message of `f()`, or "" if it did not throw taskmap::Error.
TriangleMesh unitCube() {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) m.vertices.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.faces.emplace_back(q[0], q[1], q[2]);
    m.faces.emplace_back(q[0], q[2], q[3]);
  }
  return m;
}

const std::vector<std::string> kObjects = {"cylinder", "box", "sphere", "mug", "bowl", "basket"};

TEST(MeshLoadTest, ReferenceObjectsAreClosedSolidsWithoutRepair) {
  for (const auto& name : kObjects) {
    SCOPED_TRACE(name);
    const ObjectModel model = ObjectModel::load(object(name));
    EXPECT_TRUE(model.report().closed);
    EXPECT_TRUE(model.report().repairs.empty()) << model.report().repairs.front();
    EXPECT_TRUE(model.report().warnings.empty()) << model.report().warnings.front();
    EXPECT_EQ(model.report().format, "obj");
    EXPECT_GT(model.massProperties().volume, 0);
    EXPECT_LT(fs::file_size(object(name)), 1u << 20);
  }
}

TEST(MeshLoadTest, UnitCubeIsExact) {
  const ObjectModel cube = ObjectModel::fromMesh(unitCube(), "cube");
  EXPECT_DOUBLE_EQ(cube.massProperties().volume, 1.0);
  EXPECT_LT((cube.massProperties().center_of_mass - Eigen::Vector3d::Constant(0.5)).norm(), 1e-15);
  EXPECT_NEAR(cube.massProperties().inertia(0, 0), 1.0 / 6.0, 1e-15);
  EXPECT_NEAR(cube.massProperties().inertia(0, 1), 0.0, 1e-15);
  EXPECT_TRUE(cube.report().repairs.empty());
  EXPECT_EQ(cube.report().format, "memory");
  EXPECT_EQ(cube.sourceSha256(), "");
}

TEST(MeshLoadTest, EveryFormatGivesTheSameVolume) {
  TempDir dir;
  const std::vector<std::pair<MeshFormat, std::string>> formats = {
      {MeshFormat::kObj, "obj"},
      {MeshFormat::kStlAscii, "ascii.stl"},
      {MeshFormat::kStlBinary, "stl"},
      {MeshFormat::kPly, "ply"},
      {MeshFormat::kOff, "off"}};
  for (const auto& name : kObjects) {
    const ObjectModel reference = ObjectModel::load(object(name));
    const double volume = reference.massProperties().volume;
    for (const auto& [format, ext] : formats) {
      SCOPED_TRACE(name + "." + ext);
      const std::string path = dir.file(name + "." + ext);
      writeMesh(reference.mesh(), path, format, "test copy of " + name);
      const ObjectModel copy = ObjectModel::load(path);
      // Files store float32 or 17 digits; assimp reads float32: 1e-6 relative is plenty.
      EXPECT_NEAR(copy.massProperties().volume, volume, 1e-6 * volume);
      EXPECT_LT(
          (copy.massProperties().center_of_mass - reference.massProperties().center_of_mass).norm(),
          1e-6);
      EXPECT_TRUE(copy.report().repairs.empty()) << copy.report().repairs.front();
      EXPECT_EQ(copy.mesh().faces.size(), reference.mesh().faces.size());
    }
  }
}

TEST(MeshLoadTest, AssimpExportedFormatsGiveTheSameVolume) {
  // glTF 2 (text and binary), COLLADA and assimp's own STL/PLY writers, from the OBJ files.
  TempDir dir;
  const std::vector<std::pair<std::string, std::string>> formats = {
      {"glb2", "glb"}, {"gltf2", "gltf"}, {"collada", "dae"}, {"stlb", "stl"}};
  // Not binary PLY: Debian's assimp 5.2.5 misreads some valid binary PLY files (the mug:
  // "aiMesh::mFaces[4]::mIndices[0] is out of range"); loading then fails with that error.
  for (const std::string name : {"mug", "basket", "sphere"}) {
    const ObjectModel reference = ObjectModel::load(object(name));
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(object(name), 0);
    ASSERT_NE(scene, nullptr);
    for (const auto& [id, ext] : formats) {
      SCOPED_TRACE(name + "." + ext);
      const std::string path = dir.file(name + "." + ext);
      Assimp::Exporter exporter;
      ASSERT_EQ(exporter.Export(scene, id, path), AI_SUCCESS) << exporter.GetErrorString();
      const ObjectModel copy = ObjectModel::load(path);
      EXPECT_EQ(copy.report().format, ext);
      EXPECT_NEAR(copy.massProperties().volume, reference.massProperties().volume,
                  1e-6 * reference.massProperties().volume);
      EXPECT_LT(
          (copy.massProperties().center_of_mass - reference.massProperties().center_of_mass).norm(),
          1e-6);
    }
  }
}

TEST(MeshLoadTest, ScaleMultipliesCoordinates) {
  const ObjectModel big = ObjectModel::load(object("box"), MeshLoadOptions{100.0});
  const ObjectModel m = ObjectModel::load(object("box"));
  EXPECT_NEAR(big.massProperties().volume, 1e6 * m.massProperties().volume,
              1e-6 * 1e6 * m.massProperties().volume);
  EXPECT_DOUBLE_EQ(big.scale(), 100.0);
  EXPECT_NE(errorMessage([] { ObjectModel::load(object("box"), MeshLoadOptions{-1.0}); }), "");
  EXPECT_NE(errorMessage([] {
              ObjectModel::load(object("box"), MeshLoadOptions{0.0});
            }).find("scale must be a positive finite number"),
            std::string::npos);
}

TEST(MeshLoadTest, MissingFile) {
  const std::string msg = errorMessage([] { ObjectModel::load(data("no_such_file.obj")); });
  EXPECT_NE(msg.find("no_such_file.obj"), std::string::npos) << msg;
  EXPECT_NE(msg.find("no such file"), std::string::npos) << msg;
}

TEST(MeshLoadTest, EmptyFile) {
  const std::string msg = errorMessage([] { ObjectModel::load(data("empty.obj")); });
  EXPECT_NE(msg.find("empty.obj' is empty"), std::string::npos) << msg;
}

TEST(MeshLoadTest, MalformedObj) {
  const std::string msg = errorMessage([] { ObjectModel::load(data("malformed.obj")); });
  EXPECT_NE(msg.find("malformed.obj"), std::string::npos) << msg;
  EXPECT_FALSE(msg.empty());
}

TEST(MeshLoadTest, UnknownFormat) {
  TempDir dir;
  const std::string path = dir.file("garbage.xyz123");
  std::ofstream(path) << "this is not a mesh\n";
  const std::string msg = errorMessage([&] { ObjectModel::load(path); });
  EXPECT_NE(msg.find("cannot read mesh file '" + path + "'"), std::string::npos) << msg;
}

TEST(MeshLoadTest, TruncatedFilesAreRefused) {
  TempDir dir;
  const ObjectModel box = ObjectModel::load(object("box"));
  for (const auto& [format, ext] : std::vector<std::pair<MeshFormat, std::string>>{
           {MeshFormat::kStlBinary, "stl"}, {MeshFormat::kPly, "ply"}, {MeshFormat::kOff, "off"}}) {
    SCOPED_TRACE(ext);
    const std::string full = dir.file("full." + ext), cut = dir.file("cut." + ext);
    writeMesh(box.mesh(), full, format);
    std::ifstream in(full, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    const std::string msg = errorMessage([&] { ObjectModel::load(cut); });
    EXPECT_NE(msg.find("cut." + ext), std::string::npos) << msg;
  }
}

TEST(MeshLoadTest, NanVertex) {
  const std::string msg = errorMessage([] { ObjectModel::load(data("nan_vertex.obj")); });
  EXPECT_NE(msg.find("nan_vertex.obj"), std::string::npos) << msg;
  EXPECT_NE(msg.find("non-finite coordinate"), std::string::npos) << msg;
  TriangleMesh cube = unitCube();
  cube.vertices[3].y() = std::nan("");
  const std::string mem = errorMessage([&] { ObjectModel::fromMesh(cube, "nan cube"); });
  EXPECT_NE(mem.find("mesh 'nan cube': vertex 3 has a non-finite coordinate"), std::string::npos)
      << mem;
}

TEST(MeshLoadTest, HoleThatCannotBeClosedIsRefused) {
  const std::string msg = errorMessage([] { ObjectModel::load(data("cube_open.obj")); });
  EXPECT_NE(msg.find("cube_open.obj': mesh has 4 border edges after stitching; the object must "
                     "be closed to sample its volume"),
            std::string::npos)
      << msg;
}

TEST(MeshLoadTest, SeamClosedByStitchingIsRepaired) {
  const ObjectModel model = ObjectModel::load(data("cube_seam.obj"));
  ASSERT_EQ(model.report().repairs.size(), 1u);
  EXPECT_NE(model.report().repairs[0].find("stitched borders: welded 4 border vertices"),
            std::string::npos)
      << model.report().repairs[0];
  EXPECT_NEAR(model.massProperties().volume, 1.0, 1e-5);
  MeshLoadOptions strict;
  strict.repair = false;
  const std::string msg = errorMessage([&] { ObjectModel::load(data("cube_seam.obj"), strict); });
  EXPECT_NE(msg.find("8 border edges; the object must be closed"), std::string::npos) << msg;
}

TEST(MeshLoadTest, DuplicatedSeamVerticesInMemoryAreMerged) {
  TriangleMesh cube = unitCube();
  // Give the top face its own copies of its corners.
  const int base = static_cast<int>(cube.vertices.size());
  for (int i = 4; i < 8; ++i) cube.vertices.push_back(cube.vertices[i]);
  cube.faces[2] = Eigen::Vector3i(base, base + 1, base + 3);
  cube.faces[3] = Eigen::Vector3i(base, base + 3, base + 2);
  const ObjectModel model = ObjectModel::fromMesh(cube, "seam");
  ASSERT_EQ(model.report().repairs.size(), 1u);
  EXPECT_EQ(model.report().repairs[0], "merged 4 duplicate vertices with identical coordinates");
  EXPECT_DOUBLE_EQ(model.massProperties().volume, 1.0);
}

TEST(MeshLoadTest, InwardFacesAreReversed) {
  const ObjectModel model = ObjectModel::load(data("cube_inward.obj"));
  ASSERT_EQ(model.report().repairs.size(), 1u);
  EXPECT_EQ(model.report().repairs[0], "reversed 12 faces to point outward");
  EXPECT_NEAR(model.massProperties().volume, 1.0, 1e-6);
  MeshLoadOptions strict;
  strict.repair = false;
  const std::string msg = errorMessage([&] { ObjectModel::load(data("cube_inward.obj"), strict); });
  EXPECT_NE(msg.find("12 inward-facing faces (repair is disabled)"), std::string::npos) << msg;
}

TEST(MeshLoadTest, InconsistentOrientationIsRepaired) {
  TriangleMesh cube = unitCube();
  std::swap(cube.faces[5][1], cube.faces[5][2]);
  const ObjectModel model = ObjectModel::fromMesh(cube, "one flipped");
  ASSERT_FALSE(model.report().repairs.empty());
  EXPECT_NE(model.report().repairs[0].find("reoriented faces consistently"), std::string::npos)
      << model.report().repairs[0];
  EXPECT_DOUBLE_EQ(model.massProperties().volume, 1.0);
}

TEST(MeshLoadTest, DegenerateAndDuplicateFacesAreDropped) {
  TriangleMesh cube = unitCube();
  cube.faces.emplace_back(0, 0, 1);     // repeated vertex
  cube.faces.push_back(cube.faces[0]);  // duplicate face
  const ObjectModel model = ObjectModel::fromMesh(cube, "dirty");
  ASSERT_EQ(model.report().repairs.size(), 2u);
  EXPECT_EQ(model.report().repairs[0], "dropped 1 degenerate face with a repeated vertex");
  EXPECT_EQ(model.report().repairs[1], "dropped 1 duplicate face");
  EXPECT_DOUBLE_EQ(model.massProperties().volume, 1.0);
}

TEST(MeshLoadTest, NonManifoldEdgeIsRefused) {
  // Two cubes sharing one edge: that edge has four faces.
  TriangleMesh two = unitCube();
  const TriangleMesh second = unitCube();
  const int base = static_cast<int>(two.vertices.size());
  for (const auto& v : second.vertices) two.vertices.push_back(v + Eigen::Vector3d(1, 1, 0));
  for (const auto& f : second.faces) two.faces.push_back(f + Eigen::Vector3i::Constant(base));
  const std::string msg = errorMessage([&] { ObjectModel::fromMesh(two, "two cubes"); });
  EXPECT_NE(msg.find("mesh 'two cubes': mesh has 1 non-manifold edge (shared by more than two "
                     "faces)"),
            std::string::npos)
      << msg;
}

TEST(MeshLoadTest, OverlappingShellsLoadWithAWarningAndUniteForInsideTests) {
  TriangleMesh two = unitCube();
  const TriangleMesh second = unitCube();
  const int base = static_cast<int>(two.vertices.size());
  for (const auto& v : second.vertices) {
    two.vertices.push_back(v + Eigen::Vector3d(0.5, 0.25, 0.125));
  }
  for (const auto& f : second.faces) two.faces.push_back(f + Eigen::Vector3i::Constant(base));
  const ObjectModel model = ObjectModel::fromMesh(two, "overlap");
  ASSERT_EQ(model.report().warnings.size(), 1u);
  EXPECT_NE(model.report().warnings[0].find("the surface intersects itself"), std::string::npos);
  EXPECT_TRUE(model.contains(Eigen::Vector3d(0.75, 0.6, 0.6)));  // in both cubes
  EXPECT_TRUE(model.contains(Eigen::Vector3d(0.2, 0.2, 0.2)));   // first only
  EXPECT_TRUE(model.contains(Eigen::Vector3d(1.3, 1.1, 1.0)));   // second only
  EXPECT_FALSE(model.contains(Eigen::Vector3d(1.3, 0.1, 0.5)));  // neither
  EXPECT_DOUBLE_EQ(model.massProperties().volume, 2.0);          // overlap counted twice
}

TEST(MeshLoadTest, FlatMeshIsRefused) {
  const std::string msg = errorMessage([] { ObjectModel::load(data("flat.obj")); });
  EXPECT_NE(msg.find("flat.obj': mesh encloses zero volume"), std::string::npos) << msg;
}

TEST(MeshLoadTest, AbsurdlyLargeMeshIsRefused) {
  const std::string msg =
      errorMessage([] { ObjectModel::load(object("box"), MeshLoadOptions{10000.0}); });
  EXPECT_NE(msg.find("box.obj': bounding box is 1200 m across, above the limit of 100 m for an "
                     "object (max_extent)"),
            std::string::npos)
      << msg;
}

TEST(MeshLoadTest, EmptyInMemoryMeshIsRefused) {
  const std::string msg = errorMessage([] { ObjectModel::fromMesh(TriangleMesh{}, "nothing"); });
  EXPECT_EQ(msg, "mesh 'nothing': mesh has no triangles");
  TriangleMesh bad = unitCube();
  bad.faces[0][1] = 99;
  const std::string idx = errorMessage([&] { ObjectModel::fromMesh(bad, "bad index"); });
  EXPECT_NE(idx.find("face 0 references vertex 99 but the mesh has 8 vertices"), std::string::npos)
      << idx;
}

}  // namespace
}  // namespace taskmap
