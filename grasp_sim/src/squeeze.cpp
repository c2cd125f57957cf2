// Squeeze after contact: first-order joint increments that press each contact by a distance.
#include "squeeze.hpp"

#include <algorithm>
#include <cmath>

namespace taskmap {

Eigen::Vector3d pointVelocity(const HandModel& hand, const Eigen::Isometry3d& palm,
                              const std::vector<Eigen::Isometry3d>& poses, int link,
                              const Eigen::Vector3d& point, int joint) {
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  const auto& links = hand.links();
  int cur = link;
  while (links[static_cast<std::size_t>(cur)].parent_joint >= 0) {
    const HandJoint& hj =
        hand.joints()[static_cast<std::size_t>(links[static_cast<std::size_t>(cur)].parent_joint)];
    if (hj.driver == joint) {
      const Eigen::Isometry3d jf =
          palm * poses[static_cast<std::size_t>(hj.parent_link)] * hj.origin;
      const Eigen::Vector3d ax = jf.linear() * hj.axis;
      if (hj.type == JointType::kRevolute)
        v += hj.multiplier * ax.cross(point - jf.translation());
      else if (hj.type == JointType::kPrismatic)
        v += hj.multiplier * ax;
    }
    cur = hj.parent_link;
  }
  return v;
}

void applySqueeze(const HandModel& hand, const Eigen::Isometry3d& palm,
                  const std::vector<Eigen::Isometry3d>& poses,
                  const std::vector<SqueezeContact>& contacts, double squeeze, Eigen::VectorXd* q) {
  // Proximal joints first: order by the position of the actuated joint in the tree (joints()
  // lists parents before children).
  std::vector<int> tree_index(hand.jointNames().size(), 0);
  for (std::size_t j = 0; j < hand.joints().size(); ++j) {
    const HandJoint& hj = hand.joints()[j];
    if (hj.driver >= 0 && !hj.mimic)
      tree_index[static_cast<std::size_t>(hj.driver)] = static_cast<int>(j);
  }
  std::vector<std::size_t> order(contacts.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return tree_index[static_cast<std::size_t>(contacts[a].joint)] <
           tree_index[static_cast<std::size_t>(contacts[b].joint)];
  });
  std::vector<double> delta(contacts.size(), 0.0);  // joint increments, closing direction
  for (std::size_t k = 0; k < order.size(); ++k) {
    const SqueezeContact& c = contacts[order[k]];
    // Pressing already done at this contact by the joints squeezed before.
    double pressed = 0.0;
    for (std::size_t m = 0; m < k; ++m) {
      const SqueezeContact& o = contacts[order[m]];
      const Eigen::Vector3d v = o.dir * pointVelocity(hand, palm, poses, c.link, c.point, o.joint);
      pressed += delta[order[m]] * -c.normal.dot(v);
    }
    const Eigen::Vector3d v = c.dir * pointVelocity(hand, palm, poses, c.link, c.point, c.joint);
    const double rate = -c.normal.dot(v);
    // A joint that moves its contact point mostly along the surface cannot press it.
    if (!(rate > 0.25 * v.norm()) || !(rate > 1e-12)) continue;
    const double need = squeeze + std::max(c.gap, 0.0) - pressed;
    if (need <= 0.0) continue;
    const double current = (*q)[c.joint];
    const double value = current + c.dir * need / rate;
    const double clamped = c.dir > 0 ? std::min(value, c.target) : std::max(value, c.target);
    (*q)[c.joint] = clamped;
    delta[order[k]] = std::abs(clamped - current);
  }
}

}  // namespace taskmap
