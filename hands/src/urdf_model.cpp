// The one URDF reader (urdf_model.hpp): urdfdom parses under one lock around console_bridge's
// process-global output handler; the tree is copied into plain data depth-first from the root.
#include "taskmap/hands/urdf_model.hpp"

#include <mutex>
#include <set>

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

/// Collects console_bridge messages of urdfdom while parsing (the parser reports the element).
class CaptureHandler : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_WARN)
      messages += (messages.empty() ? "" : "; ") + text;
  }
  std::string messages;
};

/// urdfdom's model of `xml`, its messages quoted in the Error when it refuses the text.
urdf::ModelInterfaceSharedPtr parse(const std::string& xml, const std::string& path,
                                    const std::string& what) {
  static std::mutex mutex;  // console_bridge's handler and log level are process-global
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
    throw Error("cannot parse " + what + " '" + path + "': " +
                (handler.messages.empty() ? std::string("malformed XML") : handler.messages));
  return model;
}

Eigen::Isometry3d isometryOf(const urdf::Pose& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  const Eigen::Quaterniond q(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z);
  t.linear() =
      (q.norm() < 1e-12 ? Eigen::Quaterniond::Identity() : q.normalized()).toRotationMatrix();
  return t;
}

UrdfShape shapeOf(const urdf::Pose& origin, const urdf::Geometry& g) {
  UrdfShape s;
  s.origin = isometryOf(origin);
  UrdfGeometry& out = s.geometry;
  switch (g.type) {
    case urdf::Geometry::BOX: {
      const auto& b = static_cast<const urdf::Box&>(g);
      out.type = UrdfGeometry::Type::kBox;
      out.box_size = Eigen::Vector3d(b.dim.x, b.dim.y, b.dim.z);
      break;
    }
    case urdf::Geometry::CYLINDER: {
      const auto& c = static_cast<const urdf::Cylinder&>(g);
      out.type = UrdfGeometry::Type::kCylinder;
      out.radius = c.radius;
      out.length = c.length;
      break;
    }
    case urdf::Geometry::SPHERE:
      out.type = UrdfGeometry::Type::kSphere;
      out.radius = static_cast<const urdf::Sphere&>(g).radius;
      break;
    case urdf::Geometry::MESH: {
      const auto& m = static_cast<const urdf::Mesh&>(g);
      out.type = UrdfGeometry::Type::kMesh;
      out.mesh_file = m.filename;
      out.mesh_scale = Eigen::Vector3d(m.scale.x, m.scale.y, m.scale.z);
      break;
    }
  }
  return s;
}

UrdfLink linkOf(const urdf::Link& l, int parent_joint) {
  UrdfLink out;
  out.name = l.name;
  out.parent_joint = parent_joint;
  for (const auto& v : l.visual_array)
    if (v && v->geometry) out.visuals.push_back(shapeOf(v->origin, *v->geometry));
  for (const auto& c : l.collision_array)
    if (c && c->geometry) out.collisions.push_back(shapeOf(c->origin, *c->geometry));
  if (l.inertial) {
    const urdf::Inertial& i = *l.inertial;
    UrdfInertial in;
    in.mass = i.mass;
    in.origin = isometryOf(i.origin);
    in.inertia << i.ixx, i.ixy, i.ixz, i.ixy, i.iyy, i.iyz, i.ixz, i.iyz, i.izz;
    out.inertial = in;
  }
  return out;
}

UrdfJointType jointTypeOf(int type) {
  switch (type) {
    case urdf::Joint::REVOLUTE:
      return UrdfJointType::kRevolute;
    case urdf::Joint::CONTINUOUS:
      return UrdfJointType::kContinuous;
    case urdf::Joint::PRISMATIC:
      return UrdfJointType::kPrismatic;
    case urdf::Joint::FLOATING:
      return UrdfJointType::kFloating;
    case urdf::Joint::PLANAR:
      return UrdfJointType::kPlanar;
    default:
      return UrdfJointType::kFixed;
  }
}

UrdfJoint jointOf(const urdf::Joint& j, int parent_link, int child_link) {
  UrdfJoint out;
  out.name = j.name;
  out.type = jointTypeOf(j.type);
  out.parent_link = parent_link;
  out.child_link = child_link;
  out.origin = isometryOf(j.parent_to_joint_origin_transform);
  out.axis = Eigen::Vector3d(j.axis.x, j.axis.y, j.axis.z);
  if (j.limits)
    out.limits = UrdfLimits{j.limits->lower, j.limits->upper, j.limits->effort, j.limits->velocity};
  if (j.mimic) out.mimic = UrdfMimic{j.mimic->joint_name, j.mimic->multiplier, j.mimic->offset};
  return out;
}

/// The tree depth-first from the root (children in URDF order) with an explicit stack: a chain
/// of any length costs linear time and no call depth. `U` prefixes errors.
void walkTree(const urdf::ModelInterface& model, const std::string& U, UrdfModel* out) {
  struct Frame {
    urdf::LinkConstSharedPtr link;
    int index;
    std::size_t next;  // next child joint to walk
  };
  const urdf::LinkConstSharedPtr root = model.getRoot();
  std::set<std::string> seen{root->name};
  out->links.push_back(linkOf(*root, -1));
  std::vector<Frame> stack{{root, 0, 0}};
  while (!stack.empty()) {
    Frame& f = stack.back();
    if (f.next == f.link->child_joints.size()) {
      stack.pop_back();
      continue;
    }
    const urdf::JointSharedPtr& joint = f.link->child_joints[f.next++];
    const int parent = f.index;
    const urdf::LinkConstSharedPtr child = model.getLink(joint->child_link_name);
    if (!child || !seen.insert(child->name).second)
      throw Error(U + "link '" + (child ? child->name : std::string("?")) +
                  "' is reached twice from the root: the joints do not form a tree");
    const int ci = static_cast<int>(out->links.size());
    out->joints.push_back(jointOf(*joint, parent, ci));
    out->links.push_back(linkOf(*child, ci - 1));  // invalidates f
    stack.push_back({child, ci, 0});
  }
  if (out->links.size() != model.links_.size()) {
    std::string detached;
    for (const auto& [name, link] : model.links_)
      if (seen.count(name) == 0) detached += (detached.empty() ? "'" : ", '") + name + "'";
    throw Error(U + "link(s) " + detached + " not reachable from the root link '" + root->name +
                "' (a cycle of joints, or a part not attached to the tree)");
  }
}

}  // namespace

int UrdfModel::jointIndex(const std::string& joint_name) const {
  for (std::size_t i = 0; i < joints.size(); ++i)
    if (joints[i].name == joint_name) return static_cast<int>(i);
  return -1;
}

UrdfModel parseUrdfModel(const std::string& xml, const std::string& path, const std::string& what) {
  const urdf::ModelInterfaceSharedPtr model = parse(xml, path, what);
  const std::string U = what + " '" + path + "': ";
  if (!model->getRoot()) throw Error(U + "has no root link");
  UrdfModel out;
  out.name = model->getName();
  walkTree(*model, U, &out);
  return out;
}

}  // namespace taskmap
