#include "taskmap/meshes/mesh_export.hpp"

#include <unistd.h>

#include <filesystem>
#include <string>

#include <assimp/scene.h>
#include <gtest/gtest.h>
#include <assimp/Importer.hpp>

#include "error_matchers.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/random.hpp"

namespace taskmap {

using taskmap::testing::errorMessage;
namespace {

std::string tempPath(const std::string& name) {
  return ::testing::TempDir() + "/mesh_export_test_" + std::to_string(::getpid()) + "_" + name;
}

// An object (a glyph mesh of 10 cm serves as a non-trivial closed solid), n random points in
// two colours and two glyphs.
ExportScene makeScene(int n) {
  ExportScene s;
  s.object = handGlyphMesh(0.1);
  Rng rng(5);
  for (int i = 0; i < n; ++i) {
    s.points.emplace_back(rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2), rng.uniform(0, 0.3));
    s.point_colors.push_back(i % 2 ? Rgba(1, 0, 0, 1) : Rgba(0, 0, 1, 1));
  }
  SceneGlyph g;
  g.pose.translation() = Eigen::Vector3d(0, 0, 0.3);
  s.glyphs.push_back(g);
  g.pose.linear() = Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  g.color = Rgba(0, 1, 0, 1);
  s.glyphs.push_back(g);
  return s;
}

int countFaces(const aiMesh& mesh, unsigned indices) {
  int n = 0;
  for (unsigned f = 0; f < mesh.mNumFaces; ++f) n += mesh.mFaces[f].mNumIndices == indices;
  return n;
}

TEST(MeshExportTest, GlyphIsClosedAndPointsAlongZ) {
  const TriangleMesh g = handGlyphMesh(0.05);
  ASSERT_EQ(g.vertices.size(), static_cast<std::size_t>(kGlyphVertices));
  EXPECT_EQ(g.faces.size(), 48u);
  // Divergence theorem: the signed volume is positive (outward faces) and the four boxes'
  // volumes add up; the fingers reach z = size.
  double volume = 0;
  double zmax = -1;
  for (const auto& f : g.faces) {
    volume += g.vertices[f[0]].dot(g.vertices[f[1]].cross(g.vertices[f[2]])) / 6.0;
  }
  for (const auto& v : g.vertices) zmax = std::max(zmax, v.z());
  const double s = 0.05, t = 0.08 * s;
  const double expected = 0.7 * s * 0.5 * s * t + 3 * t * t * s;
  EXPECT_NEAR(volume, expected, 1e-15);
  EXPECT_DOUBLE_EQ(zmax, s);
}

TEST(MeshExportTest, PlyReadsBackWithObjectVerticesAndOnePointPerGrasp) {
  const ExportScene scene = makeScene(57);
  const std::string path = tempPath("scene.ply");
  exportScene(path, scene, SceneFormat::kPly);
  Assimp::Importer importer;
  const aiScene* read = importer.ReadFile(path, 0);
  ASSERT_NE(read, nullptr) << importer.GetErrorString();
  ASSERT_EQ(read->mNumMeshes, 1u);  // PLY holds one vertex list
  const aiMesh& m = *read->mMeshes[0];
  const std::size_t nv = scene.object.vertices.size();
  ASSERT_EQ(m.mNumVertices, nv + scene.points.size() + 2 * kGlyphVertices);
  // Object vertices first, in order; then the points.
  for (std::size_t i = 0; i < nv; ++i) {
    const aiVector3D& v = m.mVertices[i];
    EXPECT_NEAR(v.x, scene.object.vertices[i].x(), 1e-6);
    EXPECT_NEAR(v.y, scene.object.vertices[i].y(), 1e-6);
    EXPECT_NEAR(v.z, scene.object.vertices[i].z(), 1e-6);
  }
  ASSERT_TRUE(m.HasVertexColors(0));
  for (std::size_t i = 0; i < scene.points.size(); ++i) {
    const aiVector3D& v = m.mVertices[nv + i];
    EXPECT_NEAR(v.x, scene.points[i].x(), 1e-6);
    EXPECT_NEAR(m.mColors[0][nv + i].r, scene.point_colors[i][0], 1e-2);
    EXPECT_NEAR(m.mColors[0][nv + i].b, scene.point_colors[i][2], 1e-2);
  }
  EXPECT_EQ(countFaces(m, 1), 57);  // one point per grasp
  EXPECT_EQ(countFaces(m, 3), static_cast<int>(scene.object.faces.size()) + 2 * 48);
  std::filesystem::remove(path);
}

TEST(MeshExportTest, GlbReadsBackAsNamedObjectGraspsAndGlyphs) {
  const ExportScene scene = makeScene(40);
  const std::string path = tempPath("scene.glb");
  exportScene(path, scene, SceneFormat::kGlb);
  Assimp::Importer importer;
  const aiScene* read = importer.ReadFile(path, 0);
  ASSERT_NE(read, nullptr) << importer.GetErrorString();
  ASSERT_EQ(read->mNumMeshes, 3u);
  const aiMesh* object = nullptr;
  const aiMesh* grasps = nullptr;
  const aiMesh* glyphs = nullptr;
  for (unsigned i = 0; i < read->mNumMeshes; ++i) {
    const std::string name = read->mMeshes[i]->mName.C_Str();
    if (name == "object") object = read->mMeshes[i];
    if (name == "grasps") grasps = read->mMeshes[i];
    if (name == "glyphs") glyphs = read->mMeshes[i];
  }
  ASSERT_TRUE(object && grasps && glyphs);
  EXPECT_EQ(object->mNumVertices, scene.object.vertices.size());
  EXPECT_EQ(object->mNumFaces, scene.object.faces.size());
  // glTF writing joins identical vertices; each grasp stays one POINTS primitive.
  EXPECT_EQ(grasps->mNumFaces, 40u);
  EXPECT_EQ(countFaces(*grasps, 1), 40);
  EXPECT_EQ(grasps->mPrimitiveTypes, static_cast<unsigned>(aiPrimitiveType_POINT));
  EXPECT_TRUE(grasps->HasVertexColors(0));
  EXPECT_EQ(glyphs->mNumVertices, 2u * kGlyphVertices);
  std::filesystem::remove(path);
}

TEST(MeshExportTest, BadInputGivesClearErrors) {
  ExportScene scene = makeScene(3);
  EXPECT_NE(errorMessage([&] {
              exportScene("/nonexistent/dir/x.ply", scene, SceneFormat::kPly);
            }).find("cannot export '/nonexistent/dir/x.ply'"),
            std::string::npos);
  scene.point_colors.pop_back();
  EXPECT_NE(errorMessage([&] { scene.validate(); }).find("3 points but 2 point colours"),
            std::string::npos);
  scene = makeScene(3);
  scene.object.faces[0][1] = 99;
  EXPECT_NE(errorMessage([&] { scene.validate(); }).find("object face 0 indexes vertex 99"),
            std::string::npos);
  EXPECT_NE(errorMessage([] { sceneFormatFromString("stl"); }).find("unknown scene format 'stl'"),
            std::string::npos);
  EXPECT_EQ(sceneFormatFromString("glb"), SceneFormat::kGlb);
  EXPECT_NE(errorMessage([] {
              exportScene(tempPath("e.ply"), ExportScene{}, SceneFormat::kPly);
            }).find("the scene is empty"),
            std::string::npos);
}

}  // namespace
}  // namespace taskmap
