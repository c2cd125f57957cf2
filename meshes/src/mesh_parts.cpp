// A mesh file as connected parts (mesh_parts.hpp): assimp reads the file (a trial parse in a
// bounded child first), its faces are split into connected parts (faces sharing a vertex
// position), identical points merged.
#include "taskmap/meshes/mesh_parts.hpp"

#include <array>
#include <filesystem>
#include <functional>
#include <map>

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include "mesh_soup.hpp"
#include "taskmap/core/bounded_child.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/input_file.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;
using detail::MeshSoup;

/// Splits one assimp mesh (transform `t`, then `scale`) into connected parts appended to
/// `parts`: vertices at the same position are one, faces sharing a vertex are connected.
void splitParts(const aiMesh& mesh, const aiMatrix4x4& t, const Eigen::Vector3d& scale,
                std::vector<MeshSoup>* parts) {
  std::vector<unsigned> weld(mesh.mNumVertices);
  std::map<std::array<float, 3>, unsigned> at;
  for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
    const aiVector3D& a = mesh.mVertices[v];
    weld[v] = at.emplace(std::array<float, 3>{a.x, a.y, a.z}, v).first->second;
  }
  std::vector<unsigned> root(mesh.mNumVertices);
  for (unsigned v = 0; v < mesh.mNumVertices; ++v) root[v] = v;
  std::function<unsigned(unsigned)> find = [&](unsigned v) {
    while (root[v] != v) v = root[v] = root[root[v]];
    return v;
  };
  for (unsigned fi = 0; fi < mesh.mNumFaces; ++fi) {
    const aiFace& face = mesh.mFaces[fi];
    for (unsigned c = 1; c < face.mNumIndices; ++c)
      root[find(weld[face.mIndices[c]])] = find(weld[face.mIndices[0]]);
  }
  std::map<unsigned, std::size_t> part_of_root;   // welded root -> index into parts
  std::vector<int> index(mesh.mNumVertices, -1);  // welded vertex -> index in its part
  for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
    if (weld[v] != v) continue;
    const auto [it, fresh] = part_of_root.emplace(find(v), parts->size());
    if (fresh) parts->emplace_back();
    MeshSoup& part = (*parts)[it->second];
    const aiVector3D a = t * mesh.mVertices[v];
    index[v] = static_cast<int>(part.points.size());
    part.points.emplace_back(a.x * scale.x(), a.y * scale.y(), a.z * scale.z());
  }
  for (unsigned fi = 0; fi < mesh.mNumFaces; ++fi) {
    const aiFace& face = mesh.mFaces[fi];
    if (face.mNumIndices != 3) continue;  // points and lines enclose nothing
    MeshSoup& part = (*parts)[part_of_root.at(find(weld[face.mIndices[0]]))];
    part.faces.push_back({index[weld[face.mIndices[0]]], index[weld[face.mIndices[1]]],
                          index[weld[face.mIndices[2]]]});
  }
}

}  // namespace

std::vector<TriangleMesh> loadMeshParts(const std::string& path, const Eigen::Vector3d& scale,
                                        const std::string& what) {
  requireRegularFile(path, what);
  const std::string named = what + " '" + path + "'";
  {
    // A trial parse in a child with memory and CPU limits first (core's bounded_child.hpp): a
    // file that crashes or exhausts assimp is refused; one that passed is read here the same way.
    std::error_code ec;
    const auto bytes = fs::file_size(path, ec);
    runBounded(
        [&path]() {
          Assimp::Importer trial;
          if (trial.ReadFile(path, aiProcess_Triangulate) == nullptr)
            throw Error(std::string("unreadable: ") + trial.GetErrorString());
          return std::string();
        },
        ec ? 0 : bytes, named);
  }
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path, aiProcess_Triangulate);
  if (!scene || scene->mNumMeshes == 0)
    throw Error(named + ": unreadable: " + importer.GetErrorString());
  std::vector<MeshSoup> parts;
  std::function<void(const aiNode*, const aiMatrix4x4&)> walk = [&](const aiNode* node,
                                                                    const aiMatrix4x4& parent) {
    const aiMatrix4x4 t = parent * node->mTransformation;
    for (unsigned m = 0; m < node->mNumMeshes; ++m)
      splitParts(*scene->mMeshes[node->mMeshes[m]], t, scale, &parts);
    for (unsigned c = 0; c < node->mNumChildren; ++c) walk(node->mChildren[c], t);
  };
  walk(scene->mRootNode, aiMatrix4x4());
  std::vector<TriangleMesh> out;
  for (auto& part : parts) {
    detail::mergeIdenticalPoints(&part);
    if (part.points.size() < 4) continue;  // encloses nothing
    TriangleMesh m;
    m.vertices = std::move(part.points);
    m.faces.reserve(part.faces.size());
    for (const auto& f : part.faces) m.faces.emplace_back(f[0], f[1], f[2]);
    out.push_back(std::move(m));
  }
  return out;
}

}  // namespace taskmap
