// The build's hold filter: contact Jacobians and actuator efforts of a grasp (docs/METHOD.md
// §4b). A contact at p on link l moves with every non-fixed joint k on l's chain to the palm:
// dp/dq_k = a_k x (p - o_k) (revolute) or a_k (prismatic), a_k and o_k the joint's axis and
// origin in the object frame at the grasp; k follows actuated joint d(k) with q_k =
// m_k q_d + offset, so J[d(k)] += m_k dp/dq_k.
#include "taskmap/builder/hold_filter.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "taskmap/core/error.hpp"
#include "taskmap/hands/hand_drive.hpp"

namespace taskmap {
namespace {

/// The URDF joint of each actuated joint (the one that is not a mimic of another).
std::vector<const HandJoint*> actuatedJoints(const HandModel& hand) {
  const std::vector<std::string> names = hand.jointNames();
  std::vector<const HandJoint*> out(names.size(), nullptr);
  for (const HandJoint& j : hand.joints())
    for (std::size_t a = 0; a < names.size(); ++a)
      if (j.name == names[a]) out[a] = &j;
  return out;
}

Eigen::VectorXd efforts(const HandModel& hand, const Eigen::VectorXd& q,
                        const HoldFilterOptions& o) {
  const std::vector<const HandJoint*> act = actuatedJoints(hand);
  const std::vector<JointDrive> drives =
      actuatorDrives(hand, {o.kp_revolute, o.kp_prismatic, o.jaw_force, o.revolute_gripper_force});
  const Eigen::VectorXd q0 = hand.preshape();
  Eigen::VectorXd e = Eigen::VectorXd::Zero(q.size());
  for (Eigen::Index a = 0; a < q.size(); ++a) {
    const HandJoint* j = act[static_cast<std::size_t>(a)];
    if (j == nullptr) continue;
    const double target =
        std::clamp(q0(a) + o.squeeze_fraction * (q(a) - q0(a)), j->lower, j->upper);
    const JointDrive& d = drives[static_cast<std::size_t>(a)];
    e(a) = std::clamp(d.kp * (target - q(a)), -d.limit, d.limit);
  }
  return e;
}

}  // namespace

void HoldFilterOptions::validate() const {
  balance.validate();
  if (!(kp_revolute > 0.0) || !std::isfinite(kp_revolute))
    throw Error("hold filter: kp_revolute must be finite and > 0 (N m/rad)");
  if (!(kp_prismatic > 0.0) || !std::isfinite(kp_prismatic))
    throw Error("hold filter: kp_prismatic must be finite and > 0 (N/m)");
  if (!(jaw_force > 0.0) || !std::isfinite(jaw_force))
    throw Error("hold filter: jaw_force must be finite and > 0 (N)");
  if (!(squeeze_fraction >= 1.0 && squeeze_fraction <= 2.0))
    throw Error("hold filter: squeeze_fraction must be in [1, 2]");
}

SqueezeDrive squeezeDrive(const HandModel& hand, const Pose& palm, const Eigen::VectorXd& joints,
                          const std::vector<Contact>& contacts, const HoldFilterOptions& options) {
  const auto n = static_cast<Eigen::Index>(hand.jointNames().size());
  if (joints.size() != n)
    throw Error("hold filter: " + std::to_string(joints.size()) + " joint values for hand '" +
                hand.name() + "' with " + std::to_string(n) + " actuated joints");
  SqueezeDrive drive;
  drive.effort = efforts(hand, joints, options);
  drive.lever = Eigen::VectorXd::Ones(n);
  const std::vector<double>& levers = hand.jointLevers();
  const std::vector<const HandJoint*> act = actuatedJoints(hand);
  for (Eigen::Index a = 0; a < n; ++a)
    if (act[static_cast<std::size_t>(a)] != nullptr &&
        act[static_cast<std::size_t>(a)]->type == JointType::kRevolute)
      drive.lever(a) = std::max(levers[static_cast<std::size_t>(a)], 1e-3);
  const std::vector<Eigen::Isometry3d> links = hand.linkPoses(joints);
  const Eigen::Isometry3d to_object = palm.toIsometry();
  const std::vector<HandLink>& hl = hand.links();
  const std::vector<HandJoint>& hj = hand.joints();
  drive.jacobians.reserve(contacts.size());
  for (const Contact& c : contacts) {
    Eigen::Matrix<double, Eigen::Dynamic, 3> jac =
        Eigen::Matrix<double, Eigen::Dynamic, 3>::Zero(n, 3);
    int l = c.link;
    while (l >= 0 && l < static_cast<int>(hl.size())) {
      const int ji = hl[static_cast<std::size_t>(l)].parent_joint;
      if (ji < 0) break;
      const HandJoint& j = hj[static_cast<std::size_t>(ji)];
      if (j.type != JointType::kFixed && j.driver >= 0) {
        const Eigen::Isometry3d child = to_object * links[static_cast<std::size_t>(j.child_link)];
        const Eigen::Vector3d axis = child.linear() * j.axis;
        const Eigen::Vector3d v = j.type == JointType::kRevolute
                                      ? Eigen::Vector3d(axis.cross(c.point - child.translation()))
                                      : axis;
        jac.row(j.driver) += j.multiplier * v.transpose();
      }
      l = j.parent_link;
    }
    drive.jacobians.push_back(std::move(jac));
  }
  return drive;
}

double squeezeForce(const std::vector<Contact>& contacts, const SqueezeDrive& drive) {
  if (drive.jacobians.size() != contacts.size())
    throw Error("squeeze force: " + std::to_string(drive.jacobians.size()) + " Jacobians for " +
                std::to_string(contacts.size()) + " contacts");
  double force = 0.0;
  for (std::size_t c = 0; c < contacts.size(); ++c) {
    const auto& jac = drive.jacobians[c];
    for (Eigen::Index a = 0; a < jac.rows(); ++a) {
      const double lever = jac.row(a).norm();
      const double e = drive.effort(a);
      if (lever < 1e-9 || e * jac.row(a).dot(contacts[c].normal) >= 0.0) continue;
      force = std::max(force, std::abs(e) / lever);
    }
  }
  return force;
}

double graspSqueezeForce(const HandModel& hand, const Pose& palm, const Eigen::VectorXd& joints,
                         const std::vector<Contact>& contacts) {
  HoldFilterOptions drive_options;
  drive_options.revolute_gripper_force = true;  // the hold test's drive
  return squeezeForce(contacts, squeezeDrive(hand, palm, joints, contacts, drive_options));
}

}  // namespace taskmap
