// The default sampler (builder/sampler_choice.hpp; docs/METHOD.md §2).
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
                            const BuildOptions& options) {
  SamplerChoice choice;
  if (options.sampler.kind) {
    choice.kind = *options.sampler.kind;
    return choice;
  }
  choice.kind = defaultSamplerKind(hand);
  if (choice.kind != SamplerKind::kMixed || !palmEnclosePossible(hand, options)) return choice;
  // palm_enclose's own probe (Sampler::attemptsInForce) may find that it cannot place the hand
  // on this object: its trials would be mixed's, so the build runs mixed.
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
