// Reaching and grasping with a task map (section 1.6.2-1.6.3): rank the clusters by comfort,
// optimise from the best (or every reachable) one, measure and keep the cheapest plan.
#include "taskmap/reaching/grasp_planner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>

#include "taskmap/core/error.hpp"
#include "taskmap/reaching/trajectory_bfgs.hpp"

namespace taskmap {

const char* toString(Descent descent) {
  return descent == Descent::kGradient ? "gradient" : "bfgs";
}

Descent descentFromString(const std::string& name) {
  if (name == "bfgs") return Descent::kBfgs;
  if (name == "gradient") return Descent::kGradient;
  throw Error("descent must be 'bfgs' or 'gradient', not '" + name + "'");
}

void GraspPlanOptions::validate() const {
  optimizer.validate();
  map_weights.validate();
  if (!(via_height >= 0.0) || !std::isfinite(via_height))
    throw Error("grasp plan options: via_height must be finite and >= 0 metres");
  if (screen_iterations < 0)
    throw Error("grasp plan options: screen_iterations must be >= 0 (0 = no screening)");
}

namespace {

Pose bodyPose(const Kinematics& kin, int body) {
  return Pose::fromIsometry(kin.pose(body));
}

/// IK for rankClusters: a reaching rollout to the world target from q0, success when reached.
IkFunction rolloutIk(const TrajectoryProblem& p) {
  return [&p](const Pose& target_world) {
    const ReachResult r =
        reach(*p.robot, p.collisions, p.body, -1, target_world.toIsometry(), p.q0, p.reach);
    IkSolution s;
    s.success = r.status == ReachStatus::kReached;
    s.q = r.q.back();
    s.message = r.message;
    return s;
  };
}

/// End-state comfort: H_jl (eq. 1.8) + H_coll (eq. 1.10) of the robot's own model.
ComfortFunction comfort(const TrajectoryProblem& p) {
  return [&p](const Eigen::VectorXd& q) {
    Kinematics kin(*p.robot);
    kin.update(q);
    return jointLimitCost(*p.robot, q, nullptr) +
           (p.collisions ? p.collisions->cost(kin, nullptr) : 0.0);
  };
}

/// First index from which every later value satisfies ok(value), -1 if the last does not.
template <class T, class F>
int firstFromWhichAlways(const std::vector<T>& v, F ok) {
  int first = -1;
  for (int i = static_cast<int>(v.size()) - 1; i >= 0 && ok(v[i]); --i) first = i;
  return first;
}

/// Clearance, limit margins and convergence measures of an optimised plan.
void measure(const TrajectoryProblem& p, const TaskMap& map, ClusterPlan& plan) {
  const std::vector<Eigen::VectorXd>& q = plan.optimization.cost.q;
  Kinematics kin(*p.robot);
  plan.min_clearance = std::numeric_limits<double>::infinity();
  plan.joint_limit_margin = std::numeric_limits<double>::infinity();
  const double dt = p.reach.attractor.dt;
  for (std::size_t t = 0; t < q.size(); ++t) {
    kin.update(q[t]);
    if (p.collisions && !p.collisions->pairs().empty())
      plan.min_clearance = std::min(plan.min_clearance, p.collisions->minimumDistance(kin));
    plan.joint_limit_margin = std::min(plan.joint_limit_margin, jointLimitMargin(*p.robot, q[t]));
    if (t > 0)
      plan.velocity_ratio = std::max(
          plan.velocity_ratio,
          ((q[t] - q[t - 1]).cwiseAbs() / dt).cwiseQuotient(p.robot->velocityLimits()).maxCoeff());
  }
  plan.collision_free = plan.min_clearance >= 0.0;
  plan.grasp_index = plan.nearest.back();
  const std::vector<int>& labels = map.data().clustering->labels;
  plan.grasp_cluster = labels.at(static_cast<std::size_t>(plan.grasp_index));
  const double sigma = *map.options().position_sigma;
  plan.iterations_to_manifold =
      firstFromWhichAlways(plan.nearest_distance, [sigma](double d) { return d <= sigma; });
  const double final_quality = plan.quality.back();
  plan.iterations_to_quality = firstFromWhichAlways(plan.quality, [final_quality](double g) {
    return std::abs(g - final_quality) <= 0.01 * std::abs(final_quality) + 1e-12;
  });
}

/// Optimises from one cluster's representative.
ClusterPlan planFrom(TrajectoryProblem p, const TaskMap& map, const ClusterRank& rank,
                     const GraspPlanOptions& o, const RunControl<PlanProgress>& control,
                     std::size_t plans_done) {
  ClusterPlan plan;
  plan.cluster = rank.cluster;
  plan.comfort = rank.comfort;
  auto record = std::make_shared<MapCostRecord>();
  p.frame = rank.target_object.toIsometry().linear();
  p.terminal = mapTerminalCost(
      map, p.body, p.reference, o.map_weights,
      o.restrict_to_cluster ? std::optional<int>(rank.cluster) : std::nullopt, record);
  const Eigen::Matrix<double, 6, 1> x0 = startTaskVariables(p);
  Eigen::Matrix<double, 6, 1> target = Eigen::Matrix<double, 6, 1>::Zero();
  target.head<3>() = rank.target_object.position;
  Eigen::Matrix<double, 6, 1> via = 0.5 * (x0 + target);
  Kinematics kin(*p.robot);
  kin.update(p.q0);
  via.head<3>() += kin.pose(p.reference).linear().transpose() * Eigen::Vector3d(0, 0, o.via_height);
  TrajectoryOptimizerOptions opt = o.optimizer;
  // The planner's bookkeeping, then the caller's callback and the run control's report.
  opt.on_iteration = [&plan, record, &control, plans_done, caller = o.optimizer.on_iteration](
                         int iteration, const TrajectoryCost& cost) {
    plan.proximity.push_back(record->proximity);
    plan.quality.push_back(record->quality);
    plan.nearest_distance.push_back(record->evaluation.proximity.nearest.distance);
    plan.nearest.push_back(static_cast<std::int64_t>(record->evaluation.proximity.nearest.index));
    if (caller) caller(iteration, cost);
    if (control.progress) control.progress({plan.cluster, iteration, cost.total, plans_done});
  };
  const auto start = std::chrono::steady_clock::now();
  plan.optimization = o.descent == Descent::kBfgs ? optimizeTrajectoryBfgs(p, {via, target}, opt)
                                                  : optimizeTrajectory(p, {via, target}, opt);
  plan.milliseconds =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  measure(p, map, plan);
  return plan;
}

bool safe(const ClusterPlan& c) {
  return c.collision_free && c.joint_limit_margin >= 0.0 && c.velocity_ratio <= 1.0 + 1e-9 &&
         c.iterations_to_manifold >= 0;
}

// A plan stopped by the run control: the clusters optimised so far, the cheapest one best.
GraspPlan interrupted(GraspPlan plan) {
  plan.status = GraspPlanStatus::kInterrupted;
  plan.best = -1;
  for (std::size_t i = 0; i < plan.plans.size(); ++i)
    if (plan.best < 0 ||
        plan.plans[i].optimization.cost.total <
            plan.plans[static_cast<std::size_t>(plan.best)].optimization.cost.total)
      plan.best = static_cast<int>(i);
  plan.message = "interrupted after " + std::to_string(plan.plans.size()) + " of the clusters";
  return plan;
}

}  // namespace

GraspPlan planGrasp(const TrajectoryProblem& problem, const TaskMap& map,
                    const GraspPlanOptions& options, const RunControl<PlanProgress>& control) {
  problem.validate();
  options.validate();
  if (map.numClusters() < 1)
    throw Error("plan grasp: the map has no clustering; run taskmap cluster");
  GraspPlan plan;
  Kinematics kin(*problem.robot);
  kin.update(problem.q0);
  const Pose object_world = bodyPose(kin, problem.reference);
  plan.ranking = rankClusters(map, object_world, rolloutIk(problem), comfort(problem));
  // Screening: short optimisations of every reachable cluster, the winner re-run in full.
  const int reachable = static_cast<int>(std::count_if(
      plan.ranking.begin(), plan.ranking.end(), [](const ClusterRank& r) { return r.reachable; }));
  const bool screen = options.all_clusters && reachable > 1 && options.screen_iterations > 0 &&
                      options.screen_iterations < options.optimizer.max_iterations;
  GraspPlanOptions first = options;
  if (screen) first.optimizer.max_iterations = options.screen_iterations;
  for (const ClusterRank& rank : plan.ranking) {
    if (!rank.reachable || control.stopRequested()) break;
    plan.plans.push_back(planFrom(problem, map, rank, first, control, plan.plans.size()));
    if (!options.all_clusters) break;
  }
  if (control.stopRequested()) return interrupted(std::move(plan));
  if (plan.plans.empty()) {
    plan.message = "no cluster's representative grasp is reachable";
    return plan;
  }
  const auto cheaper = [](const ClusterPlan& a, const ClusterPlan& b) {
    if (safe(a) != safe(b)) return safe(a);
    return a.optimization.cost.total < b.optimization.cost.total;
  };
  const auto cheapest = [&plan, &cheaper] {
    return static_cast<int>(std::min_element(plan.plans.begin(), plan.plans.end(), cheaper) -
                            plan.plans.begin());
  };
  plan.best = cheapest();
  if (screen) {  // plans[i] started from ranking[i] (the reachable clusters come first)
    plan.plans[plan.best] =
        planFrom(problem, map, plan.ranking[plan.best], options, control, plan.plans.size());
    plan.best = cheapest();
  }
  const ClusterPlan& b = plan.plans[plan.best];
  plan.status = safe(b) ? GraspPlanStatus::kPlanned : GraspPlanStatus::kUnsafe;
  plan.message = (safe(b) ? "planned: grasp " : "unsafe plan: grasp ") +
                 std::to_string(b.grasp_index) + " of cluster " + std::to_string(b.grasp_cluster) +
                 " after " + std::to_string(b.optimization.iterations) + " iterations";
  return plan;
}

}  // namespace taskmap
