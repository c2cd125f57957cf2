// The default sampler (builder/sampler_choice.hpp): a multi-finger hand that palm_enclose can
// place runs palm_enclose (the real Allegro on the reference box and the YCB banana); where its
// probe cannot place the hand the build runs mixed; a default build's map is the explicit
// sampler's; jaws, fingertip grasps and an explicit kind keep theirs.
#include "taskmap/builder/sampler_choice.hpp"

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

TEST(SamplerChoiceTest, AHandThatEnclosesRunsPalmEnclose) {
  for (const ObjectModel* object : {&referenceBox(), &banana()}) {
    const SamplerChoice c = chooseSampler(*object, allegro(), defaultBuild(2));
    EXPECT_EQ(c.kind, SamplerKind::kPalmEnclose);
    EXPECT_FALSE(c.enclose_refused);
  }
}

TEST(SamplerChoiceTest, PalmEncloseThatCannotPlaceTheHandGivesMixed) {
  // The barrett on the reference mug: palm_enclose's probe finds the mug wider than the hand
  // nearly everywhere (its trials would be mixed's).
  const HandModel barrett =
      HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf");
  const ObjectModel mug = ObjectModel::load(std::string(TASKMAP_OBJECTS_DIR) + "/mug.obj");
  const SamplerChoice c = chooseSampler(mug, barrett, defaultBuild(2));
  EXPECT_TRUE(c.enclose_refused);
  EXPECT_EQ(c.kind, SamplerKind::kMixed);
}

TEST(SamplerChoiceTest, DefaultBuildIsTheChosenSamplersBuild) {
  for (const ObjectModel* object : {&referenceBox(), &banana()}) {
    const BuildResult chosen = buildMap(*object, allegro(), defaultBuild(2));
    ASSERT_EQ(chosen.status, BuildStatus::kComplete) << chosen.message;
    EXPECT_EQ(chosen.sampler_choice.kind, SamplerKind::kPalmEnclose);
    BuildOptions explicit_kind = defaultBuild(2);
    explicit_kind.sampler.kind = chosen.sampler_choice.kind;
    const BuildResult given = buildMap(*object, allegro(), explicit_kind);
    EXPECT_EQ(chosen.map.sampling.sampler, toString(chosen.sampler_choice.kind));
    testing::expectSameMapContent(chosen.map, given.map);
    // The map's parameters name the sampler: rebuilding from them makes no choice.
    EXPECT_EQ(chosen.map.sampling.params_json, given.map.sampling.params_json);
  }
}

TEST(SamplerChoiceTest, TrialRunnerRunsTheSameChoice) {
  const TrialRunner runner(referenceBox(), allegro(), defaultBuild(1));
  EXPECT_EQ(runner.samplerChoice().kind, SamplerKind::kPalmEnclose);
}

TEST(SamplerChoiceTest, AGivenKindJawsAndFingertipGraspsKeepTheirs) {
  BuildOptions given = defaultBuild(1);
  given.sampler.kind = SamplerKind::kVolume;
  EXPECT_EQ(chooseSampler(referenceBox(), allegro(), given).kind, SamplerKind::kVolume);

  const SamplerChoice jaws =
      chooseSampler(testing::boxObject(), testing::pandaHand(), defaultBuild(1));
  EXPECT_EQ(jaws.kind, SamplerKind::kAntipodalPalm);
  EXPECT_FALSE(jaws.enclose_refused);

  BuildOptions tips = defaultBuild(1);
  tips.simulation.grasp_mode = GraspMode::kFingertip;
  const SamplerChoice t = chooseSampler(referenceBox(), allegro(), tips);
  EXPECT_EQ(t.kind, SamplerKind::kMixed);
  EXPECT_FALSE(t.enclose_refused);
}

}  // namespace
}  // namespace taskmap
