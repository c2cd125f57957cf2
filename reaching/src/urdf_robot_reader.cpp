// RobotModel::load: URDF kinematic tree (the one URDF reader, hands/urdf_model.hpp) and the
// capsule model sidecar.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include <nlohmann/json.hpp>

#include "taskmap/core/constants.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/input_file.hpp"
#include "taskmap/core/xml_scan.hpp"
#include "taskmap/hands/ros_package.hpp"
#include "taskmap/hands/urdf_model.hpp"
#include "taskmap/reaching/robot_model.hpp"

namespace taskmap {
namespace {

/// The robot URDF at `path`, read by the one URDF reader (urdf_model.hpp).
UrdfModel parseRobotUrdf(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw Error("cannot read robot URDF '" + path + "': no such file or not readable");
  const std::string text = readRegularFile(path, "robot URDF");
  refuseXacro(path, text, "robot URDF", false);
  checkUrdfShape(text, "robot URDF", path);  // before TinyXML recurses into it
  return parseUrdfModel(text, path, "robot URDF");
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

/// Builds a RobotModel from the URDF's tree (friend of RobotModel).
struct UrdfRobotReader {
  const std::string& path;
  RobotModel robot;
  std::vector<double> lower, upper, velocity;

  void fail(const std::string& what) const { throw Error("robot URDF '" + path + "': " + what); }

  void addShapes(const UrdfLink& link, RobotBody& body) {
    for (const UrdfShape& col : link.collisions) {
      const Eigen::Isometry3d& o = col.origin;
      const UrdfGeometry& g = col.geometry;
      if (g.type == UrdfGeometry::Type::kBox) {
        body.shapes.push_back(Primitive::fromBox(o, g.box_size));
      } else if (g.type == UrdfGeometry::Type::kCylinder) {
        const Eigen::Vector3d h = o.linear().col(2) * (0.5 * g.length);
        body.shapes.push_back(
            Primitive::capsule(o.translation() - h, o.translation() + h, g.radius));
      } else if (g.type == UrdfGeometry::Type::kSphere) {
        body.shapes.push_back(Primitive::capsule(o.translation(), o.translation(), g.radius));
      } else {
        robot.warnings_.push_back("link '" + link.name +
                                  "': mesh collision geometry skipped (give a capsule model)");
      }
    }
  }

  void addJoint(const UrdfJoint& j, RobotBody& body) {
    body.origin = j.origin;
    if (j.type == UrdfJointType::kFixed) return;
    if (j.type != UrdfJointType::kRevolute && j.type != UrdfJointType::kContinuous &&
        j.type != UrdfJointType::kPrismatic)
      fail("joint '" + j.name +
           "' is floating or planar; only revolute, continuous, prismatic "
           "and fixed joints are supported");
    if (j.mimic)
      fail("joint '" + j.name +
           "' mimics another joint; mimic joints are not supported "
           "in a robot arm (mount a hand with HandModel instead)");
    if (!j.axis.allFinite() || j.axis.norm() < 1e-9) fail("joint '" + j.name + "' has a zero axis");
    body.axis = j.axis.normalized();
    body.joint = j.type == UrdfJointType::kPrismatic ? JointType::kPrismatic : JointType::kRevolute;
    double lo = -kPi, hi = kPi, vel = std::numeric_limits<double>::infinity();
    if (j.type != UrdfJointType::kContinuous) {
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

  /// One body per link, in the model's order (depth-first from the root, parents first): its
  /// joint, shapes and inertia.
  void addTree(const UrdfModel& model) {
    for (const UrdfLink& link : model.links) {
      RobotBody body;
      body.name = link.name;
      if (link.parent_joint >= 0) {
        const UrdfJoint& j = model.joints[static_cast<std::size_t>(link.parent_joint)];
        body.parent = j.parent_link;
        addJoint(j, body);
      }
      addShapes(link, body);
      if (link.inertial) {
        body.mass = link.inertial->mass;
        body.com = link.inertial->origin.translation();
        if (!(body.mass >= 0.0) || !std::isfinite(body.mass) || !body.com.allFinite())
          fail("link '" + link.name + "' has a negative or non-finite mass or centre of mass");
      }
      // RobotModel::addBody's work, once per body (its name check and path rebuild would make
      // a long chain quadratic; URDF names are unique, the paths are rebuilt after the walk).
      body.chain_depth = (body.parent >= 0 ? robot.bodies_[body.parent].chain_depth : 0) +
                         (body.joint == JointType::kFixed ? 0 : 1);
      robot.bodies_.push_back(std::move(body));
    }
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
  const UrdfModel model = parseRobotUrdf(urdf_path);
  UrdfRobotReader reader{urdf_path, {}, {}, {}, {}};
  reader.robot.name_ = model.name;
  reader.addTree(model);
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
