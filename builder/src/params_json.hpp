#pragma once
// The build parameters a map stores (/sampling params_json), private to builder.

#include <string>

#include "taskmap/builder/map_builder.hpp"

namespace taskmap::detail {

/// Every build option that can change the map, as a JSON object (extra_params_json merged in).
std::string paramsJson(const BuildOptions& o, const HandModel& hand);

}  // namespace taskmap::detail
