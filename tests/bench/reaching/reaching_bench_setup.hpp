#pragma once
// Shared set-up of the reaching benchmarks: the shipped Panda with the humanoid hand in a scene
// (the default table and cylinder, or a scene file), its collision pairs (the hand may touch the
// object), the Franka ready pose, and a side grasp of the default object.
#include <memory>
#include <string>

#include "taskmap/reaching/collision_model.hpp"
#include "taskmap/reaching/reach_scene.hpp"

namespace taskmap::bench {

/// Robot, scene bodies and collision pairs of one benchmark.
struct PandaScene {
  RobotModel robot;
  std::unique_ptr<CollisionModel> collisions;
  int object = -1;     ///< the scene's object body
  Eigen::VectorXd q0;  ///< Franka's ready pose
};

/// The Panda with the humanoid hand in `scene`, collision options defaulted except that the hand
/// may touch the object.
inline std::unique_ptr<PandaScene> pandaInScene(const ReachScene& scene) {
  auto out = std::make_unique<PandaScene>();
  out->robot = RobotModel::pandaWithHumanoidHand(
      std::string(TASKMAP_SOURCE_DIR) + "/reaching/robots", TASKMAP_HANDS_DIR);
  addSceneTo(scene, out->robot);
  CollisionOptions co;
  co.hand_may_touch = {scene.object};
  out->collisions = std::make_unique<CollisionModel>(out->robot, co);
  out->object = out->robot.requireBody(scene.object);
  out->q0.resize(7);
  out->q0 << 0.0, -M_PI / 4, 0.0, -3 * M_PI / 4, 0.0, M_PI / 2, M_PI / 4;
  return out;
}

/// Side grasp of the default scene's cylinder: palm pose in the object frame.
inline Eigen::Isometry3d sideGrasp() {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(-0.07, 0.0, 0.02);
  t.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).matrix();
  return t;
}

}  // namespace taskmap::bench
