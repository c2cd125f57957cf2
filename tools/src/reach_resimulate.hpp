#pragma once
// `taskmap reach --map`: the re-simulated final grasp (taskmap/builder/resimulate.hpp) as JSON.

#include <nlohmann/json.hpp>

#include "taskmap/builder/resimulate.hpp"

namespace taskmap::cli {

/// {outcome, message, force_closure, epsilon, contacts, fingers, retraction_m, start, final,
/// hand, and hold {holds, status, max_translation_m, max_rotation_rad, failed_direction} when
/// the hold test ran}.
nlohmann::json resimulationJson(const Resimulation& r);

}  // namespace taskmap::cli
