// The default sampler's pilot (builder/sampler_choice.hpp): on the real Allegro hand the
// reference box, where mixed trials rarely find a grasp, gets palm_enclose and the YCB banana
// keeps mixed; a default build's map is then the explicit sampler's; the choice does not depend
// on threads or the build seed; jaws, fingertip grasps and an explicit kind run no pilot.
#include "taskmap/builder/sampler_choice.hpp"

#include <atomic>
#include <string>

#include <gtest/gtest.h>

#include "build_fixtures.hpp"
#include "map_compare.hpp"
#include "sampler_build_fixture.hpp"
#include "taskmap/builder/trial_block.hpp"

namespace taskmap {
namespace {

const HandModel& allegro() {
  return testing::realHand("hands/allegro_right/allegro_hand_description_right.urdf");
}
const ObjectModel& banana() {
  return testing::realObject("objects/ycb_011_banana.obj");
}
const ObjectModel& referenceBox() {
  static const ObjectModel box = ObjectModel::load(std::string(TASKMAP_OBJECTS_DIR) + "/box.obj");
  return box;
}

/// A default build (sampler kind unset) of `valid` grasps.
BuildOptions defaultBuild(int threads, std::uint64_t seed = 3) {
  BuildOptions o = testing::samplerBuild(SamplerKind::kMixed, threads, 6, 16);
  o.sampler.kind.reset();
  o.seed = seed;
  return o;
}

TEST(SamplerChoiceTest, MixedTrialsThatRarelyFindAGraspGivePalmEnclose) {
  BuildTiming pilot;
  const SamplerChoice c = chooseSampler(referenceBox(), allegro(), defaultBuild(2), {}, &pilot);
  EXPECT_TRUE(c.piloted);
  EXPECT_EQ(c.kind, SamplerKind::kPalmEnclose);
  EXPECT_EQ(c.pilot_trials, kPilotTrials);
  EXPECT_LT(c.pilot_found, kPilotFound);
  EXPECT_FALSE(c.enclose_refused);
  EXPECT_GT(pilot.simulation_seconds, 0.0) << "the pilot's CPU is reported";
}

TEST(SamplerChoiceTest, MixedTrialsThatFindGraspsKeepMixedAndStopEarly) {
  const SamplerChoice c = chooseSampler(banana(), allegro(), defaultBuild(2));
  EXPECT_TRUE(c.piloted);
  EXPECT_EQ(c.kind, SamplerKind::kMixed);
  EXPECT_EQ(c.pilot_found, kPilotFound);
  EXPECT_LT(c.pilot_trials, kPilotTrials) << "the pilot ends at the grasp that decides";
}

TEST(SamplerChoiceTest, PalmEncloseThatCannotPlaceTheHandKeepsMixed) {
  // The barrett on the reference mug: mixed finds nothing in the pilot, and palm_enclose's probe
  // finds the mug wider than the hand nearly everywhere (its trials would be mixed's).
  const HandModel barrett =
      HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf");
  const ObjectModel mug = ObjectModel::load(std::string(TASKMAP_OBJECTS_DIR) + "/mug.obj");
  const SamplerChoice c = chooseSampler(mug, barrett, defaultBuild(2));
  EXPECT_TRUE(c.piloted);
  EXPECT_LT(c.pilot_found, kPilotFound);
  EXPECT_TRUE(c.enclose_refused);
  EXPECT_EQ(c.kind, SamplerKind::kMixed);
}

TEST(SamplerChoiceTest, SameChoiceForAnyThreadCountAndBuildSeed) {
  const SamplerChoice one = chooseSampler(referenceBox(), allegro(), defaultBuild(1, 1));
  for (const auto& [threads, seed] : {std::pair{2, 1}, std::pair{1, 9}, std::pair{2, 9}}) {
    const SamplerChoice c = chooseSampler(referenceBox(), allegro(), defaultBuild(threads, seed));
    EXPECT_EQ(c.kind, one.kind) << threads << " threads, seed " << seed;
    EXPECT_EQ(c.pilot_trials, one.pilot_trials);
    EXPECT_EQ(c.pilot_found, one.pilot_found);
  }
}

TEST(SamplerChoiceTest, DefaultBuildIsTheChosenSamplersBuild) {
  for (const ObjectModel* object : {&referenceBox(), &banana()}) {
    const BuildResult chosen = buildMap(*object, allegro(), defaultBuild(2));
    ASSERT_EQ(chosen.status, BuildStatus::kComplete) << chosen.message;
    EXPECT_TRUE(chosen.sampler_choice.piloted);
    BuildOptions explicit_kind = defaultBuild(2);
    explicit_kind.sampler.kind = chosen.sampler_choice.kind;
    const BuildResult given = buildMap(*object, allegro(), explicit_kind);
    EXPECT_FALSE(given.sampler_choice.piloted);
    EXPECT_EQ(chosen.map.sampling.sampler, toString(chosen.sampler_choice.kind));
    testing::expectSameMapContent(chosen.map, given.map);
    // The map's parameters name the sampler: rebuilding from them runs no pilot.
    EXPECT_EQ(chosen.map.sampling.params_json, given.map.sampling.params_json);
  }
}

TEST(SamplerChoiceTest, TrialRunnerRunsTheSameChoice) {
  const TrialRunner runner(referenceBox(), allegro(), defaultBuild(1));
  EXPECT_EQ(runner.samplerChoice().kind, SamplerKind::kPalmEnclose);
  EXPECT_EQ(runner.samplerChoice().pilot_trials, kPilotTrials);
  EXPECT_GT(runner.timing().simulation_seconds, 0.0) << "the pilot's CPU is in the timing";
}

TEST(SamplerChoiceTest, NoPilotForAGivenKindJawsASmallBudgetOrFingertipGrasps) {
  BuildOptions given = defaultBuild(1);
  given.sampler.kind = SamplerKind::kVolume;
  const SamplerChoice g = chooseSampler(referenceBox(), allegro(), given);
  EXPECT_FALSE(g.piloted);
  EXPECT_EQ(g.kind, SamplerKind::kVolume);

  const SamplerChoice jaws =
      chooseSampler(testing::boxObject(), testing::pandaHand(), defaultBuild(1));
  EXPECT_FALSE(jaws.piloted);
  EXPECT_EQ(jaws.kind, SamplerKind::kAntipodalPalm);

  BuildOptions small = defaultBuild(1);
  small.max_trials = kPilotTrials - 1;  // a budget below the pilot's
  const SamplerChoice b = chooseSampler(referenceBox(), allegro(), small);
  EXPECT_FALSE(b.piloted);
  EXPECT_EQ(b.kind, SamplerKind::kMixed);

  BuildOptions tips = defaultBuild(1);
  tips.simulation.grasp_mode = GraspMode::kFingertip;
  const SamplerChoice t = chooseSampler(referenceBox(), allegro(), tips);
  EXPECT_FALSE(t.piloted);
  EXPECT_EQ(t.kind, SamplerKind::kMixed);
}

TEST(SamplerChoiceTest, InterruptedPilotKeepsMixed) {
  const std::atomic<bool> stop{true};
  BuildControl control;
  control.stop = &stop;
  const SamplerChoice c = chooseSampler(referenceBox(), allegro(), defaultBuild(1), control);
  EXPECT_EQ(c.kind, SamplerKind::kMixed);
}

}  // namespace
}  // namespace taskmap
