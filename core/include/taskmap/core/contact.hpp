#pragma once
/// @file contact.hpp
/// A contact between a hand link and the object, as grasp_sim produces and quality consumes.

#include <Eigen/Core>

namespace taskmap {

/// One contact in the object frame.
struct Contact {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();    ///< on the object surface, metres
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< unit, pointing out of the object
  double depth = 0.0;  ///< penetration of the link into the object, metres; > 0 carries pressure
  int link = -1;       ///< index of the hand link (HandModel::links()), -1 if unknown
};

}  // namespace taskmap
