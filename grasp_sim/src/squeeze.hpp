#pragma once
// Private to grasp_sim: the squeeze after contact (no Bullet here).

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "taskmap/hands/hand_model.hpp"

namespace taskmap {

/// A closing joint stopped by a contact, with the contact it presses.
struct SqueezeContact {
  int joint = -1;                                     ///< index into HandModel::jointNames()
  int link = -1;                                      ///< link whose contact stopped the joint
  Eigen::Vector3d point = Eigen::Vector3d::Zero();    ///< contact point, object frame
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< outward object normal there
  double gap = 0.0;     ///< signed distance of the link at the contact, metres
  double dir = 1.0;     ///< +1 when the joint closes toward its upper limit, -1 toward lower
  double target = 0.0;  ///< closed limit of the joint
};

/// Velocity (object frame) of `point`, rigidly attached to `link`, per unit of actuated joint
/// `joint`; `palm` is the palm pose, `poses` the link poses in the palm frame.
Eigen::Vector3d pointVelocity(const HandModel& hand, const Eigen::Isometry3d& palm,
                              const std::vector<Eigen::Isometry3d>& poses, int link,
                              const Eigen::Vector3d& point, int joint);

/// Advances the contact-stopped joints of `q` so that each contact point is pressed `squeeze`
/// metres into the object (to first order), proximal joints first: a distal joint only adds
/// what its ancestors' squeeze did not already press. Joints that move their contact point
/// mostly along the surface are left alone; joints stop at their limits.
void applySqueeze(const HandModel& hand, const Eigen::Isometry3d& palm,
                  const std::vector<Eigen::Isometry3d>& poses,
                  const std::vector<SqueezeContact>& contacts, double squeeze, Eigen::VectorXd* q);

}  // namespace taskmap
