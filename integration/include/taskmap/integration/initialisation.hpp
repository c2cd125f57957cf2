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
  int cluster = -1;  ///< cluster id (0..K-1); -1 for an outlier (RankOptions::member_tries)
  /// Grasp index of the cluster's representative (ClusterSummary::representative); for
  /// cluster -1 the outlier reached.
  std::size_t representative = 0;
  /// Grasp index of the target: the representative, or the member reached in its place
  /// (RankOptions::member_tries); the representative when none is reachable.
  std::size_t target = 0;
  int tried = 0;       ///< targets given to the IK: the representative, then members (or outliers)
  Pose target_object;  ///< the target grasp's palm pose, object frame
  Pose target_world;   ///< the target grasp's palm pose, world frame (the IK target)
  bool reachable = false;  ///< IK succeeded
  Eigen::VectorXd q;       ///< IK posture
  double comfort = 0.0;    ///< comfort cost (infinity if unreachable)
  std::string message;     ///< IK message when unreachable (the representative's)
};

/// How rankClusters chooses each cluster's target.
struct RankOptions {
  /// When no cluster's representative is reachable, at most this many other members of each
  /// cluster are given to the IK, spread over the cluster (sorted by pose distance to the
  /// representative, farthest first, taken at evenly spaced ranks), the first reachable one
  /// the cluster's target; when none is reachable either, at most this many outliers (grasps
  /// in no cluster, index order, evenly spaced), the first reachable one ranked as cluster -1.
  /// 0: the representatives only (the paper's rule). >= 0.
  int member_tries = 0;
  /// Skip the representatives: every cluster's target is the first reachable of at most
  /// member_tries other members, and at most member_tries outliers are tried as well (cluster
  /// -1 when one is reachable). planGrasp's second round when every plan from the first
  /// ranking is unsafe. Needs member_tries > 0 to try anything.
  bool members_only = false;
  /// Throws Error when member_tries < 0.
  void validate() const;
};

/// Ranks every cluster of the map: reachable ones first by increasing comfort cost, then the
/// unreachable ones; ties by cluster id. Throws Error if the map has no clustering or a
/// function is empty; a comfort that is not finite ranks the target as unreachable.
std::vector<ClusterRank> rankClusters(const TaskMap& map, const Pose& object_world,
                                      const IkFunction& ik, const ComfortFunction& comfort,
                                      const RankOptions& options = {});

}  // namespace taskmap
