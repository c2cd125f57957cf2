#pragma once
// Private to hands: the sidecar keys of the grasping behaviour ("coupled", "grasp").

#include <string>

#include <nlohmann/json.hpp>

#include "taskmap/hands/hand_model.hpp"

namespace taskmap {

/// Reads "coupled" and "grasp" of a parsed sidecar into `h` (its closing motion must be read
/// already). `where` prefixes every error ("hand sidecar '<path>': ").
struct HandGraspingKeys {
  static void read(const nlohmann::json& sidecar, const std::string& where, HandModel* h);
};

}  // namespace taskmap
