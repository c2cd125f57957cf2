// Text and JSON reports of a reach and of a grasp plan as `taskmap reach` prints them
// (reaching/plan_report.hpp).
#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "taskmap/core/pose.hpp"
#include "taskmap/core/text.hpp"
#include "taskmap/reaching/plan_report.hpp"

namespace taskmap {
namespace {

std::vector<double> values(const Eigen::VectorXd& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

}  // namespace

std::string graspPlanText(const GraspPlan& plan, double plan_ms) {
  std::ostringstream os;
  os << formatted("status            %s (%s)\n", toString(plan.status), plan.message.c_str());
  for (const ClusterPlan& c : plan.plans)
    os << formatted(
        "from cluster %-4d -> cluster %d grasp %lld: %d iterations (manifold %d, quality "
        "%d), clearance %.4f m, joint margin %.4f rad, %.1f ms/iteration%s\n",
        c.cluster, c.grasp_cluster, static_cast<long long>(c.grasp_index),
        c.optimization.iterations, c.iterations_to_manifold, c.iterations_to_quality,
        c.min_clearance, c.joint_limit_margin,
        c.milliseconds / std::max(1, c.optimization.iterations),
        c.min_clearance < 0.0 ? ("  <- " + clearanceWarning(c.min_clearance)).c_str() : "");
  os << formatted("plan time         %.1f ms\n", plan_ms);
  return os.str();
}

const char* toString(ReachStatus s) {
  return s == ReachStatus::kReached    ? "reached"
         : s == ReachStatus::kCollided ? "collided"
                                       : "not_reached";
}

std::string reachReport(const ReachResult& r, const ReachReportContext& c) {
  nlohmann::json j;
  j["robot"] = c.robot;
  j["hand"] = c.hand;
  j["target"] = {{"frame", c.frame}, {"pose", values(c.target)}};
  j["status"] = toString(r.status);
  j["message"] = r.message;
  j["steps"] = r.q.size() - 1;
  j["dt_s"] = c.dt;
  j["position_error_m"] = r.position_error;
  j["orientation_error_rad"] = r.orientation_error;
  j["collision_pairs"] = c.collision_pairs;
  if (std::isfinite(r.min_clearance)) {
    j["min_clearance_m"] = r.min_clearance;
    j["min_clearance_pair"] = r.min_clearance_pair;
    j["min_clearance_step"] = r.min_clearance_step;
    if (r.min_clearance < 0.0)
      j["warning"] = clearanceWarning(r.min_clearance, r.min_clearance_pair);
  } else {
    j["min_clearance_m"] = nullptr;
  }
  j["joint_limit_margin"] = r.joint_limit_margin;
  j["q_start"] = values(r.q.front());
  j["q_final"] = values(r.q.back());
  j["palm_final"] = values(Pose::fromIsometry(r.palm.back()).toVector7());
  j["compute_time_s"] = c.compute_seconds;
  return j.dump(2);
}

std::string reachText(const ReachResult& r, const ReachReportContext& c) {
  std::ostringstream os;
  os << formatted("status            %s (%s)\n", toString(r.status), r.message.c_str());
  os << formatted("steps             %zu\n", r.q.size() - 1);
  os << formatted("final error       %.3g m, %.3g rad (target in the %s frame)\n", r.position_error,
                  r.orientation_error, c.frame.c_str());
  if (std::isfinite(r.min_clearance))
    os << formatted(
        "min clearance     %.4f m (%s, step %d; %zu pairs)%s\n", r.min_clearance,
        r.min_clearance_pair.c_str(), r.min_clearance_step, c.collision_pairs,
        r.min_clearance < 0.0
            ? ("  <- " + clearanceWarning(r.min_clearance, r.min_clearance_pair)).c_str()
            : "");
  os << formatted("joint-limit margin %.4f (rad or m)\n", r.joint_limit_margin);
  return os.str();
}

}  // namespace taskmap
