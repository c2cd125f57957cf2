#pragma once
/// @file trajectory_record.hpp
/// A planned reach as a trajectory record (mapstore/TRAJECTORY.md): what `taskmap reach --map
/// -o trajectory.h5` writes and `--glb` renders.

#include <string>

#include "taskmap/integration/task_map.hpp"
#include "taskmap/mapstore/trajectory_file.hpp"
#include "taskmap/reaching/grasp_planner.hpp"
#include "taskmap/reaching/movement_terms.hpp"
#include "taskmap/reaching/robot_model.hpp"

namespace taskmap {

/// What the record names besides the plan: the planner's inputs.
struct TrajectorySource {
  std::string robot;          ///< "panda" or the robot URDF path
  std::string hand;           ///< hand name or URDF path
  std::string map_path;       ///< the task map file (its SHA-256 is computed here)
  double dt = 0.01;           ///< control step, seconds
  double quality_peak = 1.0;  ///< q* of the plan's quality term (GraspPlan::map_weights)
};

/// The record of plan b (the chosen ClusterPlan): joints, palm and body poses per step, the
/// collision primitives, the object mesh of the map at the object body's pose, the cost
/// history (one column per term), the map terms over the movement and, when the map records
/// joint values, the map's hand and the final grasp's joint values (/plan/grasp); generator
/// "taskmap <version>". Throws Error when the map file cannot be read for its SHA-256.
TrajectoryRecord trajectoryRecord(const RobotModel& robot, int palm, int object, const TaskMap& map,
                                  const ClusterPlan& b, const MovementTerms& movement,
                                  const TrajectorySource& source);

}  // namespace taskmap
