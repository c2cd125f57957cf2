// The JSON report of a grasp plan (CLI and Python share it).
#include "taskmap/reaching/plan_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace taskmap {
namespace {

nlohmann::json costHistory(const ClusterPlan& c) {
  nlohmann::json h = nlohmann::json::array();
  for (std::size_t i = 0; i < c.optimization.history.size(); ++i) {
    const TrajectoryCost& t = c.optimization.history[i];
    h.push_back({{"total", t.total},
                 {"path_length", t.path_length},
                 {"end_velocity", t.end_velocity},
                 {"collision", t.collision},
                 {"joint_limit", t.joint_limit},
                 {"proximity", c.proximity.at(i)},
                 {"quality", c.quality.at(i)},
                 {"nearest_distance_m", c.nearest_distance.at(i)}});
  }
  return h;
}

nlohmann::json clusterJson(const ClusterPlan& c) {
  const int it = c.optimization.iterations;
  nlohmann::json j = {{"start_cluster", c.cluster},
                      {"comfort", c.comfort},
                      {"cluster", c.grasp_cluster},
                      {"grasp_index", c.grasp_index},
                      {"iterations", it},
                      {"iterations_to_manifold", c.iterations_to_manifold},
                      {"iterations_to_quality", c.iterations_to_quality},
                      {"min_clearance_m", c.min_clearance},
                      {"joint_limit_margin_rad", c.joint_limit_margin},
                      {"velocity_ratio", c.velocity_ratio},
                      {"collision_free", c.collision_free},
                      {"ends_on_sample", c.ends_on_sample},
                      {"cost", c.optimization.cost.total},
                      {"ms", c.milliseconds},
                      {"ms_per_iteration", c.milliseconds / std::max(1, it)}};
  if (c.min_clearance < 0.0) j["warning"] = clearanceWarning(c.min_clearance);
  if (c.sample_out_of_reach)
    j["warning"] = "the palm cannot be put on grasp " + std::to_string(c.grasp_index) +
                   " within the joint limits";
  return j;
}

}  // namespace

std::string clearanceWarning(double clearance, const std::string& pair) {
  if (!(clearance < 0.0)) return "";
  char mm[32];
  std::snprintf(mm, sizeof mm, "%.1f", -1000.0 * clearance);
  return std::string("NEGATIVE clearance: ") + (pair.empty() ? "bodies" : pair) + " overlap by " +
         mm + " mm, the motion is not collision-free";
}

const char* toString(GraspPlanStatus s) {
  switch (s) {
    case GraspPlanStatus::kPlanned:
      return "planned";
    case GraspPlanStatus::kUnsafe:
      return "unsafe";
    case GraspPlanStatus::kUnreachable:
      return "unreachable";
    case GraspPlanStatus::kInterrupted:
      return "interrupted";
  }
  return "unreachable";
}

std::string graspPlanReport(const GraspPlan& plan, double plan_ms, const MovementTerms& movement) {
  nlohmann::json j;
  j["status"] = toString(plan.status);
  j["message"] = plan.message;
  j["ms_per_plan"] = plan_ms;
  // The map terms' weights; "quality" terms are quality_weight g_q / quality_peak.
  j["map_weights"] = {{"proximity", plan.map_weights.proximity},
                      {"quality", plan.map_weights.quality},
                      {"quality_peak", plan.map_weights.quality_peak.value_or(1.0)}};
  nlohmann::json clusters = nlohmann::json::array();
  for (const ClusterRank& r : plan.ranking) {
    nlohmann::json c = {
        {"cluster", r.cluster},
        {"target", r.target},
        {"tried", r.tried},
        {"reachable", r.reachable},
        {"comfort", std::isfinite(r.comfort) ? nlohmann::json(r.comfort) : nullptr}};
    if (!r.reachable) c["message"] = r.message;  // why the IK failed (the representative's)
    clusters.push_back(std::move(c));
  }
  j["ranking"] = clusters;
  nlohmann::json plans = nlohmann::json::array();
  for (const ClusterPlan& c : plan.plans) plans.push_back(clusterJson(c));
  j["plans"] = plans;
  if (plan.best >= 0) {
    const ClusterPlan& b = plan.plans[static_cast<std::size_t>(plan.best)];
    j.update(clusterJson(b));
    j["cost_history"] = costHistory(b);
    j["proximity_over_movement"] = movement.proximity;
    j["quality_over_movement"] = movement.quality;
    const auto& q = b.optimization.cost.q;
    j["q_final"] = std::vector<double>(q.back().data(), q.back().data() + q.back().size());
  }
  return j.dump();
}

}  // namespace taskmap
