// HandModel loading, URDF tree step: urdfdom parse (console_bridge captured), links and joints
// depth-first from the root, collision shapes (meshes: collision_mesh.hpp, each connected part
// becomes its convex hull or the pieces of a convex decomposition), actuated joints and mimic
// chains.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include "collision_mesh.hpp"
#include "hand_model_build.hpp"
#include "taskmap/core/constants.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/input_file.hpp"
#include "taskmap/core/xml_scan.hpp"
#include "taskmap/meshes/object_model.hpp"
#include "taskmap/meshes/ros_package.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

std::string readFile(const std::string& path, const char* what) {
  std::error_code ec;
  if (!fs::exists(path, ec))
    throw Error(std::string("cannot read ") + what + " '" + path + "': check the path");
  return readRegularFile(path, what);
}

/// Collects console_bridge messages of urdfdom while parsing (the parser reports the element).
class CaptureHandler : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_WARN) {
      if (!messages.empty()) messages += "; ";
      messages += text;
    }
  }
  std::string messages;
};

urdf::ModelInterfaceSharedPtr parseUrdf(const std::string& xml, const std::string& path) {
  static std::mutex mutex;  // console_bridge's handler is process-global
  std::lock_guard<std::mutex> lock(mutex);
  CaptureHandler handler;
  console_bridge::useOutputHandler(&handler);
  const auto old_level = console_bridge::getLogLevel();
  console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_WARN);
  urdf::ModelInterfaceSharedPtr model;
  try {
    model = urdf::parseURDF(xml);
  } catch (const std::exception& e) {
    handler.messages += e.what();
  }
  console_bridge::restorePreviousOutputHandler();
  console_bridge::setLogLevel(old_level);
  if (!model)
    throw Error("cannot parse URDF '" + path + "': " +
                (handler.messages.empty() ? std::string("malformed XML") : handler.messages));
  return model;
}

Eigen::Isometry3d toIso(const urdf::Pose& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  Eigen::Quaterniond q(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z);
  if (q.norm() < 1e-12) q = Eigen::Quaterniond::Identity();
  t.linear() = q.normalized().toRotationMatrix();
  return t;
}

/// The convex shapes of one <collision> element (a mesh gives convex pieces per connected part,
/// recorded in `infos`); U prefixes errors ("URDF '<path>': ").
std::vector<CollisionShape> shapesOf(const urdf::Collision& col, const std::string& urdf_path,
                                     const std::string& link, const std::string& U,
                                     const detail::CollisionOptions& options, int first_shape,
                                     std::vector<CollisionMeshInfo>* infos) {
  CollisionShape s;
  s.origin = toIso(col.origin);
  const urdf::Geometry& g = *col.geometry;
  switch (g.type) {
    case urdf::Geometry::BOX: {
      const auto& b = static_cast<const urdf::Box&>(g);
      s.type = ShapeType::kBox;
      s.box_size = Eigen::Vector3d(b.dim.x, b.dim.y, b.dim.z);
      if (!(s.box_size.minCoeff() > 0.0))
        throw Error(U + "link '" + link + "': <box size> must be positive");
      break;
    }
    case urdf::Geometry::CYLINDER: {
      const auto& c = static_cast<const urdf::Cylinder&>(g);
      s.type = ShapeType::kCylinder;
      s.radius = c.radius;
      s.length = c.length;
      if (!(s.radius > 0.0 && s.length > 0.0))
        throw Error(U + "link '" + link + "': <cylinder> radius and length must be positive");
      break;
    }
    case urdf::Geometry::SPHERE: {
      const auto& sp = static_cast<const urdf::Sphere&>(g);
      s.type = ShapeType::kSphere;
      s.radius = sp.radius;
      if (!(s.radius > 0.0))
        throw Error(U + "link '" + link + "': <sphere radius> must be positive");
      break;
    }
    case urdf::Geometry::MESH: {
      const auto& m = static_cast<const urdf::Mesh&>(g);
      std::vector<CollisionShape> out;
      for (auto& part :
           detail::collisionMeshShapes(m.filename, Eigen::Vector3d(m.scale.x, m.scale.y, m.scale.z),
                                       urdf_path, link, options)) {
        part.info.link = link;
        part.info.file = m.filename;
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

/// A URDF joint (without child link and driver, which the tree walk and mimic step fill in).
HandJoint jointOf(const urdf::Joint& uj, int parent_link, const std::string& U) {
  HandJoint j;
  j.name = uj.name;
  j.parent_link = parent_link;
  j.origin = toIso(uj.parent_to_joint_origin_transform);
  const Eigen::Vector3d axis(uj.axis.x, uj.axis.y, uj.axis.z);
  switch (uj.type) {
    case urdf::Joint::REVOLUTE:
    case urdf::Joint::CONTINUOUS:
      j.type = JointType::kRevolute;
      break;
    case urdf::Joint::PRISMATIC:
      j.type = JointType::kPrismatic;
      break;
    case urdf::Joint::FIXED:
      j.type = JointType::kFixed;
      break;
    default:
      throw Error(U + "joint '" + uj.name +
                  "' is floating or planar, which hands cannot have: use revolute, "
                  "prismatic, continuous or fixed");
  }
  if (j.type == JointType::kFixed) return j;
  if (!(axis.norm() > 1e-9)) throw Error(U + "joint '" + uj.name + "' has a zero <axis>");
  j.axis = axis.normalized();
  if (uj.type == urdf::Joint::CONTINUOUS) {
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

/// The links and joints of a URDF, depth-first from the root (children in URDF order).
struct TreeWalk {
  const urdf::ModelInterface& model;
  const std::string& urdf_path;
  const std::string& U;
  std::vector<HandLink>& links;
  std::vector<HandJoint>& joints;
  const detail::CollisionOptions& options;
  std::vector<CollisionMeshInfo>& infos;

  /// Appends `link` (reached through joint `parent_joint`, -1 for the root); returns its index.
  int addLink(const urdf::LinkConstSharedPtr& link, int parent_joint) {
    if (!link || !seen.insert(link->name).second)
      throw Error(U + "link '" + (link ? link->name : std::string("?")) +
                  "' is reached twice from the root: the joints do not form a tree");
    HandLink hl;
    hl.name = link->name;
    hl.parent_joint = parent_joint;
    for (const auto& col : link->collision_array)
      if (col && col->geometry)
        for (auto& s : shapesOf(*col, urdf_path, link->name, U, options,
                                static_cast<int>(hl.shapes.size()), &infos))
          hl.shapes.push_back(std::move(s));
    const int li = static_cast<int>(links.size());
    links.push_back(std::move(hl));
    return li;
  }

  /// Appends the root and its subtree depth-first (children in URDF order: link, first child
  /// joint, that child's subtree, next child joint, ...), with an explicit stack: a chain of
  /// any length costs linear time and no call depth.
  void add(const urdf::LinkConstSharedPtr& root) {
    struct Frame {
      urdf::LinkConstSharedPtr link;
      int index;
      std::size_t next;  // next child joint to walk
    };
    std::vector<Frame> stack{{root, addLink(root, -1), 0}};
    while (!stack.empty()) {
      Frame& f = stack.back();
      if (f.next == f.link->child_joints.size()) {
        stack.pop_back();
        continue;
      }
      const urdf::JointSharedPtr& child_joint = f.link->child_joints[f.next++];
      const int parent = f.index;
      const int ji = static_cast<int>(joints.size());
      joints.push_back(jointOf(*child_joint, parent, U));
      const urdf::LinkConstSharedPtr child = model.getLink(child_joint->child_link_name);
      const int ci = addLink(child, ji);  // invalidates f
      joints[static_cast<std::size_t>(ji)].child_link = ci;
      stack.push_back({child, ci, 0});
    }
    if (links.size() != model.links_.size()) {
      std::string detached;
      for (const auto& [name, link] : model.links_)
        if (seen.count(name) == 0) detached += (detached.empty() ? "'" : ", '") + name + "'";
      throw Error(U + "link(s) " + detached + " not reachable from the root link '" + root->name +
                  "' (a cycle of joints, or a part not attached to the tree)");
    }
  }

  std::set<std::string> seen;
};

/// Maps every mimic joint to its (transitive) driver: q_j = multiplier * q_driver + offset.
void resolveMimics(const urdf::ModelInterface& model, std::vector<HandJoint>& joints,
                   const std::string& U) {
  for (HandJoint& j : joints) {
    if (!j.mimic) continue;
    double mult = 1.0, off = 0.0;
    const HandJoint* cur = &j;
    std::set<std::string> seen{j.name};
    while (cur->mimic) {
      const auto uj = model.getJoint(cur->name);
      const std::string target = uj->mimic->joint_name;
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

urdf::ModelInterfaceSharedPtr HandModelBuilder::parseUrdfFile(HandModel& h,
                                                              const std::string& urdf_path) {
  const std::string xml = readFile(urdf_path, "URDF");
  refuseXacro(urdf_path, xml, "hand URDF", true);
  h.urdf_path_ = urdf_path;
  h.sha_ = sha256Hex(xml);
  checkUrdfShape(xml, "URDF", urdf_path, kMaxHandLinks);  // before TinyXML recurses into it
  urdf::ModelInterfaceSharedPtr model = parseUrdf(xml, urdf_path);
  h.robot_name_ = model->getName();
  if (!model->getRoot()) throw Error("URDF '" + urdf_path + "': has no root link");
  return model;
}

void HandModelBuilder::readUrdfTree(HandModel& h, const urdf::ModelInterface& model,
                                    const detail::CollisionOptions& options) {
  const std::string& urdf_path = h.urdf_path_;
  const std::string U = "URDF '" + urdf_path + "': ";
  TreeWalk{model, urdf_path, U, h.links_, h.joints_, options, h.collision_meshes_, {}}.add(
      model.getRoot());

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
