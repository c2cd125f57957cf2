// Reading mesh files with assimp into a triangle soup (private to the meshes stage).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>
#include <string>
#include <system_error>
#include <unordered_map>

#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include "mesh_bounds.hpp"
#include "mesh_soup.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/input_file.hpp"

namespace taskmap::detail {
namespace {

struct PointKey {
  double x, y, z;
  bool operator==(const PointKey& o) const { return std::memcmp(this, &o, sizeof(PointKey)) == 0; }
};

struct PointKeyHash {
  std::size_t operator()(const PointKey& k) const {
    std::uint64_t h = 1469598103934665603ULL;
    const auto* bytes = reinterpret_cast<const unsigned char*>(&k);
    for (std::size_t i = 0; i < sizeof(PointKey); ++i) {
      h ^= bytes[i];
      h *= 1099511628211ULL;
    }
    return static_cast<std::size_t>(h);
  }
};

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

void appendMesh(const aiMesh& mesh, const aiMatrix4x4& transform, double scale, MeshSoup* soup) {
  const bool mirrored = transform.Determinant() < 0;
  const int base = static_cast<int>(soup->points.size());
  for (unsigned int v = 0; v < mesh.mNumVertices; ++v) {
    const aiVector3D p = transform * mesh.mVertices[v];
    soup->points.emplace_back(scale * static_cast<double>(p.x), scale * static_cast<double>(p.y),
                              scale * static_cast<double>(p.z));
  }
  for (unsigned int f = 0; f < mesh.mNumFaces; ++f) {
    const aiFace& face = mesh.mFaces[f];
    if (face.mNumIndices != 3) continue;  // points and lines are not part of a solid
    std::array<int, 3> tri{};
    bool ok = true;
    for (int c = 0; c < 3; ++c) {
      if (face.mIndices[c] >= mesh.mNumVertices) ok = false;
      tri[c] = base + static_cast<int>(face.mIndices[c]);
    }
    if (!ok) continue;
    if (mirrored) std::swap(tri[1], tri[2]);
    soup->faces.push_back(tri);
  }
}

void appendNode(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent,
                bool skip_own_transform, double scale, MeshSoup* soup, std::vector<bool>* used,
                int depth) {
  if (depth > 1000) return;  // cyclic or absurdly deep scene graph
  const aiMatrix4x4 transform = skip_own_transform ? parent : parent * node.mTransformation;
  for (unsigned int k = 0; k < node.mNumMeshes; ++k) {
    const unsigned int mesh_index = node.mMeshes[k];
    if (mesh_index >= scene.mNumMeshes || scene.mMeshes[mesh_index] == nullptr) continue;
    (*used)[mesh_index] = true;
    appendMesh(*scene.mMeshes[mesh_index], transform, scale, soup);
  }
  for (unsigned int c = 0; c < node.mNumChildren; ++c) {
    if (node.mChildren[c] != nullptr) {
      appendNode(scene, *node.mChildren[c], transform, false, scale, soup, used, depth + 1);
    }
  }
}

}  // namespace

std::size_t mergeIdenticalPoints(MeshSoup* soup) {
  std::unordered_map<PointKey, int, PointKeyHash> index;
  index.reserve(soup->points.size());
  std::vector<int> remap(soup->points.size());
  std::vector<Eigen::Vector3d> points;
  points.reserve(soup->points.size());
  for (std::size_t i = 0; i < soup->points.size(); ++i) {
    const Eigen::Vector3d& p = soup->points[i];
    // +0.0 and -0.0 are the same point.
    PointKey key{p.x() + 0.0, p.y() + 0.0, p.z() + 0.0};
    auto [it, inserted] = index.emplace(key, static_cast<int>(points.size()));
    if (inserted) points.push_back(p);
    remap[i] = it->second;
  }
  const std::size_t merged = soup->points.size() - points.size();
  for (auto& f : soup->faces) {
    for (int& v : f) v = remap[static_cast<std::size_t>(v)];
  }
  soup->points = std::move(points);
  return merged;
}

MeshSoup importMeshFile(const std::string& path, double scale, std::string* format) {
  namespace fs = std::filesystem;
  const std::string ext = lowerExtension(path);
  if (format != nullptr) *format = ext;
  std::error_code ec;
  if (!fs::exists(path, ec)) {
    throw Error("cannot open mesh file '" + path + "': no such file");
  }
  if (fs::is_directory(path, ec)) {
    throw Error("cannot open mesh file '" + path + "': it is a directory");
  }
  requireRegularFile(path, "mesh file");  // a FIFO would block the open below
  {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error("cannot open mesh file '" + path + "': permission denied or unreadable");
  }
  const auto size = fs::file_size(path, ec);
  if (ec) throw Error("cannot read mesh file '" + path + "': " + ec.message());
  if (size == 0) throw Error("mesh file '" + path + "' is empty");
  checkDeclaredSizes(path, ext, size);  // before assimp reserves what a header declares

  Assimp::Importer importer;  // no logger is created: assimp stays silent
  importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS,
                              aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS |
                                  aiComponent_COLORS | aiComponent_TEXCOORDS |
                                  aiComponent_BONEWEIGHTS | aiComponent_ANIMATIONS |
                                  aiComponent_TEXTURES | aiComponent_LIGHTS | aiComponent_CAMERAS);
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  // Two passes: read and validate, then (after making each mesh's primitive-type flags agree
  // with its faces: Debian's assimp aborts on an ai_assert when a truncated file leaves them
  // inconsistent) triangulate and strip what a solid does not need.
  const aiScene* scene = nullptr;
  try {
    scene = importer.ReadFile(path, aiProcess_ValidateDataStructure);
    if (scene != nullptr) {
      auto* writable = const_cast<aiScene*>(scene);
      for (unsigned int m = 0; m < writable->mNumMeshes; ++m) {
        aiMesh* mesh = writable->mMeshes[m];
        if (mesh == nullptr) continue;
        unsigned int types = 0;
        for (unsigned int f = 0; f < mesh->mNumFaces; ++f) {
          const unsigned int n = mesh->mFaces[f].mNumIndices;
          if (n == 0 || mesh->mFaces[f].mIndices == nullptr) {
            throw Error("cannot read mesh file '" + path + "': face " + std::to_string(f) +
                        " has no vertices (truncated or corrupt file)");
          }
          types |= n == 1   ? aiPrimitiveType_POINT
                   : n == 2 ? aiPrimitiveType_LINE
                   : n == 3 ? aiPrimitiveType_TRIANGLE
                            : aiPrimitiveType_POLYGON;
          for (unsigned int k = 0; k < n; ++k) {
            if (mesh->mFaces[f].mIndices[k] >= mesh->mNumVertices) {
              throw Error("cannot read mesh file '" + path + "': face " + std::to_string(f) +
                          " references a missing vertex (truncated or corrupt file)");
            }
          }
        }
        mesh->mPrimitiveTypes = types;
      }
      scene = importer.ApplyPostProcessing(aiProcess_Triangulate | aiProcess_RemoveComponent |
                                           aiProcess_SortByPType);
    }
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw;  // the bounded child names the memory limit
  } catch (const std::exception& e) {
    throw Error("cannot read mesh file '" + path + "': " + e.what());
  } catch (...) {
    throw Error("cannot read mesh file '" + path + "': the importer failed");
  }
  if (scene == nullptr) {
    std::string why = importer.GetErrorString();
    // assimp turns a failed allocation into an error string; the bounded child names the limit.
    if (why.find("bad_alloc") != std::string::npos) throw std::bad_alloc();
    if (why.empty()) why = "unknown format or malformed content";
    throw Error("cannot read mesh file '" + path + "': " + why);
  }
  if ((scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0 || scene->mNumMeshes == 0) {
    throw Error("mesh file '" + path + "' contains no triangle mesh");
  }

  MeshSoup soup;
  std::vector<bool> used(scene->mNumMeshes, false);
  if (scene->mRootNode != nullptr) {
    // COLLADA: assimp folds the file's <unit> into the root node transform; we keep file
    // coordinates (times --scale), so the root transform is skipped for .dae files.
    appendNode(*scene, *scene->mRootNode, aiMatrix4x4(), ext == "dae", scale, &soup, &used, 0);
  }
  if (std::none_of(used.begin(), used.end(), [](bool b) { return b; })) {
    // No node references a mesh: take every mesh untransformed.
    for (unsigned int i = 0; i < scene->mNumMeshes; ++i) {
      if (scene->mMeshes[i] != nullptr) appendMesh(*scene->mMeshes[i], aiMatrix4x4(), scale, &soup);
    }
  }
  if (soup.faces.empty()) {
    throw Error("mesh file '" + path + "' contains no triangles");
  }
  for (std::size_t i = 0; i < soup.points.size(); ++i) {
    if (!soup.points[i].allFinite()) {
      throw Error("mesh file '" + path + "': vertex " + std::to_string(i) +
                  " has a non-finite coordinate (NaN or infinity)");
    }
  }
  mergeIdenticalPoints(&soup);
  return soup;
}

}  // namespace taskmap::detail
