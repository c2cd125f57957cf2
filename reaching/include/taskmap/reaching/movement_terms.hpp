#pragma once
/// @file movement_terms.hpp
/// The task map's terms over a whole movement (paper Fig. 1.16, proximity and quality over the
/// movement; docs/REACHING.md): the map evaluated at the hand pose of every step, not only at
/// the end as in the terminal cost (map_cost.hpp).

#include <vector>

#include <Eigen/Core>

#include "taskmap/reaching/map_cost.hpp"

namespace taskmap {

/// The weighted map terms at the palm pose of every step of a trajectory.
struct MovementTerms {
  std::vector<double> proximity;  ///< w_map,p g_p per step (g_p in m^2 with the map's W_map)
  std::vector<double> quality;    ///< w_map,q g_q per step (dimensionless, <= 0)
};

/// Pose of body `palm` in the frame of body `object` for the configuration kin holds.
Pose poseInFrameOf(const Kinematics& kin, int palm, int object);

/// Evaluates the whole map (TaskMap::evaluateBatch) at the pose of `palm` relative to `object`
/// (object frame, as the map's poses) for every configuration of q, weighted as in the terminal
/// cost (mapTerminalCost). Throws Error on a configuration of the wrong size.
MovementTerms movementTerms(const TaskMap& map, const RobotModel& robot, int palm, int object,
                            const std::vector<Eigen::VectorXd>& q, const MapCostWeights& weights);

}  // namespace taskmap
