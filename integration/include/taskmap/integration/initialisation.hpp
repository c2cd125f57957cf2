#pragma once
/// @file initialisation.hpp
/// Choosing the initial target cluster (paper 1.6.2): for each cluster's representative
/// grasp, the caller's inverse kinematics gives a posture, scored by the caller's "end-state
/// comfort" (the paper: joint-limit cost eq. 1.8 plus collision cost eq. 1.9-1.10, which the
/// reaching stage provides, robot_costs.hpp). Best cluster first.

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "taskmap/integration/task_map.hpp"

namespace taskmap {

/// Outcome of the caller's inverse kinematics for one target.
struct IkSolution {
  bool success = false;  ///< a posture reaching the target was found
  Eigen::VectorXd q;     ///< joint angles (radians or metres)
  std::string message;   ///< why not, when !success
};

/// Caller's inverse kinematics: target palm pose in the WORLD frame -> posture.
using IkFunction = std::function<IkSolution(const Pose& hand_target_world)>;
/// Caller's end-state comfort cost of a posture (lower is better), for example the joint-limit
/// plus collision cost of reaching's makeComfort (taskmap/reaching/robot_costs.hpp).
using ComfortFunction = std::function<double(const Eigen::VectorXd& q)>;

/// One ranked cluster.
struct ClusterRank {
  int cluster = -1;                ///< cluster id (0..K-1)
  std::size_t representative = 0;  ///< grasp index (ClusterSummary::representative)
  Pose target_object;              ///< representative pose, object frame
  Pose target_world;               ///< representative pose, world frame (the IK target)
  bool reachable = false;          ///< IK succeeded
  Eigen::VectorXd q;               ///< IK posture
  double comfort = 0.0;            ///< comfort cost (infinity if unreachable)
  std::string message;             ///< IK message when unreachable
};

/// Ranks every cluster of the map: reachable ones first by increasing comfort cost, then the
/// unreachable ones; ties by cluster id. Throws Error if the map has no clustering or a
/// function is empty; a comfort that is not finite ranks the cluster as unreachable.
std::vector<ClusterRank> rankClusters(const TaskMap& map, const Pose& object_world,
                                      const IkFunction& ik, const ComfortFunction& comfort);

}  // namespace taskmap
