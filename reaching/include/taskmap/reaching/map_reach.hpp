#pragma once
/// @file map_reach.hpp
/// Reaching with a task map as the library calls behind `taskmap reach` and Python's
/// `taskmap.reach` (docs/REACHING.md): the robot of the command line (the bundled Panda or a
/// URDF, a hand mounted on its flange, the scene), its start configuration, and the grasp plan
/// with the map's terms over the planned movement.

#include <optional>
#include <string>

#include <Eigen/Geometry>

#include "taskmap/core/pose.hpp"
#include "taskmap/integration/task_map.hpp"
#include "taskmap/reaching/grasp_planner.hpp"
#include "taskmap/reaching/movement_terms.hpp"
#include "taskmap/reaching/reach_scene.hpp"
#include "taskmap/reaching/robot_model.hpp"

namespace taskmap {

/// The robot of a reach, named as `taskmap reach` names it.
struct ReachRobotOptions {
  std::string robot = "panda";    ///< "panda" (the bundled Franka arm) or a robot URDF path
  std::string hand = "humanoid";  ///< hand URDF, bundled hand name, or "none"
  std::string flange;             ///< link the hand is mounted on ("" = fer_link8 of the Panda)
  /// Palm frame in the flange frame (metres); none: the hand sidecar's "mount".
  std::optional<Eigen::Isometry3d> mount;
};

/// A robot with its hand and scene, and the body a reach moves.
struct ReachRobot {
  RobotModel model;  ///< arm, hand (if any) and the scene's fixed bodies
  int body = -1;     ///< the palm with a hand, else the flange
};

/// Loads the robot (the Panda from dataDir()/robots/panda), mounts the hand (a path or a bundled
/// name) and adds the scene. Throws Error naming the option (--robot, --hand, --flange, --mount)
/// that is missing or wrong.
ReachRobot loadReachRobot(const ReachRobotOptions& options, const ReachScene& scene);

/// The start configuration of a reach: Franka's ready pose for the bundled Panda (radians),
/// else the middle of the joint ranges.
Eigen::VectorXd reachStartConfiguration(const ReachRobotOptions& options, const RobotModel& robot);

/// A grasp plan with its measures over the chosen movement.
struct MapReach {
  GraspPlan plan;          ///< the plans per cluster and the chosen one (plan.best, -1 if none)
  double plan_ms = 0.0;    ///< wall time of planGrasp, milliseconds
  MovementTerms movement;  ///< the map's terms over the best plan's movement (empty without one)
};

/// planGrasp(problem, map, options) timed, and movementTerms of the best plan with the plan's
/// map_weights (quality_peak resolved). problem.body is the palm, problem.reference the object
/// body.
MapReach planMapReach(const TrajectoryProblem& problem, const TaskMap& map,
                      const GraspPlanOptions& options);

/// The palm pose in the object frame at the last step of plan b (metres): what the final grasp
/// is re-simulated from (builder/resimulate.hpp).
Pose finalPalmInObject(const RobotModel& robot, const ClusterPlan& b, int palm, int object);

}  // namespace taskmap
