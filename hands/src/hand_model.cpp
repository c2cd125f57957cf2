// HandModel: accessors, forward kinematics and derived data (drivers, levers, reach).
// Parsing of the URDF and the sidecar is in hand_model_load.cpp.
#include "taskmap/hands/hand_model.hpp"

#include <algorithm>
#include <cmath>

#include "taskmap/core/error.hpp"

namespace taskmap {

double CollisionShape::thickness() const {
  switch (type) {
    case ShapeType::kBox:
      return box_size.minCoeff();
    case ShapeType::kCylinder:
      return std::min(2.0 * radius, length);
    case ShapeType::kSphere:
      return 2.0 * radius;
    case ShapeType::kConvex: {
      if (points.empty()) return 0.0;
      Eigen::Vector3d lo = points.front(), hi = points.front();
      for (const auto& p : points) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
      return (hi - lo).minCoeff();
    }
  }
  return 0.0;
}

double CollisionShape::boundingRadius() const {
  switch (type) {
    case ShapeType::kBox:
      return 0.5 * box_size.norm();
    case ShapeType::kCylinder:
      return std::hypot(radius, 0.5 * length);
    case ShapeType::kSphere:
      return radius;
    case ShapeType::kConvex: {
      double r = 0.0;
      for (const auto& p : points) r = std::max(r, p.norm());
      return r;
    }
  }
  return 0.0;
}

const std::string& HandModel::name() const {
  return name_;
}
const Eigen::Isometry3d& HandModel::rootToPalm() const {
  return root_to_palm_;
}
const std::string& HandModel::robotName() const {
  return robot_name_;
}
const std::string& HandModel::urdfSha256() const {
  return sha_;
}
const std::string& HandModel::urdfPath() const {
  return urdf_path_;
}
const std::string& HandModel::modelFormat() const {
  return format_;
}
const HandDynamics& HandModel::dynamics() const {
  return dynamics_;
}
const std::vector<std::string>& HandModel::loadWarnings() const {
  return load_warnings_;
}
const std::string& HandModel::sidecarPath() const {
  return sidecar_path_;
}
std::vector<std::string> HandModel::jointNames() const {
  return actuated_;
}
Eigen::VectorXd HandModel::preshape() const {
  return preshape_;
}
Eigen::Vector3d HandModel::approachAxis() const {
  return approach_;
}
double HandModel::rotationScale() const {
  return rotation_scale_;
}
double HandModel::reach() const {
  return reach_;
}
const std::vector<HandLink>& HandModel::links() const {
  return links_;
}
const std::vector<HandJoint>& HandModel::joints() const {
  return joints_;
}
int HandModel::palmLink() const {
  return palm_link_;
}
const Eigen::Isometry3d& HandModel::palmFrame() const {
  return palm_frame_;
}
const std::vector<ClosingJoint>& HandModel::closing() const {
  return closing_;
}
double HandModel::squeeze() const {
  return squeeze_;
}
const std::vector<std::vector<int>>& HandModel::coupledClosing() const {
  return coupled_;
}
GraspMode HandModel::graspMode() const {
  return grasp_mode_;
}
double HandModel::standoff() const {
  return standoff_;
}
const std::optional<Eigen::Isometry3d>& HandModel::mount() const {
  return mount_;
}
bool HandModel::hasStandoff() const {
  return has_standoff_;
}
const std::vector<CollisionMeshInfo>& HandModel::collisionMeshes() const {
  return collision_meshes_;
}
const std::vector<std::string>& HandModel::fingerNames() const {
  return fingers_;
}
const std::vector<std::vector<int>>& HandModel::linkDrivers() const {
  return link_drivers_;
}
const std::vector<double>& HandModel::jointLevers() const {
  return levers_;
}

Eigen::VectorXd HandModel::lowerLimits() const {
  return Eigen::Map<const Eigen::VectorXd>(lower_.data(), static_cast<Eigen::Index>(lower_.size()));
}

Eigen::VectorXd HandModel::upperLimits() const {
  return Eigen::Map<const Eigen::VectorXd>(upper_.data(), static_cast<Eigen::Index>(upper_.size()));
}

int HandModel::linkIndex(const std::string& n) const {
  for (std::size_t i = 0; i < links_.size(); ++i)
    if (links_[i].name == n) return static_cast<int>(i);
  return -1;
}

int HandModel::jointIndex(const std::string& n) const {
  for (std::size_t i = 0; i < actuated_.size(); ++i)
    if (actuated_[i] == n) return static_cast<int>(i);
  return -1;
}

Eigen::VectorXd HandModel::allJointValues(const Eigen::VectorXd& q) const {
  if (q.size() != static_cast<Eigen::Index>(actuated_.size()))
    throw Error("hand '" + name_ + "': joint vector has " + std::to_string(q.size()) +
                " values, expected " + std::to_string(actuated_.size()) + " (jointNames())");
  Eigen::VectorXd all(static_cast<Eigen::Index>(joints_.size()));
  for (std::size_t j = 0; j < joints_.size(); ++j) {
    const HandJoint& jt = joints_[j];
    all[static_cast<Eigen::Index>(j)] =
        jt.driver < 0 ? 0.0 : jt.multiplier * q[jt.driver] + jt.offset;
  }
  return all;
}

std::vector<Eigen::Isometry3d> HandModel::linkPoses(const Eigen::VectorXd& q) const {
  std::vector<Eigen::Isometry3d> poses;
  linkPoses(q, &poses);
  return poses;
}

void HandModel::linkPoses(const Eigen::VectorXd& q, std::vector<Eigen::Isometry3d>* out) const {
  if (q.size() != static_cast<Eigen::Index>(actuated_.size()))
    throw Error("hand '" + name_ + "': joint vector has " + std::to_string(q.size()) +
                " values, expected " + std::to_string(actuated_.size()) + " (jointNames())");
  std::vector<Eigen::Isometry3d>& poses = *out;
  poses.assign(links_.size(), Eigen::Isometry3d::Identity());
  // Root-frame poses; joints_ lists parents before children.
  for (const HandJoint& jt : joints_) {
    Eigen::Isometry3d t = poses[static_cast<std::size_t>(jt.parent_link)] * jt.origin;
    if (jt.driver >= 0) {
      const auto d = static_cast<std::size_t>(jt.driver);
      const double v = jt.multiplier * std::clamp(q[jt.driver], lower_[d], upper_[d]) + jt.offset;
      if (jt.type == JointType::kRevolute)
        t.rotate(Eigen::AngleAxisd(v, jt.axis));
      else if (jt.type == JointType::kPrismatic)
        t.translate(v * jt.axis);
    }
    poses[static_cast<std::size_t>(jt.child_link)] = t;
  }
  // The palm frame is often the root's: the product with the identity changes nothing.
  if (palm_from_root_.matrix() == Eigen::Matrix4d::Identity()) return;
  for (auto& p : poses) p = palm_from_root_ * p;
}

}  // namespace taskmap
