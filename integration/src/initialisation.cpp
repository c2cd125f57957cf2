#include "taskmap/integration/initialisation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

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

std::vector<ClusterRank> rankClusters(const TaskMap& map, const Pose& object_world,
                                      const IkFunction& ik, const ComfortFunction& comfort) {
  if (!ik) throw Error("rankClusters: no inverse kinematics function given");
  if (!comfort) throw Error("rankClusters: no comfort function given");
  if (!map.data().clustering || map.numClusters() == 0)
    throw Error("rankClusters: the map has no clusters; cluster the map first");
  const Eigen::Quaterniond qo = object_world.orientation.normalized();
  std::vector<ClusterRank> out;
  for (int c = 0; c < map.numClusters(); ++c) {
    ClusterRank r;
    r.cluster = c;
    r.representative = static_cast<std::size_t>(
        map.data().clustering->clusters[static_cast<std::size_t>(c)].representative);
    r.target_object = map.pose(r.representative);
    r.target_world.position = object_world.position + qo * r.target_object.position;
    r.target_world.orientation = (qo * r.target_object.orientation).normalized();
    const IkSolution s = ik(r.target_world);
    r.comfort = std::numeric_limits<double>::infinity();
    if (s.success) {
      r.q = s.q;
      const double c_value = comfort(s.q);
      if (std::isfinite(c_value)) {
        r.reachable = true;
        r.comfort = c_value;
      } else {
        r.message = "comfort cost is not finite";
      }
    } else {
      r.message = s.message.empty() ? "inverse kinematics failed" : s.message;
    }
    out.push_back(std::move(r));
  }
  std::stable_sort(out.begin(), out.end(), [](const ClusterRank& a, const ClusterRank& b) {
    if (a.reachable != b.reachable) return a.reachable;
    if (a.reachable && a.comfort != b.comfort) return a.comfort < b.comfort;
    return a.cluster < b.cluster;
  });
  return out;
}

}  // namespace taskmap
