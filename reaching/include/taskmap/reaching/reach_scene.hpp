#pragma once
/// @file reach_scene.hpp
/// Environment of a reaching problem: fixed bodies (table, the object) made of primitives,
/// read from JSON (format in docs/REACHING.md, "Scene file"). Units: metres, world frame.

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "taskmap/reaching/robot_model.hpp"

namespace taskmap {

/// One fixed environment body.
struct SceneBody {
  std::string name;                                        ///< unique body name
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< body frame in the world
  std::vector<Primitive> shapes;                           ///< primitives, body frame
};

/// The environment and which body is the object to grasp.
struct ReachScene {
  std::vector<SceneBody> bodies;  ///< environment bodies
  std::string object;             ///< name of the grasped object's body ("" if none)
};

/// Reads a scene file. Throws Error naming the file and the element on unreadable files,
/// unknown shape types, missing or non-finite values, duplicate names, an unknown object.
ReachScene loadReachScene(const std::string& path);
/// Table top (1.2 x 1.6 x 0.04 m, its face at z = 0 under the robot base) and an upright
/// cylinder object (radius 0.04 m, height 0.20 m) at (0.5, 0.2, 0.1), named "table", "object".
ReachScene defaultReachScene();
/// Adds every scene body to the robot as an environment body.
void addSceneTo(const ReachScene& scene, RobotModel& robot);

}  // namespace taskmap
