#pragma once
// Checks before a build and the diagnosis of a build that stored nothing (private to builder).
#include <cstdint>
#include <map>
#include <string>

#include "taskmap/meshes/hand_model.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap::detail {

/// Throws Error when the object's size against the hand's suggests wrong units: larger than
/// 100 times the open hand's reach (a millimetre file read as metres) or smaller than a
/// hundredth of it (a metre file scaled down).
void checkObjectSize(const ObjectModel& object, const HandModel& hand);

/// One line for a build that stored no grasp: the dominant trial outcome with its share, what
/// that outcome means, and what to check (units, approach axis, preshape, closing).
std::string noGraspMessage(const std::map<std::string, std::uint64_t>& outcomes,
                           std::uint64_t trials, const ObjectModel& object, const HandModel& hand);

}  // namespace taskmap::detail
