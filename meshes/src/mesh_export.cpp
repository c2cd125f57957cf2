#include "taskmap/meshes/mesh_export.hpp"

#include <cmath>
#include <filesystem>
#include <memory>
#include <system_error>

#include <unistd.h>

#include <assimp/material.h>
#include <assimp/scene.h>
#include <assimp/Exporter.hpp>

#include "taskmap/core/atomic_file.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

// An axis-aligned box [lo, hi] as 8 vertices and 12 outward triangles appended to mesh.
void appendBox(TriangleMesh& mesh, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const int base = static_cast<int>(mesh.vertices.size());
  for (int i = 0; i < 8; ++i) {
    mesh.vertices.emplace_back((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(),
                               (i & 4) ? hi.z() : lo.z());
  }
  // Faces of the unit cube with vertex index bits (x, y, z), counter-clockwise from outside.
  static constexpr int kQuads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                       {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : kQuads) {
    mesh.faces.emplace_back(base + q[0], base + q[1], base + q[2]);
    mesh.faces.emplace_back(base + q[0], base + q[2], base + q[3]);
  }
}

bool finite(const Rgba& c) {
  return c.allFinite();
}

aiColor4D toAi(const Rgba& c) {
  return aiColor4D(c[0], c[1], c[2], c[3]);
}

// A mesh owned by the scene being assembled: vertices, colours and faces of n indices.
aiMesh* makeMesh(const char* name, const std::vector<Eigen::Vector3d>& vertices,
                 const std::vector<Rgba>& colors, const std::vector<std::vector<unsigned>>& faces,
                 unsigned primitive, unsigned material) {
  auto mesh = std::make_unique<aiMesh>();
  mesh->mName = aiString(name);
  mesh->mMaterialIndex = material;
  mesh->mPrimitiveTypes = primitive;
  mesh->mNumVertices = static_cast<unsigned>(vertices.size());
  mesh->mVertices = new aiVector3D[vertices.size()];
  mesh->mColors[0] = new aiColor4D[vertices.size()];
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    mesh->mVertices[i] =
        aiVector3D(static_cast<ai_real>(vertices[i].x()), static_cast<ai_real>(vertices[i].y()),
                   static_cast<ai_real>(vertices[i].z()));
    mesh->mColors[0][i] = toAi(colors[i]);
  }
  mesh->mNumFaces = static_cast<unsigned>(faces.size());
  mesh->mFaces = new aiFace[faces.size()];
  for (std::size_t f = 0; f < faces.size(); ++f) {
    aiFace& face = mesh->mFaces[f];
    face.mNumIndices = static_cast<unsigned>(faces[f].size());
    face.mIndices = new unsigned[faces[f].size()];
    for (std::size_t k = 0; k < faces[f].size(); ++k) face.mIndices[k] = faces[f][k];
  }
  return mesh.release();
}

aiMaterial* makeMaterial(const char* name, const Rgba& color) {
  auto material = std::make_unique<aiMaterial>();
  aiString n(name);
  material->AddProperty(&n, AI_MATKEY_NAME);
  const aiColor4D c = toAi(color);
  material->AddProperty(&c, 1, AI_MATKEY_COLOR_DIFFUSE);
  material->AddProperty(&c, 1, AI_MATKEY_BASE_COLOR);
  return material.release();
}

}  // namespace

SceneFormat sceneFormatFromString(const std::string& name) {
  if (name == "ply") return SceneFormat::kPly;
  if (name == "glb") return SceneFormat::kGlb;
  throw Error("unknown scene format '" + name + "'; use ply or glb");
}

void ExportScene::validate() const {
  const auto nv = static_cast<int>(object.vertices.size());
  for (std::size_t i = 0; i < object.vertices.size(); ++i) {
    if (!object.vertices[i].allFinite()) {
      throw Error("export scene: object vertex " + std::to_string(i) + " is not finite");
    }
  }
  for (std::size_t f = 0; f < object.faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      if (object.faces[f][k] < 0 || object.faces[f][k] >= nv) {
        throw Error("export scene: object face " + std::to_string(f) + " indexes vertex " +
                    std::to_string(object.faces[f][k]) + " of " + std::to_string(nv));
      }
    }
  }
  if (point_colors.size() != points.size()) {
    throw Error("export scene: " + std::to_string(points.size()) + " points but " +
                std::to_string(point_colors.size()) + " point colours; give one colour per point");
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite() || !finite(point_colors[i])) {
      throw Error("export scene: point " + std::to_string(i) + " is not finite");
    }
  }
  for (std::size_t i = 0; i < glyphs.size(); ++i) {
    if (!glyphs[i].pose.matrix().allFinite() || !finite(glyphs[i].color)) {
      throw Error("export scene: glyph " + std::to_string(i) + " is not finite");
    }
  }
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const ScenePart& part = parts[i];
    const auto n = static_cast<int>(part.mesh.vertices.size());
    bool ok = finite(part.color) && !part.mesh.faces.empty();
    for (const auto& v : part.mesh.vertices) ok = ok && v.allFinite();
    for (const auto& f : part.mesh.faces) ok = ok && f.minCoeff() >= 0 && f.maxCoeff() < n;
    if (!ok) {
      throw Error("export scene: part " + std::to_string(i) + " ('" + part.name +
                  "') is empty, not finite or indexes a missing vertex");
    }
  }
  if (!finite(object_color)) throw Error("export scene: object colour is not finite");
  if (!(glyph_size > 0) || !std::isfinite(glyph_size)) {
    throw Error("export scene: glyph_size must be a positive length in metres");
  }
}

TriangleMesh handGlyphMesh(double size) {
  // Palm plate in the xy plane (z in [-t, 0]), three fingers rising along +z from its top:
  // two on one side, one opposite (a three-finger hand seen from the object).
  const double s = size;
  const double t = 0.08 * s;  // plate thickness and finger width
  TriangleMesh mesh;
  appendBox(mesh, {-0.35 * s, -0.25 * s, -t}, {0.35 * s, 0.25 * s, 0.0});
  appendBox(mesh, {-0.30 * s, 0.20 * s - t, 0.0}, {-0.30 * s + t, 0.20 * s, s});
  appendBox(mesh, {0.30 * s - t, 0.20 * s - t, 0.0}, {0.30 * s, 0.20 * s, s});
  appendBox(mesh, {-0.5 * t, -0.20 * s, 0.0}, {0.5 * t, -0.20 * s + t, s});
  return mesh;
}

void exportScene(const std::string& path, const ExportScene& scene, SceneFormat format) {
  scene.validate();
  auto ai = std::make_unique<aiScene>();
  ai->mRootNode = new aiNode(scene.name);

  std::vector<aiMesh*> meshes;
  std::vector<aiMaterial*> materials;
  // Object.
  {
    std::vector<Rgba> colors(scene.object.vertices.size(), scene.object_color);
    std::vector<std::vector<unsigned>> faces;
    faces.reserve(scene.object.faces.size());
    for (const auto& f : scene.object.faces) {
      faces.push_back(
          {static_cast<unsigned>(f[0]), static_cast<unsigned>(f[1]), static_cast<unsigned>(f[2])});
    }
    if (!faces.empty()) {
      materials.push_back(makeMaterial("object", scene.object_color));
      meshes.push_back(makeMesh("object", scene.object.vertices, colors, faces,
                                aiPrimitiveType_TRIANGLE,
                                static_cast<unsigned>(materials.size() - 1)));
    }
  }
  // Points, one one-index face each.
  if (!scene.points.empty()) {
    std::vector<std::vector<unsigned>> faces(scene.points.size());
    for (std::size_t i = 0; i < faces.size(); ++i) faces[i] = {static_cast<unsigned>(i)};
    materials.push_back(makeMaterial("grasps", Rgba(1.0f, 1.0f, 1.0f, 1.0f)));
    meshes.push_back(makeMesh("grasps", scene.points, scene.point_colors, faces,
                              aiPrimitiveType_POINT, static_cast<unsigned>(materials.size() - 1)));
  }
  // Glyphs, baked into object coordinates.
  if (!scene.glyphs.empty()) {
    const TriangleMesh glyph = handGlyphMesh(scene.glyph_size);
    std::vector<Eigen::Vector3d> vertices;
    std::vector<Rgba> colors;
    std::vector<std::vector<unsigned>> faces;
    for (const SceneGlyph& g : scene.glyphs) {
      const auto base = static_cast<unsigned>(vertices.size());
      for (const auto& v : glyph.vertices) {
        vertices.push_back(g.pose * v);
        colors.push_back(g.color);
      }
      for (const auto& f : glyph.faces) {
        faces.push_back({base + static_cast<unsigned>(f[0]), base + static_cast<unsigned>(f[1]),
                         base + static_cast<unsigned>(f[2])});
      }
    }
    materials.push_back(makeMaterial("glyphs", scene.glyphs.front().color));
    meshes.push_back(makeMesh("glyphs", vertices, colors, faces, aiPrimitiveType_TRIANGLE,
                              static_cast<unsigned>(materials.size() - 1)));
  }
  // Parts (e.g. hand links at the representatives), one mesh each.
  for (const ScenePart& part : scene.parts) {
    std::vector<std::vector<unsigned>> faces;
    faces.reserve(part.mesh.faces.size());
    for (const auto& f : part.mesh.faces) {
      faces.push_back(
          {static_cast<unsigned>(f[0]), static_cast<unsigned>(f[1]), static_cast<unsigned>(f[2])});
    }
    materials.push_back(makeMaterial(part.name.c_str(), part.color));
    meshes.push_back(makeMesh(part.name.c_str(), part.mesh.vertices,
                              std::vector<Rgba>(part.mesh.vertices.size(), part.color), faces,
                              aiPrimitiveType_TRIANGLE,
                              static_cast<unsigned>(materials.size() - 1)));
  }
  if (meshes.empty()) throw Error("cannot export '" + path + "': the scene is empty");

  ai->mNumMeshes = static_cast<unsigned>(meshes.size());
  ai->mMeshes = new aiMesh*[meshes.size()];
  ai->mNumMaterials = static_cast<unsigned>(materials.size());
  ai->mMaterials = new aiMaterial*[materials.size()];
  for (std::size_t i = 0; i < materials.size(); ++i) ai->mMaterials[i] = materials[i];
  // One child node per mesh so that viewers list the parts by name.
  ai->mRootNode->mNumChildren = static_cast<unsigned>(meshes.size());
  ai->mRootNode->mChildren = new aiNode*[meshes.size()];
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    ai->mMeshes[i] = meshes[i];
    aiNode* node = new aiNode(meshes[i]->mName.C_Str());
    node->mParent = ai->mRootNode;
    node->mNumMeshes = 1;
    node->mMeshes = new unsigned[1]{static_cast<unsigned>(i)};
    ai->mRootNode->mChildren[i] = node;
  }

  const char* format_id = format == SceneFormat::kPly ? "ply" : "glb2";
  const std::string tmp = path + ".tmp" + std::to_string(::getpid());
  Assimp::Exporter exporter;
  if (exporter.Export(ai.get(), format_id, tmp) != AI_SUCCESS) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw Error("cannot export '" + path + "': " + exporter.GetErrorString() +
                "; check that the directory exists and is writable");
  }
  commitTemporaryFile(tmp, path, "cannot export '" + path + "'");
}

}  // namespace taskmap
