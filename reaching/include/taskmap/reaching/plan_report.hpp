#pragma once
/// @file plan_report.hpp
/// The report of a grasp plan as `taskmap reach --map --json` prints it and Python
/// `taskmap.reach` returns it (docs/REACHING.md, "taskmap reach"): one serialiser for both.

#include <string>

#include "taskmap/reaching/grasp_planner.hpp"
#include "taskmap/reaching/movement_terms.hpp"

namespace taskmap {

/// "planned", "unsafe" or "unreachable".
const char* toString(GraspPlanStatus status);

/// The plan as a JSON object (text): status, message, ms_per_plan (plan_ms, milliseconds),
/// ranking, plans (per optimised cluster) and, with a best plan, its measures, cost_history,
/// proximity_over_movement, quality_over_movement (movement, per step) and q_final (rad).
/// Non-finite comfort values are null.
std::string graspPlanReport(const GraspPlan& plan, double plan_ms, const MovementTerms& movement);

}  // namespace taskmap
