#pragma once
/// @file plan_report.hpp
/// The report of a grasp plan as `taskmap reach --map --json` prints it and Python
/// `taskmap.reach` returns it (docs/REACHING.md, "taskmap reach"): one serialiser for both; the
/// text `taskmap reach` prints, and the reports of a reach to a fixed target.

#include <cstddef>
#include <string>

#include <Eigen/Core>

#include "taskmap/reaching/attractor.hpp"
#include "taskmap/reaching/grasp_planner.hpp"
#include "taskmap/reaching/movement_terms.hpp"

namespace taskmap {

/// Words for a negative clearance in every report (text and JSON): "NEGATIVE clearance: <pair
/// or 'bodies'> overlap by <mm> mm, the motion is not collision-free"; "" when clearance >= 0
/// (metres).
std::string clearanceWarning(double clearance, const std::string& pair = "");

/// "planned", "unsafe", "unreachable" or "interrupted".
const char* toString(GraspPlanStatus status);

/// The plan as a JSON object (text): status, message, ms_per_plan (plan_ms, milliseconds),
/// ranking, plans (per optimised cluster) and, with a best plan, its measures, cost_history,
/// proximity_over_movement, quality_over_movement (movement, per step) and q_final (rad).
/// Non-finite comfort values are null. A plan with a negative min_clearance carries "warning"
/// (clearanceWarning).
std::string graspPlanReport(const GraspPlan& plan, double plan_ms, const MovementTerms& movement);

/// The plan as `taskmap reach --map` prints it: status, one line per optimised cluster
/// (iterations, clearance, joint margin, ms per iteration, the clearance warning) and the plan
/// time (plan_ms, milliseconds); lines end in '\n'.
std::string graspPlanText(const GraspPlan& plan, double plan_ms);

/// "reached", "collided" or "not_reached".
const char* toString(ReachStatus status);

/// What the report of a reach to a fixed target says besides the ReachResult.
struct ReachReportContext {
  std::string robot;                   ///< the robot as named by the caller ("panda", a URDF)
  std::string hand;                    ///< the hand as named by the caller
  std::string frame = "world";         ///< frame of the target: "world" or "object"
  Eigen::Matrix<double, 7, 1> target;  ///< target palm pose [x y z qw qx qy qz] as given
  double dt = 0.0;                     ///< control step, s
  std::size_t collision_pairs = 0;     ///< body pairs the collision model watches
  double compute_seconds = 0.0;        ///< wall time of the reach, s
};

/// The reach as a JSON object (text, keys sorted): robot, hand, target {frame, pose}, status,
/// message, steps, dt_s, position_error_m, orientation_error_rad, collision_pairs,
/// min_clearance_m (null without pairs) and its pair and step, warning (negative clearance),
/// joint_limit_margin, q_start, q_final (rad or m), palm_final [x y z qw qx qy qz],
/// compute_time_s.
std::string reachReport(const ReachResult& result, const ReachReportContext& context);

/// The reach as `taskmap reach` prints it: status, steps, final error, clearance, joint-limit
/// margin; lines end in '\n'.
std::string reachText(const ReachResult& result, const ReachReportContext& context);

}  // namespace taskmap
