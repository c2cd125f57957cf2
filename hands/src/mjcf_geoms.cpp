// MJCF geoms as collision shapes (mjcf_reader.hpp): which geoms collide (contype, conaffinity),
// their frames (pos and orientation, or fromto), sizes per type, mesh assets, and the contact
// parameters they state (friction, solref, solimp).
#include <algorithm>
#include <filesystem>

#include "mjcf_reader.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap::detail {

namespace fs = std::filesystem;

const MjcfMesh& MjcfReader::meshOf(const TiXmlElement* g, int cls) const {
  const auto name = find(g, "geom", cls, "mesh");
  if (!name) doc_.fail(g, "a mesh geom needs a mesh attribute");
  const auto it = meshes_.find(name->text);
  if (it == meshes_.end())
    doc_.fail(g, "names mesh '" + name->text + "', which no <asset><mesh> defines");
  return it->second;
}

void MjcfReader::addGeom(const TiXmlElement* g, const Scope& scope, const Eigen::Isometry3d& frame,
                         int inherited) {
  const int cls = defaults_.classOf(g, inherited);
  const auto type_attr = find(g, "geom", cls, "type");
  const std::string type = type_attr ? type_attr->text : "sphere";
  const bool collides =
      number(g, "geom", cls, "contype", 1) != 0 || number(g, "geom", cls, "conaffinity", 1) != 0;
  if (!collides) {  // visual: grasping never needs it; a missing mesh file is only a warning
    if (type != "mesh") return;
    const MjcfMesh& mesh = meshOf(g, cls);
    std::error_code ec;
    const fs::path file = (fs::path(doc_.path()).parent_path() / mesh.file).lexically_normal();
    if (!mesh.file.empty() && !fs::exists(file, ec) && missing_visual_.insert(mesh.file).second)
      out_.warnings.push_back(doc_.where(g) + ": visual mesh '" + file.string() +
                              "' is missing; ignored (taskmap needs collision geometry only)");
    return;
  }
  UrdfShape shape;
  geomShape(g, cls, type, &shape);
  shape.origin = scope.in_link * frame * shape.origin;
  const auto link = static_cast<std::size_t>(scope.link);
  out_.tree.links[link].collisions.push_back(std::move(shape));
  out_.dynamics.shapes[link].push_back(geomContact(g, cls));
}

void MjcfReader::geomShape(const TiXmlElement* g, int cls, const std::string& type,
                           UrdfShape* shape) {
  // Frame: fromto (the segment's midpoint, z along it) or pos and orientation.
  double half = -1.0;  // half the fromto segment's length
  if (auto ft = find(g, "geom", cls, "fromto")) {
    const auto v = mjcfNumbers(doc_, *ft, "fromto", 6, 6);
    const Eigen::Vector3d a(v[0], v[1], v[2]), b(v[3], v[4], v[5]);
    if (!((b - a).norm() > 1e-12)) doc_.fail(ft->at, "fromto's two points coincide");
    half = 0.5 * (b - a).norm();
    shape->origin.translation() = 0.5 * (a + b);
    // z from `to` toward `from`, as MuJoCo's compiler turns it (the same solid either way).
    shape->origin.linear() = mjcfZToDirection(a - b).toRotationMatrix();
  } else {
    if (auto p = find(g, "geom", cls, "pos")) {
      const auto v = mjcfNumbers(doc_, *p, "pos", 3, 3);
      shape->origin.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
    }
    shape->origin.linear() =
        mjcfOrientation(doc_, defaults_, compiler_, g, {"geom"}, cls).toRotationMatrix();
  }
  std::vector<double> size(3, 0.0);
  const auto given = components(g, "geom", cls, "size", 3);
  for (std::size_t k = 0; k < 3; ++k) size[k] = given[k].value_or(0.0);
  UrdfGeometry& out = shape->geometry;
  auto positive = [&](double v, const char* what) {
    if (!(v > 0.0)) doc_.fail(g, std::string("a ") + type + " geom needs a positive " + what);
    return v;
  };
  if (type != "mesh" && find(g, "geom", cls, "mesh"))
    doc_.fail(g, "a " + type + " fitted to a mesh is not supported: give its size");
  if (type == "sphere") {
    out.type = UrdfGeometry::Type::kSphere;
    out.radius = positive(size[0], "radius (size)");
  } else if (type == "capsule" || type == "cylinder") {
    out.type = type == "capsule" ? UrdfGeometry::Type::kCapsule : UrdfGeometry::Type::kCylinder;
    out.radius = positive(size[0], "radius (size[0])");
    out.length = 2.0 * positive(half >= 0.0 ? half : size[1], "half-length (size[1] or fromto)");
  } else if (type == "box" || type == "ellipsoid") {
    const Eigen::Vector3d h(positive(size[0], "size[0]"), positive(size[1], "size[1]"),
                            positive(half >= 0.0 ? half : size[2], "size[2] (or fromto)"));
    if (type == "box") {
      out.type = UrdfGeometry::Type::kBox;
      out.box_size = 2.0 * h;
    } else {
      out.type = UrdfGeometry::Type::kEllipsoid;
      out.radii = h;
    }
  } else if (type == "mesh") {
    const MjcfMesh& mesh = meshOf(g, cls);
    out.type = UrdfGeometry::Type::kMesh;
    out.mesh_hull = true;  // MuJoCo collides a mesh geom as the convex hull of its vertices
    out.mesh_scale = mesh.scale;
    out.mesh_file = mesh.file;
    out.mesh_vertices = mesh.vertices;
    std::error_code ec;
    const fs::path file = (fs::path(doc_.path()).parent_path() / mesh.file).lexically_normal();
    if (!mesh.file.empty() && !fs::is_regular_file(file, ec))
      doc_.fail(g, "collision mesh file '" + file.string() + "' (mesh asset at line " +
                       std::to_string(mesh.at->Row()) +
                       ") does not exist or is not a file: taskmap needs every colliding mesh");
  } else if (type == "plane" || type == "hfield" || type == "sdf") {
    doc_.fail(g, "a " + type +
                     " geom cannot be part of a hand (load the hand's own file, not a "
                     "scene, or make it visual: contype=\"0\" conaffinity=\"0\")");
  } else {
    doc_.fail(g, "geom type '" + type + "' is unknown");
  }
}

ShapeContact MjcfReader::geomContact(const TiXmlElement* g, int cls) const {
  // What MuJoCo's defaults give for the components the model leaves unsaid.
  constexpr double kSolref[2] = {0.02, 1.0};
  constexpr double kSolimp[5] = {0.9, 0.95, 0.001, 0.5, 2.0};
  ShapeContact c;
  const auto f = components(g, "geom", cls, "friction", 3);
  c.sliding = f[0];
  c.torsional = f[1];
  c.rolling = f[2];
  const auto r = components(g, "geom", cls, "solref", 2);
  if (r[0] || r[1])
    c.solref = std::array<double, 2>{r[0].value_or(kSolref[0]), r[1].value_or(kSolref[1])};
  const auto i = components(g, "geom", cls, "solimp", 5);
  if (std::any_of(i.begin(), i.end(), [](const auto& v) { return v.has_value(); })) {
    std::array<double, 5> v{};
    for (std::size_t k = 0; k < 5; ++k) v[k] = i[k].value_or(kSolimp[k]);
    c.solimp = v;
  }
  return c;
}

}  // namespace taskmap::detail
