// `taskmap reach --map`: rank the clusters, optimise the trajectory over attractor points with
// the map as terminal cost, print the measures of the issue (JSON or text), draw snapshots.
#include "reach_map.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "command.hpp"
#include "reach_resimulate.hpp"
#include "reach_trajectory.hpp"
#include "taskmap/core/constants.hpp"
#include "taskmap/core/data_dir.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/inspect/glb_export.hpp"
#include "taskmap/picture/cost_picture.hpp"
#include "taskmap/picture/reach_picture.hpp"
#include "taskmap/reaching/grasp_planner.hpp"
#include "taskmap/reaching/plan_report.hpp"

namespace taskmap::cli {

Eigen::Isometry3d parseObjectPose(const std::string& text) {
  std::istringstream in(text);
  double v[4];
  for (double& x : v)
    if (!(in >> x) || !std::isfinite(x))
      throw Error("--object-pose needs 4 finite numbers \"x y z yaw\" (metres, radians)");
  std::string extra;
  if (in >> extra) throw Error("--object-pose needs exactly 4 numbers \"x y z yaw\"");
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  t.linear() = Eigen::AngleAxisd(v[3], Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return t;
}

std::string resolveMapPath(const std::string& map) {
  if (std::filesystem::exists(map)) return map;
  const bool name = map.find('/') == std::string::npos && map.find('.') == std::string::npos;
  const std::string bundled = name ? dataDir() + "/maps/" + map + ".h5" : std::string();
  if (!bundled.empty() && std::filesystem::exists(bundled)) return bundled;
  throw Error("--map '" + map + "' is neither a map file nor a bundled map name" +
              (name ? " (no " + bundled + ")" : std::string()));
}

namespace {

void printText(const GraspPlan& plan, double plan_ms) {
  std::printf("status            %s (%s)\n", toString(plan.status), plan.message.c_str());
  for (const ClusterPlan& c : plan.plans)
    std::printf(
        "from cluster %-4d -> cluster %d grasp %lld: %d iterations (manifold %d, quality "
        "%d), clearance %.4f m, joint margin %.4f rad, %.1f ms/iteration%s\n",
        c.cluster, c.grasp_cluster, static_cast<long long>(c.grasp_index),
        c.optimization.iterations, c.iterations_to_manifold, c.iterations_to_quality,
        c.min_clearance, c.joint_limit_margin,
        c.milliseconds / std::max(1, c.optimization.iterations),
        c.min_clearance < 0.0 ? ("  <- " + clearanceWarning(c.min_clearance)).c_str() : "");
  std::printf("plan time         %.1f ms\n", plan_ms);
}

/// Fig. 1.16 next to the snapshots: FILE.png -> FILE_costs.png.
std::string costPicturePath(const std::string& png) {
  const std::string::size_type dot = png.rfind(".png");
  return (dot != std::string::npos && dot + 4 == png.size() ? png.substr(0, dot) : png) +
         "_costs.png";
}

void drawCosts(const ClusterPlan& b, const MovementTerms& movement, double dt,
               const std::string& path) {
  std::vector<double> total, length, velocity, collision, limit;
  for (const TrajectoryCost& t : b.optimization.history) {
    total.push_back(t.total);
    length.push_back(t.path_length);
    velocity.push_back(t.end_velocity);
    collision.push_back(t.collision);
    limit.push_back(t.joint_limit);
  }
  writeCostPicture(
      {{"trajectory cost terms per iteration",
        "iteration",
        1.0,
        {{"total", total},
         {"path length", length},
         {"end velocity", velocity},
         {"collision", collision},
         {"joint limit", limit}}},
       {"task map terms per iteration",
        "iteration",
        1.0,
        {{"proximity g_p", b.proximity}, {"quality g_q", b.quality}}},
       {"proximity over the final movement",
        "time [s]",
        dt,
        {{"proximity g_p", movement.proximity}}},
       {"quality over the final movement", "time [s]", dt, {{"quality g_q", movement.quality}}}},
      path);
}

/// -o trajectory.h5 and --glb out.glb of the chosen plan.
void writeOutputs(const MapReachArgs& args, const RobotModel& robot, int palm, int object,
                  const TaskMap& map, const GraspPlan& plan, const MovementTerms& movement,
                  double dt, bool json) {
  if (args.output.empty() && args.glb.empty()) return;
  if (plan.best < 0) throw Error("no trajectory to write: " + plan.message);
  const TrajectoryRecord record =
      trajectoryRecord(robot, palm, object, map, plan.plans[plan.best], movement,
                       {args.robot, args.hand, resolveMapPath(args.map), dt});
  if (!args.output.empty()) writeTrajectory(args.output, record);
  if (!args.glb.empty()) writeGlb(record, args.glb);
  if (json) return;
  if (!args.output.empty()) std::printf("trajectory        %s\n", args.output.c_str());
  if (!args.glb.empty()) std::printf("glb               %s\n", args.glb.c_str());
}

/// Palm pose in the object frame at the plan's last step.
Pose finalPalmInObject(const RobotModel& robot, const ClusterPlan& b, int palm, int object) {
  Kinematics kin(robot);
  kin.update(b.optimization.cost.q.back());
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = kin.relativePosition(palm, object);
  t.linear() = kin.relativeRotation(palm, object);
  return Pose::fromIsometry(t);
}

void printResimulation(const Resimulation& r) {
  std::printf("re-simulated      %s, %s, epsilon %.4f, %d contacts (%zu fingers)\n",
              r.outcome.c_str(), r.force_closure ? "force closure" : "no force closure", r.epsilon,
              r.contacts, r.fingers.size());
  if (!r.hold) return;
  const ResimulatedHold& h = *r.hold;
  std::printf("hold test         %s (object moved %.1f mm, turned %.1f deg%s%s)\n",
              h.status.c_str(), 1000.0 * h.max_translation, h.max_rotation * 180.0 / kPi,
              h.failed_direction.empty() ? "" : ", push ", h.failed_direction.c_str());
}

}  // namespace

void runMapReach(const MapReachArgs& args, const RobotModel& robot,
                 const CollisionModel& collisions, int palm, int object, const Eigen::VectorXd& q0,
                 const ReachOptions& options, bool json, const std::string& png) {
  if (args.iterations < 1) throw Error("--iterations must be >= 1");
  if (args.hold_test && !args.resimulate)
    throw Error("--hold-test tests the re-simulated grasp: drop --no-resimulate");
  const Descent descent = [&args] {
    try {
      return descentFromString(args.descent);
    } catch (const Error& e) {
      throw Error(std::string("--") + e.what());
    }
  }();
  TaskMapOptions map_options;
  map_options.sample_weight = sampleWeightFromString(args.sample_weight);
  const TaskMap map = TaskMap::load(resolveMapPath(args.map), map_options);
  TrajectoryProblem p;
  p.robot = &robot;
  p.collisions = &collisions;
  p.body = palm;
  p.reference = object;
  p.q0 = q0;
  p.reach = options;
  GraspPlanOptions o;
  o.all_clusters = args.all_clusters;
  o.descent = descent;
  o.optimizer.max_iterations = args.iterations;
  o.map_weights.proximity = args.proximity_weight;
  o.map_weights.quality = args.quality_weight;
  const auto t0 = std::chrono::steady_clock::now();
  const GraspPlan plan = planGrasp(p, map, o);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  MovementTerms movement;
  if (plan.best >= 0)
    movement = movementTerms(map, robot, palm, object, plan.plans[plan.best].optimization.cost.q,
                             o.map_weights);
  std::optional<Resimulation> resim;
  if (args.resimulate && plan.best >= 0)
    resim =
        resimulateGrasp(map.data(), finalPalmInObject(robot, plan.plans[plan.best], palm, object));
  if (resim && args.hold_test) holdTestResimulated(map.data(), &*resim);
  if (json) {
    nlohmann::json j = nlohmann::json::parse(graspPlanReport(plan, ms, movement));
    j["sample_weight"] = toString(map.options().sample_weight);
    if (resim) j["resimulated"] = resimulationJson(*resim);
    std::cout << j.dump(2) << "\n";
  } else {
    printText(plan, ms);
    if (resim) printResimulation(*resim);
  }
  if (!png.empty() && plan.best >= 0) {
    const ClusterPlan& b = plan.plans[plan.best];
    ReachResult r;
    r.q = b.optimization.cost.q;
    Kinematics kin(robot);
    for (const Eigen::VectorXd& q : r.q) {
      kin.update(q);
      r.palm.push_back(kin.pose(palm));
    }
    kin.update(q0);
    const Eigen::Isometry3d grasp =
        kin.pose(object) * map.pose(static_cast<std::size_t>(b.grasp_index)).toIsometry();
    const int n = static_cast<int>(r.q.size()) - 1;
    writeReachPicture(robot, r, palm, {0, n / 3, 2 * n / 3, n}, grasp, png);
    drawCosts(b, movement, options.attractor.dt, costPicturePath(png));
  }
  writeOutputs(args, robot, palm, object, map, plan, movement, options.attractor.dt, json);
  if (plan.status != GraspPlanStatus::kPlanned) {
    std::cerr << "taskmap reach: " << plan.message << "\n";
    exitCode() = 1;
  }
}

}  // namespace taskmap::cli
