#pragma once
/// @file sampler_choice.hpp
/// The sampler a build runs when its options leave the kind unset (docs/METHOD.md §2, "The
/// default sampler: a pilot of mixed trials").

#include <cstdint>

#include "taskmap/builder/map_builder.hpp"

namespace taskmap {

/// Mixed trials the pilot simulates at most.
constexpr std::uint64_t kPilotTrials = 256;
/// Force-closure grasps the pilot's mixed trials must find for the build to run mixed (one in
/// 64 trials or better); the pilot stops at the trial that finds the last of them.
constexpr std::uint64_t kPilotFound = 4;
/// The pilot's run seed: the same pilot, and so the same sampler, for every build seed.
constexpr std::uint64_t kPilotSeed = 0x70696c6f74ULL;  // "pilot"

/// The sampler of a build: options.sampler.kind when set; else the hand's default
/// (defaultSamplerKind: antipodal_palm for parallel jaws, mixed otherwise), except for a hand
/// that palm_enclose can place (fingers closing across the approach axis, finger collision
/// shapes, palm grasps that require the palm's contact), in a build whose trial budget
/// (max_trials) is at least kPilotTrials: a pilot build of mixed trials (seed
/// kPilotSeed, at most kPilotTrials trials, the build's simulation, quality and checks) keeps
/// mixed when it finds kPilotFound force-closure grasps, else the build runs palm_enclose
/// unless palm_enclose's probe finds that it cannot place the hand on this object.
/// Deterministic: the same answer for any thread count and build seed. The pilot's stage CPU
/// seconds (sampling, simulation, quality) are added to *timing when given. Throws what
/// buildMap throws on invalid options; an interrupted pilot (control.stop) keeps mixed.
SamplerChoice chooseSampler(const ObjectModel& object, const HandModel& hand,
                            const BuildOptions& options, const BuildControl& control = {},
                            BuildTiming* timing = nullptr);

}  // namespace taskmap
