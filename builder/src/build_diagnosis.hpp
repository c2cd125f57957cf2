#pragma once
// The diagnosis of a build that stored nothing (private to builder).
#include <cstdint>
#include <map>
#include <string>

#include "taskmap/hands/hand_model.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap::detail {

/// One line for a build that stored no grasp: the dominant trial outcome with its share, what
/// that outcome means, and what to check (units, approach axis, preshape, closing).
std::string noGraspMessage(const std::map<std::string, std::uint64_t>& outcomes,
                           std::uint64_t trials, const ObjectModel& object, const HandModel& hand);

}  // namespace taskmap::detail
