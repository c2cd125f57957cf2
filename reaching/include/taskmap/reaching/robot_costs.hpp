#pragma once
/// @file robot_costs.hpp
/// End-state comfort of a robot posture (paper 1.6.2): the joint-limit cost (eq. 1.8) and the
/// collision cost (eq. 1.9-1.10), and a comfort function made of both for
/// taskmap::rankClusters (integration/initialisation.hpp), which takes any comfort.

#include <functional>
#include <vector>

#include <Eigen/Core>

#include "taskmap/integration/initialisation.hpp"

namespace taskmap {

/// Joint-limit cost (eq. 1.8): 1/2 sum ((q_i - q0_i) / (qmax_i - qmin_i))^2, q0 the middle of
/// the range (radians or metres). If gradient is not null it receives dH/dq. Throws Error on
/// size mismatch or a range with qmax <= qmin.
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

/// Comfort = joint-limit cost + collision_weight * collisionCost(distances(q), zone, scale);
/// distances may be empty (joint limits only). Throws Error on invalid limits or zone <= 0.
ComfortFunction makeComfort(
    const Eigen::VectorXd& lower, const Eigen::VectorXd& upper,
    std::function<std::vector<double>(const Eigen::VectorXd&)> distances = nullptr,
    double zone = 0.05, double scale = 1.0, double collision_weight = 1.0);

}  // namespace taskmap
