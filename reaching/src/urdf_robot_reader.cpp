// RobotModel::load: URDF kinematic tree (urdfdom, private) and the capsule model sidecar.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <mutex>
#include <set>
#include <sstream>

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>
#include <nlohmann/json.hpp>

#include "taskmap/core/error.hpp"
#include "taskmap/core/input_file.hpp"
#include "taskmap/core/xml_scan.hpp"
#include "taskmap/meshes/ros_package.hpp"
#include "taskmap/reaching/robot_model.hpp"

namespace taskmap {
namespace {

/// Collects urdfdom's console_bridge warnings so that the Error can quote them.
class UrdfMessages : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_WARN)
      text_ += (text_.empty() ? "" : "; ") + text;
  }
  std::string text_;
};

urdf::ModelInterfaceSharedPtr parseRobotUrdf(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw Error("cannot read robot URDF '" + path + "': no such file or not readable");
  std::stringstream ss;
  const std::string text = readRegularFile(path, "robot URDF");
  refuseXacro(path, text, "robot URDF", false);
  checkUrdfShape(text, "robot URDF", path);  // before TinyXML recurses into it
  ss << text;
  static std::mutex mutex;  // the console_bridge handler is process-global
  std::lock_guard<std::mutex> lock(mutex);
  UrdfMessages messages;
  console_bridge::useOutputHandler(&messages);
  urdf::ModelInterfaceSharedPtr model;
  try {
    model = urdf::parseURDF(ss.str());
  } catch (const std::exception& e) {
    messages.text_ += e.what();
  }
  console_bridge::restorePreviousOutputHandler();
  if (!model)
    throw Error("cannot parse robot URDF '" + path +
                "': " + (messages.text_.empty() ? "malformed XML" : messages.text_));
  return model;
}

Eigen::Isometry3d isometryOf(const urdf::Pose& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() << p.position.x, p.position.y, p.position.z;
  const Eigen::Quaterniond q(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z);
  t.linear() =
      (q.norm() > 1e-12 ? q.normalized() : Eigen::Quaterniond::Identity()).toRotationMatrix();
  return t;
}

Eigen::Vector3d vec3(const nlohmann::json& j, const std::string& where) {
  if (!j.is_array() || j.size() != 3) throw Error(where + ": expected [x, y, z]");
  Eigen::Vector3d v;
  for (int k = 0; k < 3; ++k) {
    if (!j[k].is_number()) throw Error(where + ": expected numbers");
    v[k] = j[k].get<double>();
  }
  return v;
}

}  // namespace

/// Builds a RobotModel from urdfdom's tree (friend of RobotModel).
struct UrdfRobotReader {
  const std::string& path;
  RobotModel robot;
  std::vector<double> lower, upper, velocity;

  void fail(const std::string& what) const { throw Error("robot URDF '" + path + "': " + what); }

  void addShapes(const urdf::Link& link, RobotBody& body) {
    for (const auto& col : link.collision_array) {
      if (!col || !col->geometry) continue;
      const Eigen::Isometry3d o = isometryOf(col->origin);
      const urdf::Geometry& g = *col->geometry;
      if (g.type == urdf::Geometry::BOX) {
        const auto& b = static_cast<const urdf::Box&>(g);
        body.shapes.push_back(Primitive::fromBox(o, {b.dim.x, b.dim.y, b.dim.z}));
      } else if (g.type == urdf::Geometry::CYLINDER) {
        const auto& c = static_cast<const urdf::Cylinder&>(g);
        const Eigen::Vector3d h = o.linear().col(2) * (0.5 * c.length);
        body.shapes.push_back(
            Primitive::capsule(o.translation() - h, o.translation() + h, c.radius));
      } else if (g.type == urdf::Geometry::SPHERE) {
        const double r = static_cast<const urdf::Sphere&>(g).radius;
        body.shapes.push_back(Primitive::capsule(o.translation(), o.translation(), r));
      } else {
        robot.warnings_.push_back("link '" + link.name +
                                  "': mesh collision geometry skipped (give a capsule model)");
      }
    }
  }

  void addJoint(const urdf::Joint& j, RobotBody& body) {
    body.origin = isometryOf(j.parent_to_joint_origin_transform);
    if (j.type == urdf::Joint::FIXED) return;
    if (j.type != urdf::Joint::REVOLUTE && j.type != urdf::Joint::CONTINUOUS &&
        j.type != urdf::Joint::PRISMATIC)
      fail("joint '" + j.name +
           "' is floating or planar; only revolute, continuous, prismatic "
           "and fixed joints are supported");
    if (j.mimic)
      fail("joint '" + j.name +
           "' mimics another joint; mimic joints are not supported "
           "in a robot arm (mount a hand with HandModel instead)");
    const Eigen::Vector3d axis(j.axis.x, j.axis.y, j.axis.z);
    if (!axis.allFinite() || axis.norm() < 1e-9) fail("joint '" + j.name + "' has a zero axis");
    body.axis = axis.normalized();
    body.joint = j.type == urdf::Joint::PRISMATIC ? JointType::kPrismatic : JointType::kRevolute;
    double lo = -M_PI, hi = M_PI, vel = std::numeric_limits<double>::infinity();
    if (j.type != urdf::Joint::CONTINUOUS) {
      if (!j.limits) fail("joint '" + j.name + "' has no <limit>; give lower and upper limits");
      lo = j.limits->lower;
      hi = j.limits->upper;
      if (!(lo < hi) || !std::isfinite(lo) || !std::isfinite(hi))
        fail("joint '" + j.name + "' needs finite limits with lower < upper");
    }
    if (j.limits && j.limits->velocity > 0.0) vel = j.limits->velocity;
    body.dof = static_cast<int>(robot.dof_names_.size());
    robot.dof_names_.push_back(j.name);
    lower.push_back(lo);
    upper.push_back(hi);
    velocity.push_back(vel);
  }

  /// The tree depth-first from root (children in URDF order) with an explicit stack: the same
  /// body order as a recursive walk, linear time and no call depth for any chain.
  void addTree(const urdf::ModelInterface& model) {
    std::vector<std::pair<urdf::LinkConstSharedPtr, int>> stack{{model.getRoot(), -1}};
    std::set<std::string> seen;
    while (!stack.empty()) {
      const auto [link, parent] = stack.back();
      stack.pop_back();
      if (!link || !seen.insert(link->name).second)
        fail("link '" + (link ? link->name : std::string("?")) +
             "' is reached twice from the root: the joints do not form a tree");
      const int index = addLink(link, parent);
      for (auto it = link->child_links.rbegin(); it != link->child_links.rend(); ++it)
        stack.emplace_back(*it, index);
    }
    if (seen.size() != model.links_.size()) {
      std::string detached;
      for (const auto& [name, link] : model.links_)
        if (seen.count(name) == 0) detached += (detached.empty() ? "'" : ", '") + name + "'";
      fail("link(s) " + detached + " not reachable from the root link '" + model.getRoot()->name +
           "' (a cycle of joints, or a part not attached to the tree)");
    }
  }

  /// Appends one body (its joint, shapes, inertia); returns its index.
  int addLink(const urdf::LinkConstSharedPtr& link, int parent) {
    RobotBody body;
    body.name = link->name;
    body.parent = parent;
    if (link->parent_joint) addJoint(*link->parent_joint, body);
    addShapes(*link, body);
    if (link->inertial) {
      body.mass = link->inertial->mass;
      const urdf::Vector3& c = link->inertial->origin.position;
      body.com = Eigen::Vector3d(c.x, c.y, c.z);
      if (!(body.mass >= 0.0) || !std::isfinite(body.mass) || !body.com.allFinite())
        fail("link '" + link->name + "' has a negative or non-finite mass or centre of mass");
    }
    // RobotModel::addBody's work, once per body (its name check and path rebuild would make
    // a long chain quadratic; urdfdom's names are unique, the paths are rebuilt after the walk).
    body.chain_depth = (body.parent >= 0 ? robot.bodies_[body.parent].chain_depth : 0) +
                       (body.joint == JointType::kFixed ? 0 : 1);
    robot.bodies_.push_back(std::move(body));
    return static_cast<int>(robot.bodies_.size()) - 1;
  }

  void readCapsules(const std::string& file) {
    nlohmann::json j;
    const std::string text = readRegularFile(file, "capsule model");
    try {
      j = nlohmann::json::parse(text);
    } catch (const std::exception& e) {
      throw Error("capsule model '" + file + "': not valid JSON (" + e.what() + ")");
    }
    if (!j.contains("links") || !j["links"].is_object())
      throw Error("capsule model '" + file + "': needs an object \"links\"");
    for (RobotBody& b : robot.bodies_) b.shapes.clear();
    robot.warnings_.clear();
    for (const auto& [name, list] : j["links"].items()) {
      const int index = robot.bodyIndex(name);
      const std::string where = "capsule model '" + file + "', link '" + name + "'";
      if (index < 0) throw Error(where + ": no such link in '" + path + "'");
      if (!list.is_array()) throw Error(where + ": expected a list of capsules");
      for (const auto& c : list) {
        if (!c.is_object() || !c.contains("radius") || !c["radius"].is_number())
          throw Error(where + ": each capsule needs p0, p1 and a numeric radius");
        try {
          robot.bodies_[index].shapes.push_back(Primitive::capsule(
              vec3(c.value("p0", nlohmann::json()), where + " p0"),
              vec3(c.value("p1", nlohmann::json()), where + " p1"), c["radius"].get<double>()));
        } catch (const Error& e) {
          throw Error(where + ": " + e.what());
        }
      }
    }
  }
};

RobotModel RobotModel::load(const std::string& urdf_path) {
  const urdf::ModelInterfaceSharedPtr model = parseRobotUrdf(urdf_path);
  UrdfRobotReader reader{urdf_path, {}, {}, {}, {}};
  reader.robot.name_ = model->getName();
  if (!model->getRoot()) reader.fail("no root link");
  reader.addTree(*model);
  reader.robot.rebuildPaths();
  if (reader.robot.dofs() == 0) reader.fail("no movable joint");
  const auto to_vec = [](const std::vector<double>& v) {
    return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
  };
  reader.robot.lower_ = to_vec(reader.lower);
  reader.robot.upper_ = to_vec(reader.upper);
  reader.robot.velocity_ = to_vec(reader.velocity);
  const std::filesystem::path p(urdf_path);
  const std::filesystem::path capsules = p.parent_path() / (p.stem().string() + ".capsules.json");
  if (std::filesystem::exists(capsules)) reader.readCapsules(capsules.string());
  return reader.robot;
}

}  // namespace taskmap
