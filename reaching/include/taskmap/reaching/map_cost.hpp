#pragma once
/// @file map_cost.hpp
/// The task map as the terminal cost of the trajectory optimisation (paper section 1.6.2,
/// docs/REACHING.md eq. 1.22): the final hand pose relative to the object is evaluated by
/// TaskMap::evaluate (proximity g_p and quality g_q with object-frame gradients), and the
/// gradient is chained to joint space with the hand-relative-to-object Jacobian.

#include <cstdint>
#include <memory>
#include <optional>

#include "taskmap/integration/task_map.hpp"
#include "taskmap/reaching/trajectory_optimizer.hpp"

namespace taskmap {

/// Weights of the map terms in the terminal cost, each >= 0 (docs/REACHING.md "The quality
/// term's scale"): the terminal cost is w_p g_p + w_q g_q / q*.
struct MapCostWeights {
  double proximity = 1.0;  ///< w_map,p on g_p (g_p is in m^2 with the map's W_map)
  double quality = 1.0;    ///< w_map,q on g_q / q* (about -1 at the map's best grasp)
  /// q* (> 0), the scale of g_q: mapQualityPeak(map) in planGrasp when unset; unset here means
  /// 1 (g_q as TaskMap::evaluate returns it, a mixture density of order 1 / (sigma_p^3 sigma_r^3)).
  std::optional<double> quality_peak;
  /// Throws Error naming the field when a weight is negative or not finite, or q* is not > 0.
  void validate() const;
  /// The factor on g_q: w_q / q* (w_q when q* is unset).
  double qualityFactor() const { return quality / quality_peak.value_or(1.0); }
};

/// q* of a map: the largest -g_q at the map's own grasp poses (TaskMap::evaluateBatch over the
/// whole map, its quality mode), so that g_q / q* is -1 at its best grasp and about 0 off the
/// manifold; 1 when g_q is 0 at every grasp (every sample weight 0).
double mapQualityPeak(const TaskMap& map);

/// The last map evaluation made by a map terminal cost (for reports per iteration).
struct MapCostRecord {
  Evaluation evaluation;   ///< g_p, g_q, nearest sample, gradients
  Pose hand;               ///< hand (palm) pose in the object frame
  double proximity = 0.0;  ///< weighted g_p
  double quality = 0.0;    ///< weighted g_q
  std::int64_t calls = 0;  ///< TaskMap::evaluate calls so far
};

/// Terminal cost w_p g_p(x) + w_q g_q(x), x the pose of `palm` relative to `object` (both
/// bodies of the robot model; the object a fixed body), with gradient
/// J_rel^T dg/dx (eq. 1.22; J_rel rows: relativePositionJacobian, relativeAngularJacobian, both
/// in the object frame as the map's gradients). `cluster` restricts the map to one cluster.
/// Every call writes its evaluation to *record when given. The map must outlive the cost.
TerminalCost mapTerminalCost(const TaskMap& map, int palm, int object,
                             const MapCostWeights& weights, std::optional<int> cluster,
                             std::shared_ptr<MapCostRecord> record);

}  // namespace taskmap
