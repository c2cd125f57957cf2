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
  if (end_steps < 1) throw Error("grasp plan options: end_steps must be >= 1");
  ranking.validate();
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

/// Joint configuration near *q whose palm pose relative to the object is `target` (palm in the
/// object frame): damped least-squares Newton steps on the relative pose (eq. 1.4-1.5), a joint
/// that leaves its range clamped and frozen. False when it does not reach 1e-7 m and 1e-6 rad
/// in 100 steps.
bool solveRelativePose(const TrajectoryProblem& p, const Eigen::Isometry3d& target,
                       Eigen::VectorXd* q) {
  Kinematics kin(*p.robot);
  const Eigen::VectorXd &lo = p.robot->lower(), &up = p.robot->upper();
  std::vector<bool> held(static_cast<std::size_t>(q->size()), false);
  for (int it = 0; it < 100; ++it) {
    kin.update(*q);
    Eigen::Matrix<double, 6, 1> e;
    e.head<3>() = target.translation() - kin.relativePosition(p.body, p.reference);
    e.tail<3>() =
        rotationLog(target.linear() * kin.relativeRotation(p.body, p.reference).transpose());
    if (e.head<3>().norm() < 1e-7 && e.tail<3>().norm() < 1e-6) return true;
    Eigen::Matrix<double, 6, Eigen::Dynamic> j(6, q->size());
    j.topRows<3>() = kin.relativePositionJacobian(p.body, p.reference);
    j.bottomRows<3>() = kin.relativeAngularJacobian(p.body, p.reference);
    for (Eigen::Index k = 0; k < q->size(); ++k)
      if (held[static_cast<std::size_t>(k)]) j.col(k).setZero();
    const Eigen::Matrix<double, 6, 6> a =
        j * j.transpose() + 1e-8 * Eigen::Matrix<double, 6, 6>::Identity();
    *q += j.transpose() * a.ldlt().solve(e);
    for (Eigen::Index k = 0; k < q->size(); ++k) {
      if ((*q)[k] < lo[k] || (*q)[k] > up[k]) held[static_cast<std::size_t>(k)] = true;
      (*q)[k] = std::clamp((*q)[k], lo[k], up[k]);
    }
  }
  return false;
}

/// Bends the last `steps` steps of the plan's trajectory onto its final nearest sample: q_t +=
/// s(t) dq (smoothstep s from 0 to 1, clamped to the limits), dq taking the last step's palm to
/// the sample's pose. False (the trajectory unchanged) when the IK does not get there.
bool endOnSample(const TrajectoryProblem& p, const TaskMap& map, int steps, ClusterPlan& plan) {
  std::vector<Eigen::VectorXd>& q = plan.optimization.cost.q;
  Eigen::VectorXd end = q.back();
  const Eigen::Isometry3d target =
      map.data().grasps.poseAt(static_cast<std::size_t>(plan.nearest.back())).toIsometry();
  if (!solveRelativePose(p, target, &end)) return false;
  const Eigen::VectorXd dq = end - q.back();
  const int n = std::min(steps, static_cast<int>(q.size()) - 1);
  for (int k = 1; k <= n; ++k) {
    const double s = static_cast<double>(k) / n, w = s * s * (3.0 - 2.0 * s);
    Eigen::VectorXd& qt = q[q.size() - 1 - static_cast<std::size_t>(n - k)];
    qt = (qt + w * dq).cwiseMax(p.robot->lower()).cwiseMin(p.robot->upper());
  }
  return true;
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
  if (o.end_on_sample) {
    plan.ends_on_sample = endOnSample(p, map, o.end_steps, plan);
    plan.sample_out_of_reach = !plan.ends_on_sample;
  }
  measure(p, map, plan);  // of the trajectory as returned (bent onto the sample or not)
  return plan;
}

bool safe(const ClusterPlan& c) {
  return c.collision_free && c.joint_limit_margin >= 0.0 && c.velocity_ratio <= 1.0 + 1e-9 &&
         c.iterations_to_manifold >= 0 && !c.sample_out_of_reach;
}

/// a before b: a safe plan first, then the lower total cost.
bool cheaperPlan(const ClusterPlan& a, const ClusterPlan& b) {
  if (safe(a) != safe(b)) return safe(a);
  return a.optimization.cost.total < b.optimization.cost.total;
}

/// The second round when every plan is unsafe (docs/REACHING.md "When every plan is unsafe"):
/// each cluster's other members and the outliers as targets (rankClusters, members_only), a
/// full optimisation from every reachable one that no full plan started from already (when the
/// first round's ranking fell back on members, the same members come first again: the same
/// plan; full[i]: plans[i] ran every iteration, not only the screening's), the cheapest plan
/// (safe first) the best. The new ranks go into plan.ranking after the planned ones, so that
/// plans[i] still started from ranking[i].
void planFromMembers(const TrajectoryProblem& problem, const TaskMap& map, const Pose& object_world,
                     const GraspPlanOptions& options, const RunControl<PlanProgress>& control,
                     const std::vector<bool>& full, GraspPlan& plan) {
  RankOptions members = options.ranking;
  members.members_only = true;
  const std::vector<ClusterRank> more =
      rankClusters(map, object_world, rolloutIk(problem), comfort(problem), members);
  for (const ClusterRank& rank : more) {
    if (!rank.reachable || control.stopRequested()) break;
    const auto at = static_cast<std::ptrdiff_t>(plan.plans.size());
    bool planned = false;
    for (std::size_t i = 0; i < full.size(); ++i)
      planned = planned || (full[i] && plan.ranking[i].target == rank.target);
    if (planned) continue;
    plan.ranking.insert(plan.ranking.begin() + at, rank);
    plan.plans.push_back(planFrom(problem, map, rank, options, control, plan.plans.size()));
    if (cheaperPlan(plan.plans.back(), plan.plans[static_cast<std::size_t>(plan.best)]))
      plan.best = static_cast<int>(at);
  }
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
                    const GraspPlanOptions& given, const RunControl<PlanProgress>& control) {
  problem.validate();
  given.validate();
  if (map.numClusters() < 1)
    throw Error("plan grasp: the map has no clustering; run taskmap cluster");
  GraspPlan plan;
  // The quality term's scale q*, once per plan (docs/REACHING.md "The quality term's scale").
  GraspPlanOptions options = given;
  if (!options.map_weights.quality_peak) options.map_weights.quality_peak = mapQualityPeak(map);
  plan.map_weights = options.map_weights;
  Kinematics kin(*problem.robot);
  kin.update(problem.q0);
  const Pose object_world = bodyPose(kin, problem.reference);
  plan.ranking =
      rankClusters(map, object_world, rolloutIk(problem), comfort(problem), options.ranking);
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
  const auto cheapest = [&plan] {
    return static_cast<int>(std::min_element(plan.plans.begin(), plan.plans.end(), cheaperPlan) -
                            plan.plans.begin());
  };
  plan.best = cheapest();
  // Screening: the cheapest is re-run in full; when the full run loses its place (it became
  // unsafe, e.g. its sample out of reach), the new cheapest is re-run too, until the cheapest
  // plan is a full one. plans[i] started from ranking[i] (the reachable clusters come first).
  std::vector<bool> full(plan.plans.size(), !screen);
  while (!full[static_cast<std::size_t>(plan.best)] && !control.stopRequested()) {
    plan.plans[plan.best] =
        planFrom(problem, map, plan.ranking[plan.best], options, control, plan.plans.size());
    full[static_cast<std::size_t>(plan.best)] = true;
    plan.best = cheapest();
  }
  if (!safe(plan.plans[plan.best]) && options.ranking.member_tries > 0)
    planFromMembers(problem, map, object_world, options, control, full, plan);
  if (control.stopRequested()) return interrupted(std::move(plan));
  const ClusterPlan& b = plan.plans[plan.best];
  plan.status = safe(b) ? GraspPlanStatus::kPlanned : GraspPlanStatus::kUnsafe;
  plan.message =
      (safe(b) ? "planned: grasp " : "unsafe plan: grasp ") + std::to_string(b.grasp_index) +
      " of cluster " + std::to_string(b.grasp_cluster) + " after " +
      std::to_string(b.optimization.iterations) + " iterations" +
      (b.sample_out_of_reach ? " (the palm cannot be put on the grasp within the joint limits)"
                             : "");
  return plan;
}

}  // namespace taskmap
