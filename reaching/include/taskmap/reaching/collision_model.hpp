#pragma once
/// @file collision_model.hpp
/// Collision-relevant body pairs and the collision avoidance cost of the paper (eq. 1.9-1.16,
/// docs/REACHING.md): a closest-point term with linear / parabolic / zero zones and a
/// centre-point term, summed over the pairs, with its gradient through the closest points'
/// Jacobians. Units: metres; the cost is dimensionless (scaled by the slope s).

#include <string>
#include <vector>

#include <Eigen/Core>

#include "taskmap/reaching/kinematics.hpp"
#include "taskmap/reaching/primitive_distance.hpp"

namespace taskmap {

/// Which pairs are checked and the shape of the cost.
struct CollisionOptions {
  double boundary_distance = 0.1;  ///< d_B: the cost is zero beyond it, metres (> 0)
  double slope = 1.0;  ///< s: the closest-point cost is s d_B (d_B - 2 d) when penetrating (> 0)
  /// Weight of the centre-point term e^{-d_c} (>= 0); negative means s d_B^2, the closest-point
  /// cost at contact, so that both terms have the same scale.
  double center_weight = -1.0;
  /// Robot bodies with fewer moving joints to the world than this skip environment pairs (the
  /// base and the first link stand on the table by construction). >= 0.
  int min_environment_depth = 2;
  /// Self pairs need at least this many moving joints between the two bodies (>= 1).
  int min_self_gap = 3;
  bool self_collision = true;  ///< check robot-robot and hand-robot pairs
  /// Environment bodies the hand may touch (the grasped object): no hand pairs with them.
  std::vector<std::string> hand_may_touch;
  /// Throws Error naming the field when a value is out of range.
  void validate() const;
};

/// One primitive pair: shape_a of body_a against shape_b of body_b (indices into the model).
struct CollisionPair {
  int body_a = -1;   ///< robot or hand body
  int shape_a = -1;  ///< index into bodies()[body_a].shapes
  int body_b = -1;   ///< robot, hand or environment body
  int shape_b = -1;  ///< index into bodies()[body_b].shapes
};

/// Distances of one pair at the current configuration.
struct PairDistance {
  PrimitiveDistance closest;     ///< closest points, signed distance d_p, metres
  double center_distance = 0.0;  ///< d_c = |C_b - C_a| between the primitive centres, metres
};

/// Collision pairs of a robot and the cost H_coll(q). Holds a pointer to the model, which must
/// outlive it; const methods are thread-safe.
class CollisionModel {
 public:
  /// Selects the pairs: robot/hand bodies (depth >= min_environment_depth) against every
  /// environment body, and self pairs at least min_self_gap joints apart that do not already
  /// overlap at the mid configuration. Throws Error on invalid options.
  CollisionModel(const RobotModel& robot, const CollisionOptions& options);

  const std::vector<CollisionPair>& pairs() const { return pairs_; }  ///< checked pairs
  const CollisionOptions& options() const { return options_; }        ///< the options
  /// "body_a[shape] - body_b[shape]" for messages.
  std::string pairName(int pair) const;

  /// Exact distances of every pair (no culling) at the state of kin.
  std::vector<PairDistance> distances(const Kinematics& kin) const;
  /// Smallest signed distance over the pairs, metres (+inf without pairs); writes the pair
  /// index to *pair when given.
  double minimumDistance(const Kinematics& kin, int* pair = nullptr) const;
  /// H_coll (eq. 1.10) at the state of kin; when gradient is given, writes dH/dq (eq. 1.16,
  /// dofs() entries). Pairs whose bounding spheres are farther apart than d_B contribute 0.
  double cost(const Kinematics& kin, Eigen::VectorXd* gradient) const;

  /// Closest-point cost g_p(d) of eq. 1.9 and its derivative dg_p/dd.
  double closestPointCost(double d, double* derivative) const;
  /// Centre-point cost g_c(d_p, d_c) of eq. 1.9 and its partial derivatives (eq. 1.15).
  double centerPointCost(double dp, double dc, double* d_dp, double* d_dc) const;

 private:
  const RobotModel* robot_;
  CollisionOptions options_;
  double center_weight_ = 0.0;
  std::vector<CollisionPair> pairs_;
};

}  // namespace taskmap
