// HandModel loading, URDF tree step: the URDF read by the one reader (urdf_model.hpp), links and
// joints depth-first from the root, collision shapes (collision_mesh.hpp over meshes' convex
// pieces: each connected part becomes its convex hull or the pieces of a convex decomposition),
// actuated joints and mimic chains.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "collision_mesh.hpp"
#include "hand_model_build.hpp"
#include "round_shapes.hpp"
#include "taskmap/core/constants.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/input_file.hpp"
#include "taskmap/core/xml_scan.hpp"
#include "taskmap/hands/mjcf_model.hpp"
#include "taskmap/hands/ros_package.hpp"
#include "taskmap/hands/urdf_model.hpp"
#include "taskmap/meshes/convex_hull.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

std::string readFile(const std::string& path, const char* what) {
  std::error_code ec;
  if (!fs::exists(path, ec))
    throw Error(std::string("cannot read ") + what + " '" + path + "': check the path");
  return readRegularFile(path, what);
}

/// An MJCF mesh geom as one convex shape: the hull of all its vertices (how MuJoCo collides it),
/// recorded in `infos`; U prefixes errors ("MJCF '<path>': ").
CollisionShape meshHull(const UrdfGeometry& g, const std::string& path, const std::string& link,
                        const std::string& U, int first_shape,
                        std::vector<CollisionMeshInfo>* infos) {
  CollisionMeshInfo info;
  info.link = link;
  info.file = g.mesh_file.empty() ? std::string("(inline vertices)") : g.mesh_file;
  info.first_shape = first_shape;
  info.note = "the convex hull of the whole mesh (MJCF: how MuJoCo collides a mesh geom)";
  std::vector<Eigen::Vector3d> points;
  if (g.mesh_file.empty()) {
    for (const auto& v : g.mesh_vertices) points.push_back(v.cwiseProduct(g.mesh_scale));
  } else {
    detail::CollisionOptions hulls;
    hulls.decompose = false;
    for (auto& part :
         detail::collisionMeshShapes(g.mesh_file, g.mesh_scale, path, link, hulls, "MJCF")) {
      info.faces += part.info.faces;
      info.mesh_volume += part.info.mesh_volume;
      for (const auto& piece : part.pieces)
        points.insert(points.end(), piece.vertices.begin(), piece.vertices.end());
    }
  }
  const PointHull hull = convexHull(points, U + "link '" + link + "': mesh '" + info.file + "'");
  info.hull_volume = info.pieces_volume = hull.volume;
  infos->push_back(info);
  CollisionShape s;
  s.type = ShapeType::kConvex;
  s.points = hull.vertices;
  return s;
}

/// The convex shapes of one <collision> element (a mesh gives convex pieces per connected part,
/// recorded in `infos`); U prefixes errors ("URDF '<path>': "), `format` names the file's format.
std::vector<CollisionShape> shapesOf(const UrdfShape& col, const std::string& urdf_path,
                                     const std::string& link, const std::string& U,
                                     const detail::CollisionOptions& options, int first_shape,
                                     std::vector<CollisionMeshInfo>* infos,
                                     const std::string& format) {
  CollisionShape s;
  s.origin = col.origin;
  const UrdfGeometry& g = col.geometry;
  switch (g.type) {
    case UrdfGeometry::Type::kBox:
      s.type = ShapeType::kBox;
      s.box_size = g.box_size;
      if (!(s.box_size.minCoeff() > 0.0))
        throw Error(U + "link '" + link + "': <box size> must be positive");
      break;
    case UrdfGeometry::Type::kCylinder:
      s.type = ShapeType::kCylinder;
      s.radius = g.radius;
      s.length = g.length;
      if (!(s.radius > 0.0 && s.length > 0.0))
        throw Error(U + "link '" + link + "': <cylinder> radius and length must be positive");
      break;
    case UrdfGeometry::Type::kSphere:
      s.type = ShapeType::kSphere;
      s.radius = g.radius;
      if (!(s.radius > 0.0))
        throw Error(U + "link '" + link + "': <sphere radius> must be positive");
      break;
    case UrdfGeometry::Type::kCapsule:
    case UrdfGeometry::Type::kEllipsoid:
      // Inscribed polytopes (round_shapes.hpp): HandModel's round primitives are spheres and
      // cylinders only.
      s.type = ShapeType::kConvex;
      s.points = g.type == UrdfGeometry::Type::kCapsule ? detail::capsulePoints(g.radius, g.length)
                                                        : detail::ellipsoidPoints(g.radii);
      break;
    case UrdfGeometry::Type::kMesh: {
      if (g.mesh_hull) {
        CollisionShape h = meshHull(g, urdf_path, link, U, first_shape, infos);
        h.origin = col.origin;
        return {h};
      }
      std::vector<CollisionShape> out;
      for (auto& part : detail::collisionMeshShapes(g.mesh_file, g.mesh_scale, urdf_path, link,
                                                    options, format)) {
        part.info.link = link;
        part.info.file = g.mesh_file;
        part.info.first_shape = first_shape + static_cast<int>(out.size());
        infos->push_back(part.info);
        for (auto& piece : part.pieces) {
          CollisionShape h = s;
          h.type = ShapeType::kConvex;
          h.points = std::move(piece.vertices);
          out.push_back(std::move(h));
        }
      }
      return out;
    }
  }
  return {s};
}

/// A URDF joint as a hand joint (without driver, which the mimic step fills in).
HandJoint jointOf(const UrdfJoint& uj, const std::string& U) {
  HandJoint j;
  j.name = uj.name;
  j.parent_link = uj.parent_link;
  j.child_link = uj.child_link;
  j.origin = uj.origin;
  switch (uj.type) {
    case UrdfJointType::kRevolute:
    case UrdfJointType::kContinuous:
      j.type = JointType::kRevolute;
      break;
    case UrdfJointType::kPrismatic:
      j.type = JointType::kPrismatic;
      break;
    case UrdfJointType::kFixed:
      j.type = JointType::kFixed;
      break;
    default:
      throw Error(U + "joint '" + uj.name +
                  "' is floating or planar, which hands cannot have: use revolute, "
                  "prismatic, continuous or fixed");
  }
  if (j.type == JointType::kFixed) return j;
  if (!(uj.axis.norm() > 1e-9)) throw Error(U + "joint '" + uj.name + "' has a zero <axis>");
  j.axis = uj.axis.normalized();
  if (uj.type == UrdfJointType::kContinuous) {
    j.lower = -kPi;
    j.upper = kPi;
  } else {
    if (!uj.limits) throw Error(U + "joint '" + uj.name + "' has no <limit lower upper>");
    j.lower = uj.limits->lower;
    j.upper = uj.limits->upper;
    if (!(j.lower <= j.upper))
      throw Error(U + "joint '" + uj.name + "': <limit> lower must not exceed upper");
  }
  if (uj.mimic) {
    j.mimic = true;
    j.multiplier = uj.mimic->multiplier;
    j.offset = uj.mimic->offset;
  }
  return j;
}

/// Maps every mimic joint to its (transitive) driver: q_j = multiplier * q_driver + offset.
void resolveMimics(const UrdfModel& model, std::vector<HandJoint>& joints, const std::string& U) {
  for (HandJoint& j : joints) {
    if (!j.mimic) continue;
    double mult = 1.0, off = 0.0;
    const HandJoint* cur = &j;
    std::set<std::string> seen{j.name};
    while (cur->mimic) {
      // Hand joints are the URDF's joints in the same order.
      const std::string target =
          model.joints[static_cast<std::size_t>(cur - joints.data())].mimic->joint;
      auto it = std::find_if(joints.begin(), joints.end(),
                             [&](const HandJoint& x) { return x.name == target; });
      if (it == joints.end() || it->type == JointType::kFixed)
        throw Error(U + "joint '" + j.name + "': <mimic joint='" + target +
                    "'> names no movable joint of the URDF");
      if (!seen.insert(target).second)
        throw Error(U + "joint '" + j.name + "': <mimic> chain is cyclic");
      // q_cur = m_cur * q_target + o_cur; accumulated q_j = mult * q_cur + off.
      off += mult * cur->offset;
      mult *= cur->multiplier;
      cur = &*it;
    }
    j.multiplier = mult;
    j.offset = off;
    j.driver = cur->driver;
  }
}

}  // namespace

UrdfModel HandModelBuilder::parseUrdfFile(HandModel& h, const std::string& urdf_path) {
  const std::string xml =
      readFile(urdf_path, fs::path(urdf_path).extension() == ".xml" ? "MJCF" : "URDF");
  h.urdf_path_ = urdf_path;
  h.sha_ = sha256Hex(xml);
  if (isMjcfText(xml)) {
    h.format_ = "MJCF";
    MjcfModel mjcf = readMjcfModel(xml, urdf_path);
    if (mjcf.tree.links.size() > kMaxHandLinks)
      throw Error("MJCF '" + urdf_path + "': " + std::to_string(mjcf.tree.links.size()) +
                  " links, more than the limit of " + std::to_string(kMaxHandLinks) + " of a hand");
    h.dynamics_ = std::move(mjcf.dynamics);
    h.load_warnings_ = std::move(mjcf.warnings);
    h.robot_name_ = mjcf.tree.name;
    return std::move(mjcf.tree);
  }
  refuseXacro(urdf_path, xml, "hand URDF", true);
  checkUrdfShape(xml, "URDF", urdf_path, kMaxHandLinks);  // before TinyXML recurses into it
  UrdfModel model = parseUrdfModel(xml, urdf_path, "URDF");
  h.robot_name_ = model.name;
  return model;
}

void HandModelBuilder::readUrdfTree(HandModel& h, const UrdfModel& model,
                                    const detail::CollisionOptions& options) {
  const std::string& urdf_path = h.urdf_path_;
  const std::string U = h.format_ + " '" + urdf_path + "': ";
  // Links and joints in the model's order (depth-first from the root): a link's parent joint,
  // then its collision shapes.
  for (const UrdfLink& link : model.links) {
    if (link.parent_joint >= 0)
      h.joints_.push_back(jointOf(model.joints[static_cast<std::size_t>(link.parent_joint)], U));
    HandLink hl;
    hl.name = link.name;
    hl.parent_joint = link.parent_joint;
    for (const UrdfShape& col : link.collisions)
      for (auto& s : shapesOf(col, urdf_path, link.name, U, options,
                              static_cast<int>(hl.shapes.size()), &h.collision_meshes_, h.format_))
        hl.shapes.push_back(std::move(s));
    h.links_.push_back(std::move(hl));
  }

  // Actuated joints: movable, not mimic; mimic joints resolve to their (transitive) driver.
  for (HandJoint& j : h.joints_) {
    if (j.type == JointType::kFixed || j.mimic) continue;
    j.driver = static_cast<int>(h.actuated_.size());
    h.actuated_.push_back(j.name);
    h.lower_.push_back(j.lower);
    h.upper_.push_back(j.upper);
  }
  resolveMimics(model, h.joints_, U);
  if (h.actuated_.empty()) throw Error(U + "has no actuated (non-fixed, non-mimic) joint");
}

std::string readHandFile(const std::string& path, const char* what) {
  return readFile(path, what);
}

}  // namespace taskmap
