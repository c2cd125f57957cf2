#pragma once
/// @file sampler_choice.hpp
/// The sampler a build runs when its options leave the kind unset (docs/METHOD.md §2, "The
/// default sampler").

#include "taskmap/builder/map_builder.hpp"

namespace taskmap {

/// The sampler of a build: options.sampler.kind when set; else the hand's default
/// (defaultSamplerKind: antipodal_palm for parallel jaws, mixed otherwise), except for a hand
/// that palm_enclose can place (fingers closing across the approach axis, finger collision
/// shapes, palm grasps that require the palm's contact): it runs palm_enclose unless
/// palm_enclose's probe finds that it cannot place the hand on this object (then mixed, with
/// SamplerChoice::enclose_refused). Measured: of 1300 validated grasps of 13 multi-finger
/// hand x object pairs 658 hold with palm_enclose against 401 with mixed (docs/VALIDATION.md,
/// "The default sampler for multi-finger hands"). Deterministic: it reads only the hand, the
/// object and the options' simulation settings (no trials). Throws what the sampler's
/// construction throws on invalid options.
SamplerChoice chooseSampler(const ObjectModel& object, const HandModel& hand,
                            const BuildOptions& options);

}  // namespace taskmap
