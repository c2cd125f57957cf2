// The default sampler's pilot (builder/sampler_choice.hpp; docs/METHOD.md §2).
#include "taskmap/builder/sampler_choice.hpp"

#include "taskmap/sampler/palm_enclose.hpp"
#include "trial_pool.hpp"

namespace taskmap {
namespace {

// Whether palm_enclose can place this hand in this build: enclosing geometry, finger points to
// check, palm grasps with the palm's contact required (the sampler puts the palm's front on
// the surface).
bool palmEnclosePossible(const HandModel& hand, const BuildOptions& options) {
  const GraspMode mode = options.simulation.grasp_mode.value_or(hand.graspMode());
  if (mode != GraspMode::kPalm || !options.simulation.require_palm_contact) return false;
  if (!encloseGeometry(hand)) return false;
  return !fingerCheckPoints(hand, detail::kFingerCheckSpacing).empty();
}

}  // namespace

SamplerChoice chooseSampler(const ObjectModel& object, const HandModel& hand,
                            const BuildOptions& options, const BuildControl& control,
                            BuildTiming* timing) {
  SamplerChoice choice;
  if (options.sampler.kind) {
    choice.kind = *options.sampler.kind;
    return choice;
  }
  choice.kind = defaultSamplerKind(hand);
  // A trial budget below the pilot's: the pilot would spend more than the build may.
  if (choice.kind != SamplerKind::kMixed || options.max_trials < kPilotTrials ||
      !palmEnclosePossible(hand, options))
    return choice;
  BuildOptions pilot = options;
  pilot.sampler.kind = SamplerKind::kMixed;
  pilot.seed = kPilotSeed;
  pilot.valid_target = kPilotFound;
  pilot.max_trials = kPilotTrials;
  pilot.stored = StoredGrasps::kForceClosure;
  pilot.cluster = false;
  pilot.check_size = false;
  BuildControl quiet;
  quiet.stop = control.stop;
  const BuildResult r = buildMap(object, hand, pilot, quiet);
  choice.piloted = true;
  choice.pilot_trials = r.map.sampling.trials;
  choice.pilot_found = r.map.grasps.size();
  if (timing != nullptr) {
    timing->sampling_seconds += r.timing.sampling_seconds;
    timing->simulation_seconds += r.timing.simulation_seconds;
    timing->quality_seconds += r.timing.quality_seconds;
    timing->closing_check_seconds += r.timing.closing_check_seconds;
  }
  if (choice.pilot_found >= kPilotFound || r.status == BuildStatus::kInterrupted) return choice;
  // palm_enclose's own probe (Sampler::attemptsInForce) may find that it cannot place the hand
  // on this object: its trials would be mixed's, so the build stays mixed.
  BuildOptions enclose = options;
  enclose.sampler.kind = SamplerKind::kPalmEnclose;
  const Sampler probed(object, detail::samplerOptionsFor(enclose, hand));
  if (probed.attemptsInForce() > 0)
    choice.kind = SamplerKind::kPalmEnclose;
  else
    choice.enclose_refused = true;
  return choice;
}

}  // namespace taskmap
