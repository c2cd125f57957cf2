#pragma once
// Sample weights of the quality criterion (task_map.hpp SampleWeight).
#include <cassert>
#include <vector>

#include "taskmap/integration/task_map.hpp"

namespace taskmap::detail {

/// kAuto resolved for `map`; throws Error when kHoldMargin is asked of a map without hold
/// labels for every grasp.
SampleWeight resolveSampleWeight(const TaskMapData& map, SampleWeight requested);

/// Hold margin of every grasp in [0, 1]. With robust labels for every grasp: 0 when it is not
/// robust, else min(1 - d_c / d_m, 1 - a_c / a_m), d_c and a_c its largest displacement and
/// rotation from the closed state over the variants, d_m and a_m the margin (1 cm, 5 degrees,
/// from robust_json). Without: 0 when it does not hold, else min(1 - d / d_max, 1 - a / a_max)
/// with the protocol's displacement from the start and limits. The map must be fully validated.
std::vector<double> holdMargins(const TaskMapData& map);

}  // namespace taskmap::detail
