// The robot of `taskmap reach` and the grasp plan with a task map (map_reach.hpp).
#include "taskmap/reaching/map_reach.hpp"

#include <chrono>
#include <cmath>
#include <filesystem>

#include "taskmap/core/data_dir.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/reaching/kinematics.hpp"

namespace taskmap {

ReachRobot loadReachRobot(const ReachRobotOptions& options, const ReachScene& scene) {
  const bool panda = options.robot == "panda";
  if (!panda && !std::filesystem::exists(options.robot))
    throw Error("--robot '" + options.robot + "' is neither 'panda' nor an existing URDF file");
  ReachRobot r{RobotModel::load(panda ? dataDir() + "/robots/panda/panda.urdf" : options.robot),
               -1};
  if (options.hand != "none") {
    const std::string hand_path = resolveHandUrdf(options.hand);
    if (!panda && options.flange.empty())
      throw Error("--flange LINK is needed to mount a hand on " + options.robot);
    const std::string flange = options.flange.empty() ? "fer_link8" : options.flange;
    const HandModel hand = HandModel::load(hand_path);
    // The mount: the given one, else the hand sidecar's (never another hand's adapter).
    HandMount mount;
    if (options.mount) {
      mount.flange = flange;
      mount.palm_in_flange = *options.mount;
    } else {
      mount = mountFromSidecar(hand, flange);
    }
    r.model.mountHand(hand, mount);
  }
  addSceneTo(scene, r.model);
  if (r.model.palmBody() >= 0) {
    r.body = r.model.palmBody();
    return r;
  }
  if (options.flange.empty() && !panda)
    throw Error("--hand none on " + options.robot + ": give --flange LINK, the body to move");
  r.body = r.model.requireBody(options.flange.empty() ? "fer_link8" : options.flange);
  return r;
}

Eigen::VectorXd reachStartConfiguration(const ReachRobotOptions& options, const RobotModel& robot) {
  if (options.robot == "panda") {
    Eigen::VectorXd q(7);
    q << 0.0, -M_PI / 4, 0.0, -3 * M_PI / 4, 0.0, M_PI / 2, M_PI / 4;  // Franka's ready pose
    return q;
  }
  return robot.midConfiguration();
}

MapReach planMapReach(const TrajectoryProblem& problem, const TaskMap& map,
                      const GraspPlanOptions& options) {
  MapReach r;
  const auto t0 = std::chrono::steady_clock::now();
  r.plan = planGrasp(problem, map, options);
  r.plan_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (r.plan.best >= 0)
    r.movement = movementTerms(map, *problem.robot, problem.body, problem.reference,
                               r.plan.plans[r.plan.best].optimization.cost.q, r.plan.map_weights);
  return r;
}

Pose finalPalmInObject(const RobotModel& robot, const ClusterPlan& b, int palm, int object) {
  Kinematics kin(robot);
  kin.update(b.optimization.cost.q.back());
  return poseInFrameOf(kin, palm, object);
}

}  // namespace taskmap
