// The task map in the trajectory cost (section 1.6.2, eq. 1.22): TaskMap::evaluate at the final
// hand pose, chained to joint space with the hand-relative-to-object Jacobian.
#include "taskmap/reaching/map_cost.hpp"

#include <cmath>
#include <string>

#include "taskmap/core/error.hpp"

namespace taskmap {

void MapCostWeights::validate() const {
  if (!(proximity >= 0.0) || !std::isfinite(proximity))
    throw Error("map cost weights: proximity must be finite and >= 0");
  if (!(quality >= 0.0) || !std::isfinite(quality))
    throw Error("map cost weights: quality must be finite and >= 0");
  if (quality_peak && (!(*quality_peak > 0.0) || !std::isfinite(*quality_peak)))
    throw Error("map cost weights: quality_peak must be finite and > 0");
}

double mapQualityPeak(const TaskMap& map) {
  const MapGrasps& g = map.data().grasps;
  if (g.size() == 0) return 1.0;
  const PoseRows poses = g.pose;
  const double peak = -map.evaluateBatch(poses).quality.minCoeff();
  return peak > 0.0 && std::isfinite(peak) ? peak : 1.0;
}

TerminalCost mapTerminalCost(const TaskMap& map, int palm, int object,
                             const MapCostWeights& weights, std::optional<int> cluster,
                             std::shared_ptr<MapCostRecord> record) {
  weights.validate();
  if (cluster && (*cluster < 0 || *cluster >= map.numClusters()))
    throw Error("map cost: cluster " + std::to_string(*cluster) + " is not a cluster of the map");
  return [&map, palm, object, weights, cluster, record](const Kinematics& kin,
                                                        Eigen::VectorXd* gradient) {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.translation() = kin.relativePosition(palm, object);
    t.linear() = kin.relativeRotation(palm, object);
    const Pose hand = Pose::fromIsometry(t);
    const Evaluation e = map.evaluate(hand, cluster);
    const double gp = weights.proximity * e.proximity.value;
    const double wq = weights.qualityFactor();
    const double gq = wq * e.quality.value;
    if (gradient) {
      const Twist g = weights.proximity * e.proximity.gradient + wq * e.quality.gradient;
      *gradient = kin.relativePositionJacobian(palm, object).transpose() * g.head<3>() +
                  kin.relativeAngularJacobian(palm, object).transpose() * g.tail<3>();
    }
    if (record) {
      record->evaluation = e;
      record->hand = hand;
      record->proximity = gp;
      record->quality = gq;
      ++record->calls;
    }
    return gp + gq;
  };
}

}  // namespace taskmap
