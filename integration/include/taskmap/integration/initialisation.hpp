#pragma once
/// @file initialisation.hpp
/// Choosing the initial target cluster (paper 1.6.2): for each cluster's representative
/// grasp, the caller's inverse kinematics gives a posture, scored by "end-state comfort"
/// (joint-limit cost eq. 1.8 plus collision cost eq. 1.9-1.10). Best cluster first.

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "taskmap/integration/task_map.hpp"

namespace taskmap {

/// Joint-limit cost (eq. 1.8): 1/2 sum ((q_i - q0_i) / (qmax_i - qmin_i))^2, q0 the middle of
/// the range. If gradient is not null it receives dH/dq. Throws Error on size mismatch or a
/// range with qmax <= qmin.
double jointLimitCost(const Eigen::VectorXd& q, const Eigen::VectorXd& lower,
                      const Eigen::VectorXd& upper, Eigen::VectorXd* gradient = nullptr);

/// Collision cost of one body pair (eq. 1.9-1.10) from its closest-point distance d (metres,
/// negative when penetrating) and zone distance d_B (> 0): s d_B (d_B - 2d) for d < 0,
/// s (d - d_B)^2 for 0 <= d <= d_B, 0 beyond. Continuous with continuous slope at d = 0.
/// If derivative is not null it receives dg/dd.
double collisionPairCost(double distance, double zone, double scale = 1.0,
                         double* derivative = nullptr);

/// Sum of collisionPairCost over pairs (eq. 1.10).
double collisionCost(const std::vector<double>& distances, double zone, double scale = 1.0);

/// Outcome of the caller's inverse kinematics for one target.
struct IkSolution {
  bool success = false;  ///< a posture reaching the target was found
  Eigen::VectorXd q;     ///< joint angles (radians or metres)
  std::string message;   ///< why not, when !success
};

/// Caller's inverse kinematics: target palm pose in the WORLD frame -> posture.
using IkFunction = std::function<IkSolution(const Pose& hand_target_world)>;
/// Caller's end-state comfort cost of a posture (lower is better), for example
/// jointLimitCost(q, ...) + collisionCost(pair distances at q, ...).
using ComfortFunction = std::function<double(const Eigen::VectorXd& q)>;

/// Comfort = joint-limit cost + collision_weight * collisionCost(distances(q), zone, scale);
/// distances may be empty (joint limits only). Throws Error on invalid limits or zone <= 0.
ComfortFunction makeComfort(
    const Eigen::VectorXd& lower, const Eigen::VectorXd& upper,
    std::function<std::vector<double>(const Eigen::VectorXd&)> distances = nullptr,
    double zone = 0.05, double scale = 1.0, double collision_weight = 1.0);

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
