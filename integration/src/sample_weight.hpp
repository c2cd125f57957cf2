#pragma once
// Sample weights of the quality criterion (task_map.hpp SampleWeight).
#include <cassert>
#include <vector>

#include "taskmap/integration/task_map.hpp"

namespace taskmap::detail {

/// kAuto resolved for `map`; throws Error when kHoldMargin is asked of a map without hold
/// labels for every grasp.
SampleWeight resolveSampleWeight(const TaskMapData& map, SampleWeight requested);

/// Hold margin of every grasp in [0, 1]: 0 when it does not hold, else
/// min(1 - d / d_max, 1 - a / a_max). The map must be fully validated.
std::vector<double> holdMargins(const TaskMapData& map);

}  // namespace taskmap::detail
