// How the physics models drive a hand's joints (docs/VALIDATION.md, "Parameters", and
// docs/history/validation-2026-11.md, "Grippers driven by a revolute joint").
#include "taskmap/hands/hand_drive.hpp"

#include <cmath>
#include <cstddef>
#include <string>

namespace taskmap {
namespace {

std::size_t at(int i) {
  return static_cast<std::size_t>(i);
}

/// Per finger with links, the link farthest from the root along the tree (its tip link).
std::vector<int> tipLinks(const HandModel& hand) {
  const auto& links = hand.links();
  const auto& joints = hand.joints();
  const auto depth = [&](int l) {
    int d = 0;
    for (int j = links[at(l)].parent_joint; j >= 0;
         j = links[at(joints[at(j)].parent_link)].parent_joint)
      ++d;
    return d;
  };
  std::vector<int> tip(hand.fingerNames().size(), -1);
  std::vector<int> best(tip.size(), -1);
  for (std::size_t l = 0; l < links.size(); ++l) {
    const int f = links[l].finger;
    if (f < 0) continue;
    const int d = depth(static_cast<int>(l));
    if (d > best[at(f)]) {
      best[at(f)] = d;
      tip[at(f)] = static_cast<int>(l);
    }
  }
  std::vector<int> out;
  for (int l : tip)
    if (l >= 0) out.push_back(l);
  return out;
}

/// The URDF joint of actuated joint `a`.
const HandJoint* actuatedJoint(const HandModel& hand, std::size_t a) {
  const std::string name = hand.jointNames()[a];
  for (const HandJoint& j : hand.joints())
    if (j.name == name) return &j;
  return nullptr;
}

/// 1 + |multiplier| of the prismatic joints that actuated joint `a` drags along (mimic jaws).
double jawShare(const HandModel& hand, int a, const std::string& name) {
  double share = 1.0;
  for (const HandJoint& j : hand.joints())
    if (j.driver == a && j.name != name && j.type == JointType::kPrismatic)
      share += std::abs(j.multiplier);
  return share;
}

/// The tips' positions at actuated value q, and their centroid.
struct Tips {
  std::vector<int> links;
  std::vector<Eigen::Isometry3d> poses;  ///< every link's pose at q (root frame)
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
};

Tips tipsAt(const HandModel& hand, const std::vector<int>& links, double q) {
  Tips t;
  t.links = links;
  t.poses = hand.linkPoses(Eigen::VectorXd::Constant(1, q));
  for (int l : links)
    t.centroid += t.poses[at(l)].translation() / static_cast<double>(links.size());
  return t;
}

/// True when joint j lies on the chain from the root to link l.
bool moves(const HandModel& hand, int j, int l) {
  for (int k = hand.links()[at(l)].parent_joint; k >= 0;
       k = hand.links()[at(hand.joints()[at(k)].parent_link)].parent_joint)
    if (k == j) return true;
  return false;
}

/// Per tip, its closing speed (toward the centroid) per unit of URDF joint j's own value.
std::vector<double> tipSpeeds(const HandModel& hand, const Tips& t, int j) {
  const HandJoint& joint = hand.joints()[at(j)];
  const Eigen::Isometry3d frame = t.poses[at(joint.parent_link)] * joint.origin;
  const Eigen::Vector3d axis = frame.linear() * joint.axis;
  std::vector<double> out;
  for (int l : t.links) {
    const Eigen::Vector3d tip = t.poses[at(l)].translation();
    const Eigen::Vector3d toward = t.centroid - tip;
    if (!moves(hand, j, l) || !(toward.norm() > 0.0)) {
      out.push_back(0.0);
      continue;
    }
    const Eigen::Vector3d v = joint.type == JointType::kPrismatic
                                  ? axis
                                  : Eigen::Vector3d(axis.cross(tip - frame.translation()));
    out.push_back(toward.normalized().dot(v));
  }
  return out;
}

double midRange(const HandModel& hand) {
  return 0.5 * (hand.lowerLimits()(0) + hand.upperLimits()(0));
}

}  // namespace

RevoluteGripper revoluteGripper(const HandModel& hand, const DriveOptions& options) {
  if (!options.revolute_gripper_force || hand.jointNames().size() != 1) return {};
  const HandJoint* joint = actuatedJoint(hand, 0);
  if (joint == nullptr || joint->type != JointType::kRevolute) return {};
  const std::vector<int> tips = tipLinks(hand);
  if (tips.size() < 2) return {};
  const double lo = hand.lowerLimits()(0), hi = hand.upperLimits()(0);
  const double mid = midRange(hand), h = 1e-5 * std::max(hi - lo, 1e-3);
  const Tips now = tipsAt(hand, tips, mid), plus = tipsAt(hand, tips, mid + h),
             minus = tipsAt(hand, tips, mid - h);
  RevoluteGripper drive;
  double squares = 0.0;
  for (int l : tips) {
    const Eigen::Vector3d toward = now.centroid - now.poses[at(l)].translation();
    if (!(toward.norm() > 0.0)) continue;
    const Eigen::Vector3d velocity =
        (plus.poses[at(l)].translation() - minus.poses[at(l)].translation()) / (2.0 * h);
    const double speed = toward.normalized().dot(velocity);
    drive.lever += std::abs(speed);
    squares += speed * speed;
  }
  if (!(drive.lever > 0.0)) return {};  // no tip closes: not a gripper
  drive.torque = options.jaw_force * drive.lever;
  drive.kp = options.kp_prismatic * squares;
  drive.squares = squares;
  return drive;
}

std::vector<JointDrive> actuatorDrives(const HandModel& hand, const DriveOptions& options) {
  const RevoluteGripper gripper = revoluteGripper(hand, options);
  std::vector<JointDrive> out(hand.jointNames().size());
  for (std::size_t a = 0; a < out.size(); ++a) {
    const HandJoint* j = actuatedJoint(hand, a);
    if (j != nullptr && j->type == JointType::kPrismatic)
      out[a] = {options.kp_prismatic,
                options.jaw_force * jawShare(hand, static_cast<int>(a), j->name)};
    else if (gripper.lever > 0.0)
      out[a] = {gripper.kp, gripper.torque};
    else
      out[a] = {options.kp_revolute, JointDrive{}.limit};
  }
  return out;
}

std::vector<JointDrive> jointDrives(const HandModel& hand, const DriveOptions& options) {
  const RevoluteGripper gripper = revoluteGripper(hand, options);
  const std::vector<HandJoint>& joints = hand.joints();
  std::vector<JointDrive> out(joints.size());
  Tips tips;
  if (gripper.lever > 0.0) tips = tipsAt(hand, tipLinks(hand), midRange(hand));
  for (std::size_t k = 0; k < joints.size(); ++k) {
    const HandJoint& j = joints[k];
    if (j.type == JointType::kFixed) {
      out[k] = {0.0, 0.0};
    } else if (j.type == JointType::kPrismatic) {
      out[k] = {options.kp_prismatic, options.jaw_force};
    } else if (gripper.lever > 0.0) {
      double sum = 0.0, squares = 0.0;
      for (double s : tipSpeeds(hand, tips, static_cast<int>(k))) {
        sum += std::abs(s);
        squares += s * s;
      }
      // A joint that hardly moves a tip (the pad's parallel-keeping joint, a loose link of the
      // four-bar) holds the linkage with the actuator's drive.
      if (sum > 1e-3 * gripper.lever)
        out[k] = {options.kp_prismatic * squares, options.jaw_force * sum};
      else
        out[k] = {gripper.kp, gripper.torque};
    } else {
      out[k] = {options.kp_revolute, JointDrive{}.limit};
    }
  }
  return out;
}

}  // namespace taskmap
