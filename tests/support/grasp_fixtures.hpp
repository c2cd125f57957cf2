#pragma once
// Grasp-simulation fixtures shared by the grasp_sim unit tests (grasp_simulator_test.cpp,
// coupled_closing_test.cpp): the reference hands, the contact tolerance and the top-down palm
// pose of the box-hand cases.

#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "taskmap/core/pose.hpp"
#include "taskmap/meshes/hand_model.hpp"

namespace taskmap::testing {

/// GraspSimOptions::contact_tolerance default, metres.
constexpr double kContactTolerance = 5e-4;

/// A bundled reference hand (TASKMAP_HANDS_DIR/<name>/<name>.urdf): panda, barrett, humanoid.
inline HandModel referenceHand(const std::string& name) {
  return HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/" + name + "/" + name + ".urdf");
}

/// A test hand in its own folder (TEST_DATA_DIR/hands/<name>/<name>.urdf).
inline std::string testHandPath(const std::string& name) {
  return std::string(TEST_DATA_DIR) + "/hands/" + name + "/" + name + ".urdf";
}

/// Palm pose at `p` whose approach axis (palm z) points along -z of the object and whose palm
/// y axis (the Panda's finger motion, the jaws' closing direction) is the object's x axis.
inline Pose fromAbove(const Eigen::Vector3d& p) {
  Eigen::Matrix3d r;
  r << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  Pose pose;
  pose.position = p;
  pose.orientation = Eigen::Quaterniond(r);
  return pose;
}

}  // namespace taskmap::testing
