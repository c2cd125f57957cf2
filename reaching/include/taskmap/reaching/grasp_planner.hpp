#pragma once
/// @file grasp_planner.hpp
/// Reaching and grasping with a task map (paper section 1.6.2-1.6.3, docs/REACHING.md): the
/// clusters are ranked by end-state comfort (IK to each representative, rankClusters), the
/// trajectory over attractor points is optimised with the map as terminal cost from the best
/// (or every reachable) cluster, and the cheapest plan is kept. Units: metres, radians, s.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "taskmap/core/run_control.hpp"
#include "taskmap/integration/initialisation.hpp"
#include "taskmap/reaching/map_cost.hpp"

namespace taskmap {

/// The descent planGrasp runs (docs/REACHING.md "Descent").
enum class Descent {
  kBfgs,      ///< quasi-Newton, optimizeTrajectoryBfgs (the default)
  kGradient,  ///< normalised steepest descent, optimizeTrajectory
};

/// "bfgs" or "gradient".
const char* toString(Descent descent);

/// Descent of its name ("bfgs", "gradient"); throws Error naming both for anything else.
Descent descentFromString(const std::string& name);

/// Options of planGrasp.
struct GraspPlanOptions {
  /// descent; a caller's on_iteration is called after the planner's own bookkeeping of each
  /// iteration (chained, not replaced)
  TrajectoryOptimizerOptions optimizer;
  /// w_map,p and w_map,q (docs/REACHING.md "Chosen weights", "The quality term's scale"); the
  /// quality term can hold the optimiser's last step millimetres off a sample, which
  /// end_on_sample corrects. An unset quality_peak is the map's (mapQualityPeak).
  MapCostWeights map_weights{1.0e4, 3.0e4, std::nullopt};
  bool all_clusters = false;         ///< optimise from every reachable cluster, keep the cheapest
  bool restrict_to_cluster = false;  ///< evaluate the map on the start cluster only
  double via_height = 0.05;          ///< a via point this high (metres) above the straight line
  Descent descent = Descent::kBfgs;  ///< BFGS or the normalised gradient descent
  /// With all_clusters: optimise every reachable cluster for only this many iterations, then
  /// re-run the cheapest (safe first) with the full optimizer.max_iterations (docs/REACHING.md
  /// "Screening"). 0 = off (every cluster optimised fully); >= 0. Default 5.
  int screen_iterations = 5;
  /// Which grasp of each cluster the plan starts from (rankClusters): the representatives, or,
  /// when none is reachable, one of at most ranking.member_tries other members of each cluster,
  /// then of as many outliers; when every plan from the first ranking is unsafe, a second
  /// round plans from other members and outliers (members_only; docs/REACHING.md "When every
  /// plan is unsafe"). Default 16; 0 = the representatives only, no second round.
  RankOptions ranking{16};
  /// End each plan on its final nearest sample (docs/REACHING.md "Ending on the sample"): the
  /// last end_steps steps of the optimised trajectory are bent (smoothstep) onto the joint
  /// configuration whose palm pose relative to the object is the sample's (damped
  /// least-squares IK within the joint limits, to 1e-7 m and 1e-6 rad). A plan that cannot end
  /// there is not safe (ClusterPlan::ends_on_sample). The optimised attractor points, costs
  /// and convergence measures are the optimiser's; clearance, limits and velocities are
  /// measured on the bent trajectory. false keeps the optimiser's last step.
  bool end_on_sample = true;
  int end_steps = 50;  ///< steps bent onto the sample (>= 1; fewer when the trajectory is shorter)
  /// Throws Error naming the field when a value is out of range.
  void validate() const;
};

/// The plan started from one cluster.
struct ClusterPlan {
  int cluster = -1;                      ///< start cluster
  double comfort = 0.0;                  ///< its end-state comfort (rankClusters)
  TrajectoryOptimization optimization;   ///< the optimised trajectory
  std::vector<double> proximity;         ///< weighted g_p per iteration, 0 first
  std::vector<double> quality;           ///< weighted g_q per iteration, 0 first
  std::vector<double> nearest_distance;  ///< pose distance to the nearest sample per iteration
  std::vector<std::int64_t> nearest;     ///< nearest grasp index per iteration
  int grasp_cluster = -1;                ///< cluster of the final nearest grasp
  std::int64_t grasp_index = -1;         ///< final nearest grasp
  int iterations_to_manifold = -1;       ///< first iteration from which nearest_distance <= sigma_p
  int iterations_to_quality = -1;   ///< first iteration from which g_q stays within 1% of final
  double min_clearance = 0.0;       ///< smallest signed pair distance over the trajectory, m
  double joint_limit_margin = 0.0;  ///< smallest distance to a position limit, rad
  double velocity_ratio = 0.0;      ///< max |dq/dt| / velocity limit over the trajectory
  bool collision_free = false;      ///< min_clearance >= 0 (hand-object pairs excluded)
  /// The trajectory ends on grasp_index's pose (GraspPlanOptions::end_on_sample).
  bool ends_on_sample = false;
  /// end_on_sample was asked and the IK could not put the palm on the sample within the joint
  /// limits: the plan is not safe.
  bool sample_out_of_reach = false;
  double milliseconds = 0.0;  ///< wall time of the optimisation
};

/// Outcome of planGrasp.
enum class GraspPlanStatus {
  kPlanned,      ///< a plan ends on the manifold, collision-free and within the limits
  kUnsafe,       ///< the best plan collides, leaves a limit or misses the manifold
  kUnreachable,  ///< no cluster's representative was reachable by IK
  /// the run control's stop flag was raised: plans holds the clusters optimised before it
  /// (best the cheapest of them, -1 if none)
  kInterrupted,
};

/// A report after every descent iteration of planGrasp (RunControl::progress).
struct PlanProgress {
  int cluster = -1;            ///< the cluster being optimised
  int iteration = 0;           ///< its descent iteration (0: the start)
  double cost = 0.0;           ///< total trajectory cost after it
  std::size_t plans_done = 0;  ///< clusters optimised before this one
};

/// Result of planGrasp.
struct GraspPlan {
  GraspPlanStatus status = GraspPlanStatus::kUnreachable;  ///< outcome
  std::string message;                                     ///< one line for people
  std::vector<ClusterRank> ranking;                        ///< every cluster, best comfort first
  std::vector<ClusterPlan> plans;                          ///< optimised clusters in ranking order
  int best = -1;  ///< index into plans of the cheapest, -1 if none
  /// The map weights of the plans, quality_peak set (options' or mapQualityPeak of the map).
  MapCostWeights map_weights;
};

/// Plans a reach-and-grasp of the object body `problem.reference` (a fixed body of the robot
/// model) with the palm `problem.body`: problem carries robot, collisions (the hand may touch
/// the object), q0, dynamics and trajectory weights; its frame and terminal are set here.
/// The map's hand poses are palm poses in the object frame. Throws Error on invalid input or a
/// map without clustering. control.progress gets a PlanProgress after every descent iteration
/// (control.interval_seconds is not used); control.stop is checked between clusters (then
/// status kInterrupted); an exception from the callback leaves planGrasp.
GraspPlan planGrasp(const TrajectoryProblem& problem, const TaskMap& map,
                    const GraspPlanOptions& options, const RunControl<PlanProgress>& control = {});

}  // namespace taskmap
