// End-state comfort costs of a robot posture (eq. 1.8-1.10): reaching/robot_costs.hpp.
#include "taskmap/reaching/robot_costs.hpp"

#include <cmath>
#include <string>

#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

void checkLimits(const Eigen::VectorXd& lower, const Eigen::VectorXd& upper) {
  if (lower.size() != upper.size())
    throw Error("joint limits: " + std::to_string(lower.size()) + " lower but " +
                std::to_string(upper.size()) + " upper values");
  for (Eigen::Index i = 0; i < lower.size(); ++i)
    if (!(std::isfinite(lower[i]) && std::isfinite(upper[i]) && upper[i] > lower[i]))
      throw Error("joint limits of joint " + std::to_string(i) + ": need finite lower < upper");
}

}  // namespace

double jointLimitCost(const Eigen::VectorXd& q, const Eigen::VectorXd& lower,
                      const Eigen::VectorXd& upper, Eigen::VectorXd* gradient) {
  checkLimits(lower, upper);
  if (q.size() != lower.size())
    throw Error("joint-limit cost: posture has " + std::to_string(q.size()) + " joints, limits " +
                std::to_string(lower.size()));
  const Eigen::VectorXd range = upper - lower;
  const Eigen::VectorXd u = (q - 0.5 * (lower + upper)).cwiseQuotient(range);
  if (gradient) *gradient = u.cwiseQuotient(range);
  return 0.5 * u.squaredNorm();
}

double collisionPairCost(double distance, double zone, double scale, double* derivative) {
  if (!(zone > 0)) throw Error("collision cost: zone distance must be > 0 (metres)");
  double g = 0.0, dg = 0.0;
  if (distance < 0) {
    g = scale * zone * (zone - 2.0 * distance);
    dg = -2.0 * scale * zone;
  } else if (distance <= zone) {
    g = scale * (distance - zone) * (distance - zone);
    dg = 2.0 * scale * (distance - zone);
  }
  if (derivative) *derivative = dg;
  return g;
}

double collisionCost(const std::vector<double>& distances, double zone, double scale) {
  double sum = 0.0;
  for (double d : distances) sum += collisionPairCost(d, zone, scale);
  return sum;
}

ComfortFunction makeComfort(const Eigen::VectorXd& lower, const Eigen::VectorXd& upper,
                            std::function<std::vector<double>(const Eigen::VectorXd&)> distances,
                            double zone, double scale, double collision_weight) {
  checkLimits(lower, upper);
  if (!(zone > 0)) throw Error("comfort: zone distance must be > 0 (metres)");
  return [=](const Eigen::VectorXd& q) {
    double c = jointLimitCost(q, lower, upper);
    if (distances) c += collision_weight * collisionCost(distances(q), zone, scale);
    return c;
  };
}

}  // namespace taskmap
