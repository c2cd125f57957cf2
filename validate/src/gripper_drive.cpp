// The force-limited drive of a one-joint revolute gripper (docs/VALIDATION.md, "Grippers driven
// by a revolute joint").
#include "gripper_drive.hpp"

#include <cmath>
#include <vector>

namespace taskmap::detail {
namespace {

/// Per finger, the link farthest from the root along the tree (its tip link).
std::vector<int> tipLinks(const HandModel& hand) {
  const auto& links = hand.links();
  const auto& joints = hand.joints();
  const auto depth = [&](int l) {
    int d = 0;
    for (int j = links[static_cast<std::size_t>(l)].parent_joint; j >= 0;
         j = links[static_cast<std::size_t>(joints[static_cast<std::size_t>(j)].parent_link)]
                 .parent_joint)
      ++d;
    return d;
  };
  std::vector<int> tip(hand.fingerNames().size(), -1);
  std::vector<int> best(tip.size(), -1);
  for (std::size_t l = 0; l < links.size(); ++l) {
    const int f = links[l].finger;
    if (f < 0) continue;
    const int d = depth(static_cast<int>(l));
    if (d > best[static_cast<std::size_t>(f)]) {
      best[static_cast<std::size_t>(f)] = d;
      tip[static_cast<std::size_t>(f)] = static_cast<int>(l);
    }
  }
  std::vector<int> out;
  for (int l : tip)
    if (l >= 0) out.push_back(l);
  return out;
}

}  // namespace

GripperDrive revoluteGripperDrive(const HandModel& hand, double jaw_force, double kp_prismatic) {
  const std::vector<std::string> names = hand.jointNames();
  if (names.size() != 1) return {};
  const HandJoint* joint = nullptr;
  for (const HandJoint& j : hand.joints())
    if (j.name == names[0]) joint = &j;
  if (joint == nullptr || joint->type != JointType::kRevolute) return {};
  const std::vector<int> tips = tipLinks(hand);
  if (tips.size() < 2) return {};
  const double lo = hand.lowerLimits()(0), hi = hand.upperLimits()(0);
  const double mid = 0.5 * (lo + hi), h = 1e-5 * std::max(hi - lo, 1e-3);
  const auto tipsAt = [&](double q) {
    const std::vector<Eigen::Isometry3d> poses = hand.linkPoses(Eigen::VectorXd::Constant(1, q));
    std::vector<Eigen::Vector3d> out;
    for (int l : tips) out.push_back(poses[static_cast<std::size_t>(l)].translation());
    return out;
  };
  const std::vector<Eigen::Vector3d> at = tipsAt(mid), plus = tipsAt(mid + h),
                                     minus = tipsAt(mid - h);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : at) centroid += p / static_cast<double>(at.size());
  GripperDrive drive;
  double squares = 0.0;
  for (std::size_t k = 0; k < at.size(); ++k) {
    const Eigen::Vector3d toward = centroid - at[k];
    if (!(toward.norm() > 0.0)) continue;
    const double speed = toward.normalized().dot((plus[k] - minus[k]) / (2.0 * h));
    drive.lever += std::abs(speed);
    squares += speed * speed;
  }
  if (!(drive.lever > 0.0)) return {};  // no tip closes: not a gripper
  drive.torque = jaw_force * drive.lever;
  drive.kp = kp_prismatic * squares;
  return drive;
}

}  // namespace taskmap::detail
