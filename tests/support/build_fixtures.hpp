#pragma once
// The small build every builder test and benchmark runs: the 4 x 5 x 12 cm box with the
// Franka gripper (meshes/hands/panda/), and the gripper's squeeze of it from the top. Needs
// TASKMAP_HANDS_DIR.
#include <string>

#include "taskmap/core/pose.hpp"
#include "taskmap/hands/hand_model.hpp"
#include "taskmap/meshes/object_model.hpp"
#include "test_meshes.hpp"

namespace taskmap::testing {

/// The 4 x 5 x 12 cm box, loaded once.
inline const ObjectModel& boxObject() {
  static const ObjectModel object = ObjectModel::fromMesh(makeBox(0.04, 0.05, 0.12), "box");
  return object;
}

/// The gripper's palm above the box, `height` metres up its z axis, approaching down (-z) with
/// the jaws closing along the box's x (its 4 cm side): the hold tests' squeeze of the box.
inline Pose topBoxGrasp(double height) {
  Eigen::Matrix3d r;
  r.col(0) = Eigen::Vector3d(0, 1, 0);
  r.col(1) = Eigen::Vector3d(1, 0, 0);
  r.col(2) = Eigen::Vector3d(0, 0, -1);
  Pose p;
  p.position = Eigen::Vector3d(0, 0, height);
  p.orientation = Eigen::Quaterniond(r);
  return p;
}

/// The bundled Franka gripper, loaded once.
inline const HandModel& pandaHand() {
  static const HandModel hand =
      HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/panda/panda.urdf");
  return hand;
}

}  // namespace taskmap::testing
