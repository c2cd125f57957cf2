#pragma once
// Grasp-simulation fixtures shared by the grasp_sim unit tests (grasp_simulator_test.cpp,
// coupled_closing_test.cpp, contact_depths_test.cpp): the reference hands, the contact tolerance,
// the top-down palm pose of the box-hand cases and random poses around an object.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "taskmap/core/pose.hpp"
#include "taskmap/core/random.hpp"
#include "taskmap/hands/hand_model.hpp"

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

/// `n` poses uniform in the box [lo, hi] with uniform orientations (the volume sampler's
/// distribution without the inside test), pose i from Rng(seed, i).
inline std::vector<Pose> randomPoses(int n, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                     std::uint64_t seed = 42) {
  std::vector<Pose> poses;
  for (int i = 0; i < n; ++i) {
    Rng rng(seed, static_cast<std::uint64_t>(i));
    Pose p;
    for (int k = 0; k < 3; ++k) p.position[k] = rng.uniform(lo[k], hi[k]);
    p.orientation = rng.rotation();
    poses.push_back(p);
  }
  return poses;
}

}  // namespace taskmap::testing
