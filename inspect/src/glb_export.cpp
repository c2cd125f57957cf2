// GLB export of a trajectory (glTF 2.0 binary): JSON chunk written with nlohmann-json, one
// binary chunk holding every accessor's data (float32 positions, uint32 indices, keyframes).
#include "taskmap/inspect/glb_export.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <tuple>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "taskmap/core/atomic_file.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

constexpr int kFloat = 5126, kUnsignedInt = 5125;  // glTF componentType
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;
constexpr int kLatitudes = 8, kLongitudes = 16;  // sphere tessellation of the primitives
/// Materials by body role (robot, hand, environment), then the object.
const std::pair<const char*, std::array<double, 3>> kMaterials[] = {
    {"robot", {0.9, 0.45, 0.1}},
    {"hand", {0.2, 0.45, 0.85}},
    {"environment", {0.6, 0.6, 0.6}},
    {"object", {0.55, 0.35, 0.2}}};

/// A triangle mesh in one body's frame.
struct MeshData {
  std::vector<float> positions;  // x y z per vertex
  std::vector<std::uint32_t> indices;
};

/// One sphere-swept primitive (capsule or rectangle): a UV sphere of the sweep radius whose
/// vertices move by +-half_u along u and +-half_v along v with the sign of their u and v
/// coordinates. No vertex lies on u = 0 or v = 0 except the poles (half-step longitudes), so
/// the stretched triangles form the flat and cylindrical parts exactly.
void appendShape(const TrajectoryShape& s, MeshData& m) {
  const auto first = static_cast<std::uint32_t>(m.positions.size() / 3);
  const auto add = [&](double x, double y, double z) {
    const double sx = x > 0 ? 1.0 : x < 0 ? -1.0 : 0.0, sy = y > 0 ? 1.0 : y < 0 ? -1.0 : 0.0;
    const Eigen::Vector3d local(s.radius * x + sx * s.half_u, s.radius * y + sy * s.half_v,
                                s.radius * z);
    const Eigen::Vector3d p = s.center + s.axes * local;
    for (int k = 0; k < 3; ++k) m.positions.push_back(static_cast<float>(p[k]));
  };
  add(0, 0, 1);  // top pole
  for (int i = 0; i < kLatitudes; ++i) {
    const double theta = M_PI * (i + 0.5) / kLatitudes;
    for (int j = 0; j < kLongitudes; ++j) {
      const double phi = 2 * M_PI * (j + 0.5) / kLongitudes;
      add(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
    }
  }
  add(0, 0, -1);  // bottom pole
  const std::uint32_t bottom = first + 1 + kLatitudes * kLongitudes;
  const auto ring = [&](int i, int j) {
    return first + 1 + static_cast<std::uint32_t>(i * kLongitudes + (j % kLongitudes));
  };
  for (int j = 0; j < kLongitudes; ++j) {  // counter-clockwise seen from outside
    m.indices.insert(m.indices.end(), {first, ring(0, j), ring(0, j + 1)});
    for (int i = 0; i + 1 < kLatitudes; ++i) {
      m.indices.insert(m.indices.end(), {ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
      m.indices.insert(m.indices.end(), {ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
    }
    m.indices.insert(m.indices.end(),
                     {ring(kLatitudes - 1, j), bottom, ring(kLatitudes - 1, j + 1)});
  }
}

/// Accumulates the binary chunk and the bufferViews/accessors describing it.
class GltfBuilder {
 public:
  nlohmann::json json = {{"asset", {{"version", "2.0"}, {"generator", "taskmap export-glb"}}},
                         {"bufferViews", nlohmann::json::array()},
                         {"accessors", nlohmann::json::array()}};
  std::string bin;

  /// Float accessor of count elements of `type` ("SCALAR", "VEC3", "VEC4") with min/max.
  int floats(const std::vector<float>& v, const char* type, int width, int target = 0) {
    const std::size_t count = v.size() / static_cast<std::size_t>(width);
    std::vector<float> lo(static_cast<std::size_t>(width), INFINITY),
        hi(static_cast<std::size_t>(width), -INFINITY);
    for (std::size_t i = 0; i < v.size(); ++i) {
      const std::size_t k = i % static_cast<std::size_t>(width);
      lo[k] = std::min(lo[k], v[i]);
      hi[k] = std::max(hi[k], v[i]);
    }
    nlohmann::json a = {{"bufferView", view(v.data(), v.size() * sizeof(float), target)},
                        {"componentType", kFloat},
                        {"count", count},
                        {"type", type}};
    if (count > 0) {
      a["min"] = lo;
      a["max"] = hi;
    }
    json["accessors"].push_back(a);
    return static_cast<int>(json["accessors"].size()) - 1;
  }
  /// uint32 index accessor.
  int indices(const std::vector<std::uint32_t>& v) {
    json["accessors"].push_back(
        {{"bufferView", view(v.data(), v.size() * sizeof(std::uint32_t), kElementArrayBuffer)},
         {"componentType", kUnsignedInt},
         {"count", v.size()},
         {"type", "SCALAR"}});
    return static_cast<int>(json["accessors"].size()) - 1;
  }
  /// A mesh of one triangle primitive with material (kMaterials index); returns its index.
  int mesh(const std::string& name, const MeshData& m, int material) {
    const int pos = floats(m.positions, "VEC3", 3, kArrayBuffer), idx = indices(m.indices);
    json["meshes"].push_back({{"name", name},
                              {"primitives",
                               {{{"attributes", {{"POSITION", pos}}},
                                 {"indices", idx},
                                 {"material", material},
                                 {"mode", 4}}}}});
    return static_cast<int>(json["meshes"].size()) - 1;
  }

 private:
  int view(const void* data, std::size_t bytes, int target) {
    while (bin.size() % 4 != 0) bin.push_back('\0');
    nlohmann::json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}};
    if (target != 0) v["target"] = target;
    bin.append(static_cast<const char*>(data), bytes);
    json["bufferViews"].push_back(v);
    return static_cast<int>(json["bufferViews"].size()) - 1;
  }
};

nlohmann::json nodeAt(const std::string& name, const Pose& p) {
  const Eigen::Quaterniond q = p.orientation.normalized();
  return {{"name", name},
          {"translation", {p.position.x(), p.position.y(), p.position.z()}},
          {"rotation", {q.x(), q.y(), q.z(), q.w()}}};
}

/// One node per body (with its primitives' mesh) and the object mesh; returns node indices.
std::vector<int> addNodes(const TrajectoryRecord& r, GltfBuilder& g) {
  std::vector<MeshData> meshes(r.body_names.size());
  for (const TrajectoryShape& s : r.shapes)
    appendShape(s, meshes[static_cast<std::size_t>(s.body)]);
  std::vector<int> children;
  for (std::size_t b = 0; b < r.body_names.size(); ++b) {
    nlohmann::json node = nodeAt(r.body_names[b], r.bodyPose(0, b));
    if (!meshes[b].indices.empty())
      node["mesh"] = g.mesh(r.body_names[b], meshes[b], r.body_roles[b]);
    g.json["nodes"].push_back(node);
    children.push_back(static_cast<int>(g.json["nodes"].size()) - 1);
  }
  if (r.object_faces.rows() > 0) {
    MeshData m;
    for (Eigen::Index i = 0; i < r.object_vertices.rows(); ++i)
      for (int k = 0; k < 3; ++k)
        m.positions.push_back(static_cast<float>(r.object_vertices(i, k)));
    for (Eigen::Index i = 0; i < r.object_faces.rows(); ++i)
      for (int k = 0; k < 3; ++k)
        m.indices.push_back(static_cast<std::uint32_t>(r.object_faces(i, k)));
    nlohmann::json node = nodeAt("object_mesh", r.object_pose);
    node["mesh"] = g.mesh(r.object_name, m, 3);
    g.json["nodes"].push_back(node);
    children.push_back(static_cast<int>(g.json["nodes"].size()) - 1);
  }
  return children;
}

/// Animation "reach": translation and rotation channels of every robot and hand body.
void addAnimation(const TrajectoryRecord& r, GltfBuilder& g) {
  std::vector<float> times;
  for (std::size_t t = 0; t < r.rows(); ++t) times.push_back(static_cast<float>(t * r.dt));
  const int input = g.floats(times, "SCALAR", 1);
  nlohmann::json samplers = nlohmann::json::array(), channels = nlohmann::json::array();
  for (std::size_t b = 0; b < r.body_names.size(); ++b) {
    if (r.body_roles[b] == 2) continue;  // environment bodies do not move
    std::vector<float> translation, rotation;
    for (std::size_t t = 0; t < r.rows(); ++t) {
      const Pose p = r.bodyPose(t, b);
      const Eigen::Quaterniond q = p.orientation.normalized();
      for (int k = 0; k < 3; ++k) translation.push_back(static_cast<float>(p.position[k]));
      for (double c : {q.x(), q.y(), q.z(), q.w()}) rotation.push_back(static_cast<float>(c));
    }
    const int node = static_cast<int>(b);
    for (const auto& [path, data, type, width] :
         {std::make_tuple("translation", &translation, "VEC3", 3),
          std::make_tuple("rotation", &rotation, "VEC4", 4)}) {
      samplers.push_back({{"input", input},
                          {"output", g.floats(*data, type, width)},
                          {"interpolation", "LINEAR"}});
      channels.push_back(
          {{"sampler", samplers.size() - 1}, {"target", {{"node", node}, {"path", path}}}});
    }
  }
  if (!channels.empty())
    g.json["animations"] = {{{"name", "reach"}, {"samplers", samplers}, {"channels", channels}}};
}

void appendU32(std::string& out, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) out.push_back(static_cast<char>((v >> (8 * k)) & 0xff));
}

}  // namespace

std::string glbBytes(const TrajectoryRecord& record) {
  record.validate();
  GltfBuilder g;
  g.json["nodes"] = nlohmann::json::array();
  g.json["meshes"] = nlohmann::json::array();
  g.json["materials"] = nlohmann::json::array();
  for (const auto& [name, rgb] : kMaterials)
    g.json["materials"].push_back(
        {{"name", name},
         {"pbrMetallicRoughness",
          {{"baseColorFactor", {rgb[0], rgb[1], rgb[2], 1.0}}, {"metallicFactor", 0.0}}}});
  const std::vector<int> children = addNodes(record, g);
  const double s = std::sqrt(0.5);
  g.json["nodes"].push_back(
      {{"name", "world"}, {"rotation", {-s, 0.0, 0.0, s}}, {"children", children}});
  const int root = static_cast<int>(g.json["nodes"].size()) - 1;
  g.json["scenes"] = {{{"name", "reach"}, {"nodes", {root}}}};
  g.json["scene"] = 0;
  addAnimation(record, g);
  while (g.bin.size() % 4 != 0) g.bin.push_back('\0');
  g.json["buffers"] = {{{"byteLength", g.bin.size()}}};
  std::string text = g.json.dump();
  while (text.size() % 4 != 0) text.push_back(' ');
  std::string out = "glTF";
  appendU32(out, 2);
  appendU32(out, static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + g.bin.size()));
  appendU32(out, static_cast<std::uint32_t>(text.size()));
  out += "JSON";
  out += text;
  appendU32(out, static_cast<std::uint32_t>(g.bin.size()));
  out.append("BIN\0", 4);
  out += g.bin;
  return out;
}

void writeGlb(const TrajectoryRecord& record, const std::string& path) {
  writeFileAtomically(path, glbBytes(record), "cannot write GLB '" + path + "'");
}

}  // namespace taskmap
