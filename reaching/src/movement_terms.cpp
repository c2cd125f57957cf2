// The task map's proximity and quality at every step of a movement (Fig. 1.16).
#include "taskmap/reaching/movement_terms.hpp"

#include <string>

#include "taskmap/core/error.hpp"

namespace taskmap {

Pose poseInFrameOf(const Kinematics& kin, int palm, int object) {
  Eigen::Isometry3d rel = Eigen::Isometry3d::Identity();
  rel.translation() = kin.relativePosition(palm, object);
  rel.linear() = kin.relativeRotation(palm, object);
  return Pose::fromIsometry(rel);
}

MovementTerms movementTerms(const TaskMap& map, const RobotModel& robot, int palm, int object,
                            const std::vector<Eigen::VectorXd>& q, const MapCostWeights& weights) {
  weights.validate();
  PoseRows poses(static_cast<Eigen::Index>(q.size()), 7);
  Kinematics kin(robot);
  for (std::size_t t = 0; t < q.size(); ++t) {
    if (q[t].size() != robot.dofs())
      throw Error("movementTerms: configuration " + std::to_string(t) + " has " +
                  std::to_string(q[t].size()) + " values, the robot " +
                  std::to_string(robot.dofs()));
    kin.update(q[t]);
    poses.row(static_cast<Eigen::Index>(t)) = poseInFrameOf(kin, palm, object).toVector7();
  }
  const BatchEvaluation e = map.evaluateBatch(poses);
  MovementTerms m;
  for (Eigen::Index t = 0; t < poses.rows(); ++t) {
    m.proximity.push_back(weights.proximity * e.proximity(t));
    m.quality.push_back(weights.qualityFactor() * e.quality(t));
  }
  return m;
}

}  // namespace taskmap
