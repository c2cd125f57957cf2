// A URDF <mesh> collision element as convex shapes: assimp reads the file, its faces are split
// into connected parts (faces sharing a vertex position), and each part becomes its qhull hull
// or, when clearly non-convex (volume below (1 - convex_tolerance) of the hull's), the merged
// pieces of an exact convex decomposition (of its alpha wrap when the part is not a clean
// solid); a failed decomposition falls back to the hull and says why.
#include "collision_mesh.hpp"
#include "bounded_load.hpp"

#include <array>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <set>

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <Eigen/Geometry>
#include <assimp/Importer.hpp>

#include "convex_decomposition.hpp"
#include "mesh_soup.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/input_file.hpp"
#include "taskmap/meshes/ros_package.hpp"

namespace taskmap::detail {
namespace {

namespace fs = std::filesystem;

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

/// True when every edge is used once in each direction (closed, consistently oriented).
bool closedOriented(const MeshSoup& soup) {
  std::map<std::pair<int, int>, int> uses;
  for (const auto& f : soup.faces)
    for (int c = 0; c < 3; ++c) ++uses[{f[static_cast<std::size_t>(c)], f[(c + 1) % 3]}];
  for (const auto& [e, n] : uses) {
    const auto it = uses.find({e.second, e.first});
    if (n != 1 || it == uses.end() || it->second != 1) return false;
  }
  return !soup.faces.empty();
}

/// Decomposes `part`; when it is not a clean solid (open, non-manifold, self-intersecting) and
/// options allow, decomposes its alpha wrap instead (alpha = diagonal / 30, offset = diagonal /
/// 1000: a closed surface just outside the part). Throws Error when neither works.
ConvexPieces decomposeOrWrap(const MeshSoup& part, const CollisionOptions& o,
                             const std::string& what, CollisionMeshInfo* info) {
  DecompositionLimits limits;
  limits.max_pieces = o.max_pieces;
  limits.max_faces = o.max_faces;
  try {
    return decomposeClosedMesh(part, limits, what);
  } catch (const Error& e) {
    if (!o.wrap) throw;
    Eigen::AlignedBox3d box;
    for (const auto& p : part.points) box.extend(p);
    const double d = box.diagonal().norm();
    const MeshSoup wrapped = alphaWrap(part, d / 30.0, d / 1000.0, what);
    try {
      ConvexPieces out = decomposeClosedMesh(wrapped, limits, "its alpha wrap");
      info->wrapped = true;
      info->note = std::string(e.what()) + "; decomposed its alpha wrap";
      return out;
    } catch (const Error& e2) {
      throw Error(std::string(e.what()) + "; " + e2.what());
    }
  }
}

}  // namespace

PartShapes partShapes(MeshSoup part, const CollisionOptions& o, const std::string& what) {
  PartShapes out;
  PointHull hull = convexHull(part.points, what);
  dropBadFaces(&part);
  out.info.faces = static_cast<int>(part.faces.size());
  out.info.hull_volume = hull.volume;
  const bool closed = closedOriented(part);
  out.info.mesh_volume = closed ? std::abs(soupVolume(part)) : 0.0;
  const bool convex = out.info.mesh_volume >= (1.0 - o.convex_tolerance) * hull.volume;
  if (!o.decompose || (closed && convex)) {
    out.info.note = !o.decompose ? "decomposition off" : "nearly convex";
  } else {
    try {
      ConvexPieces d = decomposeOrWrap(part, o, what, &out.info);
      out.info.raw_pieces = d.raw_pieces;
      out.pieces = std::move(d.pieces);
      out.info.decomposed = true;
    } catch (const Error& e) {
      out.info.note = std::string(e.what()) + "; its convex hull is used";
      out.info.warning = true;
    }
  }
  if (out.pieces.empty()) out.pieces.push_back(std::move(hull));
  out.info.pieces = static_cast<int>(out.pieces.size());
  for (const auto& p : out.pieces) out.info.pieces_volume += p.volume;
  return out;
}

CollisionOptions collisionOptionsOf(const nlohmann::json& sidecar, const std::string& where) {
  CollisionOptions o;
  if (!sidecar.is_object() || !sidecar.contains("collision")) return o;
  const nlohmann::json& c = sidecar["collision"];
  const std::string W = where + "collision";
  if (!c.is_object()) throw Error(W + " must be an object (see meshes/hands/README.md)");
  static const std::set<std::string> kKeys = {"decompose", "max_pieces", "max_faces",
                                              "convex_tolerance", "wrap"};
  for (auto it = c.begin(); it != c.end(); ++it)
    if (!kKeys.count(it.key())) throw Error(W + ": unknown key '" + it.key() + "'");
  if (c.contains("decompose")) {
    if (!c["decompose"].is_boolean()) throw Error(W + ".decompose must be true or false");
    o.decompose = c["decompose"].get<bool>();
  }
  if (c.contains("wrap")) {
    if (!c["wrap"].is_boolean()) throw Error(W + ".wrap must be true or false");
    o.wrap = c["wrap"].get<bool>();
  }
  auto integer = [&](const char* key, int lo, int hi, int* out) {
    if (!c.contains(key)) return;
    if (!c[key].is_number_integer() || c[key].get<long long>() < lo || c[key].get<long long>() > hi)
      throw Error(W + "." + key + " must be an integer in [" + std::to_string(lo) + ", " +
                  std::to_string(hi) + "]");
    *out = c[key].get<int>();
  };
  integer("max_pieces", 1, 64, &o.max_pieces);
  integer("max_faces", 50, 5000, &o.max_faces);
  if (c.contains("convex_tolerance")) {
    const auto& t = c["convex_tolerance"];
    if (!t.is_number() || !(t.get<double>() >= 0.0 && t.get<double>() < 1.0))
      throw Error(W + ".convex_tolerance must be a number in [0, 1)");
    o.convex_tolerance = t.get<double>();
  }
  return o;
}

std::vector<PartShapes> collisionMeshShapes(const std::string& file, const Eigen::Vector3d& scale,
                                            const std::string& urdf_path, const std::string& link,
                                            const CollisionOptions& options,
                                            const std::string& format) {
  const std::string L = format + " '" + urdf_path + "': link '" + link + "'";
  std::string f = file;
  if (f.rfind("file://", 0) == 0) f = f.substr(7);
  f = resolvePackageUri(f, urdf_path, L + ": collision mesh ");
  fs::path p(f);
  if (p.is_relative()) p = fs::path(urdf_path).parent_path() / p;
  requireRegularFile(p.string(), L + ": collision mesh");
  {
    // A trial parse in a child with memory and CPU limits first (bounded_load.hpp): a file
    // that crashes or exhausts assimp is refused; one that passed is read here the same way.
    std::error_code ec;
    const auto bytes = fs::file_size(p, ec);
    runBounded(
        [&p]() {
          Assimp::Importer trial;
          if (trial.ReadFile(p.string(), aiProcess_Triangulate) == nullptr)
            throw Error(std::string("unreadable: ") + trial.GetErrorString());
          return std::string();
        },
        ec ? 0 : bytes, L + ": collision mesh '" + p.string() + "'");
  }
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(p.string(), aiProcess_Triangulate);
  if (!scene || scene->mNumMeshes == 0)
    throw Error(L + ": cannot read collision mesh '" + p.string() +
                "': " + importer.GetErrorString());
  std::vector<MeshSoup> parts;
  std::function<void(const aiNode*, const aiMatrix4x4&)> walk = [&](const aiNode* node,
                                                                    const aiMatrix4x4& parent) {
    const aiMatrix4x4 t = parent * node->mTransformation;
    for (unsigned m = 0; m < node->mNumMeshes; ++m)
      splitParts(*scene->mMeshes[node->mMeshes[m]], t, scale, &parts);
    for (unsigned c = 0; c < node->mNumChildren; ++c) walk(node->mChildren[c], t);
  };
  walk(scene->mRootNode, aiMatrix4x4());
  std::vector<PartShapes> out;
  for (auto& part : parts) {
    mergeIdenticalPoints(&part);
    // Parts of fewer than 4 distinct vertices enclose nothing (stray edges, lone triangles).
    if (part.points.size() < 4) continue;
    out.push_back(partShapes(std::move(part), options,
                             L + ": collision mesh '" + file + "' (a connected part)"));
    out.back().info.part = static_cast<int>(out.size()) - 1;
  }
  if (out.empty())
    throw Error(L + ": collision mesh '" + p.string() + "' has fewer than 4 vertices");
  return out;
}

}  // namespace taskmap::detail
