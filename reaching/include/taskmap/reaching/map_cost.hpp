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

/// Weights of the map terms in the terminal cost, each >= 0.
struct MapCostWeights {
  double proximity = 1.0;  ///< w_map,p on g_p (g_p is in m^2 with the map's W_map)
  double quality = 1.0;    ///< w_map,q on g_q (negative mixture of epsilons, dimensionless)
  /// Throws Error naming the field when a weight is negative or not finite.
  void validate() const;
};

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
