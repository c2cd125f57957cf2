// A URDF <mesh> collision element as convex shapes: meshes' loadMeshParts reads the file (assimp
// in a bounded child) as connected parts, and meshes' convexPieces makes each part its qhull hull
// or, when clearly non-convex, the merged pieces of an exact convex decomposition; the sidecar's
// "collision" object chooses how.
#include "collision_mesh.hpp"

#include <filesystem>
#include <set>

#include "taskmap/core/error.hpp"
#include "taskmap/hands/ros_package.hpp"
#include "taskmap/meshes/mesh_parts.hpp"

namespace taskmap::detail {
namespace {

namespace fs = std::filesystem;

/// One connected part as convex pieces, with how they were made.
PartShapes partShapes(const TriangleMesh& part, const CollisionOptions& o,
                      const std::string& what) {
  ConvexPieces c = convexPieces(part, o, what);
  PartShapes out;
  for (std::size_t i = 0; i < c.pieces.size(); ++i)
    out.pieces.push_back(PointHull{std::move(c.pieces[i]), c.piece_volumes[i]});
  CollisionMeshInfo& info = out.info;
  info.pieces = static_cast<int>(out.pieces.size());
  info.decomposed = c.decomposed;
  info.wrapped = c.wrapped;
  info.mesh_volume = c.mesh_volume;
  info.hull_volume = c.hull_volume;
  info.pieces_volume = c.pieces_volume;
  info.faces = c.faces;
  info.raw_pieces = c.raw_pieces;
  info.note = std::move(c.note);
  info.warning = c.failed;
  return out;
}

}  // namespace

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
  std::vector<PartShapes> out;
  for (const auto& part : loadMeshParts(p.string(), scale, L + ": collision mesh")) {
    out.push_back(
        partShapes(part, options, L + ": collision mesh '" + file + "' (a connected part)"));
    out.back().info.part = static_cast<int>(out.size()) - 1;
  }
  if (out.empty())
    throw Error(L + ": collision mesh '" + p.string() + "' has fewer than 4 vertices");
  return out;
}

}  // namespace taskmap::detail
