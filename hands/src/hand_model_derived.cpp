// HandModel loading, derived-quantity step: palm-rigid links, palm frame in the root frame,
// drivers of each link, lever bounds of each actuated joint, reach and rotation scale.
#include <algorithm>
#include <cmath>
#include <functional>
#include <set>

#include "hand_model_build.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

/// Largest distance from the origin to a point of shape `s` placed at pose `t`, metres.
double farthestPoint(const CollisionShape& s, const Eigen::Isometry3d& t) {
  double r = 0.0;
  switch (s.type) {
    case ShapeType::kBox:
      for (int i = 0; i < 8; ++i) {
        const Eigen::Vector3d c((i & 1 ? 0.5 : -0.5) * s.box_size.x(),
                                (i & 2 ? 0.5 : -0.5) * s.box_size.y(),
                                (i & 4 ? 0.5 : -0.5) * s.box_size.z());
        r = std::max(r, (t * c).norm());
      }
      break;
    case ShapeType::kCylinder:
      // Farthest point of each end disc: axial offset and radial offset plus the radius.
      for (double side : {-0.5, 0.5}) {
        const Eigen::Vector3d c = t * Eigen::Vector3d(0, 0, side * s.length);
        const Eigen::Vector3d n = t.linear().col(2);
        const double axial = c.dot(n);
        const double radial = (c - axial * n).norm() + s.radius;
        r = std::max(r, std::hypot(axial, radial));
      }
      break;
    case ShapeType::kSphere:
      r = t.translation().norm() + s.radius;
      break;
    case ShapeType::kConvex:
      for (const auto& p : s.points) r = std::max(r, (t * p).norm());
      break;
  }
  return r;
}

/// Marks the palm link and every link joined to it by fixed joints (above or below) as palm.
void markPalmRigid(std::vector<HandLink>& links, const std::vector<HandJoint>& joints, int palm,
                   const std::string& S) {
  links[static_cast<std::size_t>(palm)].palm = true;
  for (const HandJoint& j : joints) {
    const auto child = static_cast<std::size_t>(j.child_link);
    if (j.type == JointType::kFixed && links[static_cast<std::size_t>(j.parent_link)].palm)
      links[child].palm = true;
  }
  // Links above the palm attached by fixed joints also move with it.
  for (int pass = 0; pass < 2; ++pass)
    for (const HandJoint& j : joints) {
      if (j.type != JointType::kFixed) continue;
      auto& parent = links[static_cast<std::size_t>(j.parent_link)];
      auto& child = links[static_cast<std::size_t>(j.child_link)];
      if (child.palm) parent.palm = true;
      if (parent.palm) child.palm = true;
    }
  for (const HandLink& l : links)
    if (l.palm && l.finger >= 0)
      throw Error(S + "finger link '" + l.name + "' is rigidly attached to the palm");
}

/// Pose of link `li` in the root frame through its (fixed) parent joints.
Eigen::Isometry3d rootToLink(const std::vector<HandLink>& links,
                             const std::vector<HandJoint>& joints, int li) {
  std::vector<const HandJoint*> chain;
  while (links[static_cast<std::size_t>(li)].parent_joint >= 0) {
    const HandJoint& j =
        joints[static_cast<std::size_t>(links[static_cast<std::size_t>(li)].parent_joint)];
    chain.push_back(&j);
    li = j.parent_link;
  }
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  for (auto it = chain.rbegin(); it != chain.rend(); ++it) t = t * (*it)->origin;
  return t;
}

/// For each link, the actuated joints moving it relative to the palm (none for palm links).
std::vector<std::vector<int>> linkDriversOf(const std::vector<HandLink>& links,
                                            const std::vector<HandJoint>& joints) {
  std::vector<std::vector<int>> out(links.size());
  for (std::size_t li = 0; li < links.size(); ++li) {
    std::set<int> drivers;
    int cur = static_cast<int>(li);
    while (links[static_cast<std::size_t>(cur)].parent_joint >= 0) {
      const HandJoint& j =
          joints[static_cast<std::size_t>(links[static_cast<std::size_t>(cur)].parent_joint)];
      if (j.driver >= 0 && !links[li].palm) drivers.insert(j.driver);
      cur = j.parent_link;
    }
    out[li].assign(drivers.begin(), drivers.end());
  }
  return out;
}

/// Max distance from a joint origin to any point of its subtree, independent of joint values:
/// sum of joint offsets (+ prismatic travel) down the chain plus the shape's bounding radius.
double subtreeExtent(const std::vector<HandLink>& links, const std::vector<HandJoint>& joints,
                     int li) {
  const HandLink& l = links[static_cast<std::size_t>(li)];
  double r = 0.0;
  for (const auto& s : l.shapes)
    r = std::max(r, s.origin.translation().norm() + s.boundingRadius());
  for (const HandJoint& j : joints) {
    if (j.parent_link != li) continue;
    double travel = j.origin.translation().norm();
    if (j.type == JointType::kPrismatic) travel += std::max(std::abs(j.lower), std::abs(j.upper));
    r = std::max(r, travel + subtreeExtent(links, joints, j.child_link));
  }
  return r;
}

}  // namespace

void HandModelBuilder::derive(HandModel& h, const nlohmann::json& js) {
  const std::string S = "hand sidecar '" + h.sidecar_path_ + "': ";
  markPalmRigid(h.links_, h.joints_, h.palm_link_, S);
  // Palm frame in the root frame (constant: the palm hangs from the root by fixed joints).
  h.root_to_palm_ = rootToLink(h.links_, h.joints_, h.palm_link_) * h.palm_frame_;
  h.palm_from_root_ = h.root_to_palm_.inverse();
  h.link_drivers_ = linkDriversOf(h.links_, h.joints_);
  h.levers_.assign(h.actuated_.size(), 0.0);
  for (const HandJoint& j : h.joints_) {
    if (j.driver < 0) continue;
    const double lever =
        j.type == JointType::kPrismatic ? 1.0 : subtreeExtent(h.links_, h.joints_, j.child_link);
    double& l = h.levers_[static_cast<std::size_t>(j.driver)];
    l = std::max(l, std::abs(j.multiplier) * lever);
  }

  // Reach and rotation scale from the open hand: the farthest point of any (finger) shape
  // from the palm origin.
  const auto poses = h.linkPoses(h.preshape_);
  double reach = 0.0, finger_reach = 0.0;
  for (std::size_t li = 0; li < h.links_.size(); ++li)
    for (const auto& s : h.links_[li].shapes) {
      const double r = farthestPoint(s, poses[li] * s.origin);
      reach = std::max(reach, r);
      if (h.links_[li].finger >= 0) finger_reach = std::max(finger_reach, r);
    }
  h.reach_ = reach;
  h.rotation_scale_ = finger_reach > 0.0 ? finger_reach : reach;
  if (js.contains("rotation_scale")) {
    const nlohmann::json& v = js["rotation_scale"];
    if (!v.is_number()) throw Error(S + "rotation_scale must be a number");
    if (!std::isfinite(v.get<double>())) throw Error(S + "rotation_scale must be finite");
    h.rotation_scale_ = v.get<double>();
    if (!(h.rotation_scale_ > 0.0)) throw Error(S + "rotation_scale must be positive");
  }
}

}  // namespace taskmap
