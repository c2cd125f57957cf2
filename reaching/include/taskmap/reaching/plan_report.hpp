#pragma once
/// @file plan_report.hpp
/// The report of a grasp plan as `taskmap reach --map --json` prints it and Python
/// `taskmap.reach` returns it (docs/REACHING.md, "taskmap reach"): one serialiser for both.

#include <string>

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

}  // namespace taskmap
